"""Feature schema `lpnn.features.v1` (Documentation~/features.md): 19 values per evaluation point.

Deterministic, cell-relative and exposure-invariant: fixed direction sets (D14 for lighting, D26 for
rays), radii in cells, and every lighting value divided by the scene scale S or by the point floor
n(p). Neighbours are read through grid ids only, so the light sampler is called once per point.
Precision as features.md states it: float32 inputs, E(p, d) rounded to float32, every other step float64,
the result rounded to float32 at the end.
Points are processed in chunks so a million points fit in a few GiB.
"""

from __future__ import annotations

from typing import Callable, Protocol, runtime_checkable

import numpy as np

from ..errors import InvalidInputError
from . import features_kernel
from . import sh as shmath
from .grid import EvaluationGrid
from .schema import LPNN_V1

EPSILON = 1e-3
NEIGHBOUR_SCALES = (1, 2, 4)
RAY_LENGTH_CELLS = 4.0  # R = 4h
NEAR_CELLS = 1.0  # "near" = within 1h
DEFAULT_CHUNK_POINTS = 65_536
DEFAULT_RAY_CHUNK_POINTS = 16_384  # 26 rays each: ~430k rays per raycaster call
LIGHTING_FEATURE_COUNT = 15
GEOMETRY_FEATURE_COUNT = 4
FEATURE_COUNT = LPNN_V1.feature_count

_SIGNS = (1.0, -1.0)
_FACES = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
_CORNERS = np.array([[sx, sy, sz] for sx in _SIGNS for sy in _SIGNS for sz in _SIGNS]) / np.sqrt(3.0)
_EDGES = np.array(
    [[sx, sy, 0.0] for sx in _SIGNS for sy in _SIGNS]
    + [[sx, 0.0, sz] for sx in _SIGNS for sz in _SIGNS]
    + [[0.0, sy, sz] for sy in _SIGNS for sz in _SIGNS]
) / np.sqrt(2.0)
D14 = np.concatenate([_FACES, _CORNERS])  # lighting directions, features.md order
D26 = np.concatenate([D14, _EDGES])  # ray directions: D14 then the 12 edge directions
D14.setflags(write=False)
D26.setflags(write=False)
# The rays actually cast: D26 rounded to float32, as Unity's Vector3 (and Embree, and the C# core) hold
# them. Grazing rays (t_near == t_far on a box edge) flip between hit and miss with the last bit of the
# direction, so both languages must cast the very same directions.
RAY_DIRECTIONS = D26.astype(np.float32).astype(np.float64)
RAY_DIRECTIONS.setflags(write=False)
LIGHT_VALUES = D14.shape[0] * 3  # the 42 numbers rel() compares


class FeatureError(InvalidInputError):
    """Features cannot be extracted from these inputs; the message names the bad point and the fix."""


@runtime_checkable
class Raycaster(Protocol):
    def cast(self, origins: np.ndarray, directions: np.ndarray, max_distance: float) -> tuple[np.ndarray, np.ndarray]:
        """First hit of each ray with any surface of either facing.

        origins, directions: (R, 3) float64, directions unit (the extractor casts D26 rounded to float32,
        like Unity and the C# core). Returns distances (R,) float64 in
        [0, max_distance], np.inf for no hit within max_distance, and normals (R, 3) float64 (zeros
        for misses; orientation free: the extractor turns them to face the ray).

        A raycaster may also offer `first_hit_distances(origins, directions, max_distances (R,)) -> distances (R,)`,
        each ray ending at its own distance: segment tests (lpnn.core.segments) then cast each segment to its own
        length (EmbreeRaycaster does).
        """
        ...


# ------------------------------------------------------------------------------------------ inputs

def _bad_sh_message(sh: np.ndarray, grid: EvaluationGrid | None) -> str | None:
    bad_rows = np.flatnonzero(~np.all(np.isfinite(sh), axis=1))
    if bad_rows.shape[0] == 0:
        return None
    row = int(bad_rows[0])
    column = int(np.flatnonzero(~np.isfinite(sh[row]))[0])
    where = f"point {row}"
    if grid is not None:
        i, j, k = (int(v) for v in grid.ids[row])
        x, y, z = (float(v) for v in grid.positions[row])
        where += f" (id {i},{j},{k}, position {x:g},{y:g},{z:g})"
    return (
        f"SH of {where} is not finite: sh[{'rgb'[column // 9]},{column % 9}] = {float(sh[row, column])}; "
        f"{bad_rows.shape[0]:,} of {sh.shape[0]:,} points have non-finite SH. Re-bake the lighting "
        "(Unity: Generate Lighting) or re-import the scene, then extract the features again"
    )


def _checked_sh(sh: np.ndarray, grid: EvaluationGrid | None) -> np.ndarray:
    values = np.asarray(sh)
    if values.ndim != 2 or values.shape[1] != shmath.SH_FLOATS:
        raise FeatureError(f"SH must have shape (N, 27), got {list(values.shape)}")
    if grid is not None and values.shape[0] != grid.point_count:
        raise FeatureError(f"SH has {values.shape[0]:,} rows but the grid has {grid.point_count:,} points")
    message = _bad_sh_message(values, grid)
    if message:
        raise FeatureError(message)
    return values


def _dc_luminance(sh: np.ndarray) -> np.ndarray:
    """Y0 = w . (s0, s9, s18), float64."""
    return shmath.luminance(shmath.as_rgb_coefficients(sh)[..., 0])


def scene_scale(sh: np.ndarray) -> float:
    """S = median of Y0 over points with Y0 > 0 (mean of the middle two for an even count); 1 if none."""
    return _scene_scale(_checked_sh(sh, None))


def _scene_scale(sh: np.ndarray) -> float:
    y0 = _dc_luminance(sh)
    positive = y0[y0 > 0.0]
    if positive.shape[0] == 0:
        return 1.0
    return float(np.median(positive))


def _checked_scale(scale: float) -> float:
    s = float(scale)
    if not (np.isfinite(s) and s > 0.0):
        raise FeatureError(f"scene scale {scale!r} must be a finite number > 0 (see scene_scale)")
    return s


# --------------------------------------------------------------------------------------- lighting

def _light_values(sh: np.ndarray, chunk_points: int) -> np.ndarray:
    """E(p, d) over D14 for every point: (N, 42), direction-major. Rounded to float32 like the C# cache
    (features.md "Precision"), held in float64 so every later step computes in double."""
    out = np.empty((sh.shape[0], LIGHT_VALUES), dtype=np.float64)
    for start in range(0, sh.shape[0], chunk_points):
        stop = min(start + chunk_points, sh.shape[0])
        values = shmath.evaluate(sh[start:stop], D14).reshape(stop - start, LIGHT_VALUES)
        out[start:stop] = values.astype(np.float32)
    return out


def _local_features(sh: np.ndarray, light: np.ndarray, scale: float) -> np.ndarray:
    """Features 0-7 for a chunk: (M, 8) float64."""
    coefficients = shmath.as_rgb_coefficients(sh)  # (M, 3, 9)
    dc = coefficients[:, :, 0]  # C0 (M, 3)
    y0 = shmath.luminance(dc)
    floor = np.maximum(y0, 0.0) + EPSILON * scale  # n(p)
    floor_sq = floor * floor
    ycocg = shmath.rgb_to_ycocg(dc)
    l1 = shmath.luminance(np.swapaxes(coefficients[:, :, 1:4], 1, 2))  # (M, 3): w.(s1..), w.(s2..), w.(s3..)
    rgb = light.reshape(-1, D14.shape[0], 3)  # (M, 14, 3)
    out = np.empty((sh.shape[0], 8), dtype=np.float64)
    out[:, 0] = np.log(np.maximum(y0, 0.0) / scale + EPSILON)
    out[:, 1] = ycocg[:, 1] / floor
    out[:, 2] = ycocg[:, 2] / floor
    out[:, 3] = np.sqrt(np.sum(l1 * l1, axis=1)) / floor
    out[:, 4] = np.var(shmath.luminance(rgb), axis=1) / floor_sq
    out[:, 5:8] = np.var(rgb, axis=1) / floor_sq[:, None]
    return out


def lighting_features(grid: EvaluationGrid, sh: np.ndarray, scale: float,
                      chunk_points: int = DEFAULT_CHUNK_POINTS,
                      progress: Callable[[int, int], None] | None = None) -> np.ndarray:
    """Features 0-14 (SH, variances, boundary, change_k, curvature_k): (N, 15) float64."""
    return _lighting_features(grid, _checked_sh(sh, grid), _checked_scale(scale), chunk_points, progress)


def _lighting_features(grid: EvaluationGrid, values: np.ndarray, s: float, chunk_points: int,
                       progress: Callable[[int, int], None] | None) -> np.ndarray:
    chunk = max(int(chunk_points), 1)
    n = grid.point_count
    out = np.zeros((n, LIGHTING_FEATURE_COUNT), dtype=np.float64)
    light = _light_values(values, chunk)
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        out[start:stop, 0:8] = _local_features(values[start:stop], light[start:stop], s)
        if progress is not None:
            progress(stop, n)
    rel = _RelativeDifference(light, LIGHT_VALUES * EPSILON * s, chunk)
    change = np.zeros(n, dtype=np.float64)
    curvature = np.zeros(n, dtype=np.float64)
    for scale_number, k in enumerate(NEIGHBOUR_SCALES):
        change[:] = 0.0
        curvature[:] = 0.0
        for axis in range(3):
            plus = grid.neighbour(axis, k)
            minus = _inverse_neighbours(plus)
            if k == 1:
                out[:, 8] += ((plus < 0).astype(np.float64) + (minus < 0).astype(np.float64)) / 6.0
            rel.raise_change(plus, change)
            rel.raise_curvature(plus, minus, curvature)
        out[:, 9 + scale_number] = change
        out[:, 12 + scale_number] = curvature
    return out


def _inverse_neighbours(plus: np.ndarray) -> np.ndarray:
    """The -offset neighbours from the +offset ones: plus[p] = q  <=>  minus[q] = p."""
    minus = np.full(plus.shape[0], -1, dtype=np.int64)
    present = np.flatnonzero(plus >= 0)
    minus[plus[present]] = present
    return minus


class _RelativeDifference:
    """rel(A, B) = sum|A - B| / (sum(|A| + |B|) + 42 eps S) over rows of the (N, 42) light values.

    sum(|A| + |B|) is taken as sum|A| + sum|B|, with sum|E| precomputed per point (in chunks on one
    buffer); the comparisons run pair by pair in features_kernel.py (no 42-wide temporaries).
    """

    def __init__(self, light: np.ndarray, floor: float, chunk: int):
        self.light = light
        self.floor = floor
        self.chunk = chunk
        self.abs_sum = np.empty(light.shape[0], dtype=np.float64)
        buffer = np.empty((min(chunk, light.shape[0]), LIGHT_VALUES), dtype=np.float64)
        for start in range(0, light.shape[0], chunk):
            block = buffer[: min(chunk, light.shape[0] - start)]
            np.abs(light[start:start + block.shape[0]], out=block)
            self.abs_sum[start:start + block.shape[0]] = block.sum(axis=1)

    def raise_change(self, plus: np.ndarray, change: np.ndarray) -> None:
        """change[p] and change[q] = max(., rel(E(q), E(p))) for every pair q = plus[p].

        rel is symmetric (and bit-identical when swapped), so each pair is computed once for both ends
        (compiled: features_kernel.py, numpy's arithmetic).
        """
        features_kernel.raise_change(self.light, self.abs_sum, self.floor, np.ascontiguousarray(plus, dtype=np.int64),
                                     change)

    def raise_curvature(self, plus: np.ndarray, minus: np.ndarray, curvature: np.ndarray) -> None:
        """curvature[p] = max(., rel(E(p), (E(p+) + E(p-))/2)) where both neighbours exist."""
        features_kernel.raise_curvature(self.light, self.abs_sum, self.floor, np.ascontiguousarray(plus, dtype=np.int64),
                                        np.ascontiguousarray(minus, dtype=np.int64), curvature)


# --------------------------------------------------------------------------------------- geometry

def _checked_distances(distances: np.ndarray, rays: int) -> np.ndarray:
    """A raycaster's distances (rays,) as float64: each >= 0, or inf for no hit; FeatureError naming the first bad one."""
    t = np.asarray(distances, dtype=np.float64)
    if t.shape != (rays,):
        raise FeatureError(f"raycaster returned distances {list(t.shape)} for {rays:,} rays; expected ({rays},)")
    bad = np.isnan(t) | (t < 0.0)
    if np.any(bad):
        ray = int(np.flatnonzero(bad)[0])
        raise FeatureError(f"raycaster returned distance {t[ray]} for ray {ray}: distances must be >= 0, or inf for "
                           "no hit (a raycaster bug)")
    return t


def _checked_hits(distances: np.ndarray, normals: np.ndarray, rays: int) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(distances, dtype=np.float64)
    nrm = np.asarray(normals, dtype=np.float64)
    if t.shape != (rays,) or nrm.shape != (rays, 3):
        raise FeatureError(f"raycaster returned distances {list(t.shape)} and normals {list(nrm.shape)} for "
                           f"{rays:,} rays; expected ({rays},) and ({rays}, 3)")
    t = _checked_distances(t, rays)
    bad = ~np.all(np.isfinite(nrm), axis=1)
    if np.any(bad):
        ray = int(np.flatnonzero(bad)[0])
        raise FeatureError(f"raycaster returned a non-finite normal {nrm[ray].tolist()} for ray {ray} (a raycaster bug)")
    return t, nrm


def geometry_features(grid: EvaluationGrid, raycaster: Raycaster, chunk_points: int = DEFAULT_RAY_CHUNK_POINTS,
                      progress: Callable[[int, int], None] | None = None) -> np.ndarray:
    """Features 15-18 (occlusion near/far, nearest surface, normal spread) from D26 rays: (N, 4) float64."""
    h = grid.cell_size
    ray_length = RAY_LENGTH_CELLS * h
    near = NEAR_CELLS * h
    rays_per_point = D26.shape[0]
    positions = grid.positions.astype(np.float64)
    n = grid.point_count
    chunk = max(int(chunk_points), 1)
    out = np.zeros((n, GEOMETRY_FEATURE_COUNT), dtype=np.float64)
    all_directions = np.tile(RAY_DIRECTIONS, (min(chunk, n), 1))  # the same 26 rays for every point
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        count = stop - start
        origins = np.repeat(positions[start:stop], rays_per_point, axis=0)
        directions = all_directions[: count * rays_per_point]
        t, normals = _checked_hits(*raycaster.cast(origins, directions, ray_length), count * rays_per_point)
        t = t.reshape(count, rays_per_point)
        # Face the ray origin: dot(n, d) <= 0, whatever the mesh winding.
        facing = np.where(np.sum(normals * directions, axis=1) > 0.0, -1.0, 1.0)
        normals = (normals * facing[:, None]).reshape(count, rays_per_point, 3)
        hit = t <= ray_length
        out[start:stop, 0] = np.count_nonzero(t <= near, axis=1) / rays_per_point
        out[start:stop, 1] = np.count_nonzero(hit, axis=1) / rays_per_point
        nearest = np.min(np.where(hit, t, np.inf), axis=1)
        out[start:stop, 2] = np.where(np.isfinite(nearest), nearest / ray_length, 1.0)
        out[start:stop, 3] = _normal_spread(normals, hit)
        if progress is not None:
            progress(stop, n)
    return out


def _normal_spread(normals: np.ndarray, hit: np.ndarray) -> np.ndarray:
    """1 - |mean of the unit hit normals| per point; zero-length normals ignored; 0 without any."""
    length = np.sqrt(np.sum(normals * normals, axis=2))
    used = hit & (length > 0.0)
    unit = np.where(used[:, :, None], normals / np.where(used, length, 1.0)[:, :, None], 0.0)
    count = np.count_nonzero(used, axis=1)
    mean = unit.sum(axis=1) / np.maximum(count, 1)[:, None]
    return np.where(count > 0, 1.0 - np.sqrt(np.sum(mean * mean, axis=1)), 0.0)


# ------------------------------------------------------------------------------------------ all 19

def extract_features(grid: EvaluationGrid, sh: np.ndarray, raycaster: Raycaster,
                     progress: Callable[[int, int], None] | None = None) -> tuple[np.ndarray, float]:
    """The (N, 19) float32 `lpnn.features.v1` matrix and the scene scale S.

    progress(done, total), if given, is called after every chunk; total = 2N (lighting pass, then
    ray pass) and the last call has done == total.
    """
    if grid.point_count == 0:
        raise FeatureError("the evaluation grid has no points: add a box that covers part of the scene")
    values = _checked_sh(sh, grid)
    scale = _scene_scale(values)
    n = grid.point_count
    lighting_progress = None if progress is None else (lambda done, _total: progress(done, 2 * n))
    geometry_progress = None if progress is None else (lambda done, _total: progress(n + done, 2 * n))
    out = np.empty((n, FEATURE_COUNT), dtype=np.float32)
    out[:, :LIGHTING_FEATURE_COUNT] = _lighting_features(grid, values, scale, DEFAULT_CHUNK_POINTS, lighting_progress)
    out[:, LIGHTING_FEATURE_COUNT:] = geometry_features(grid, raycaster, progress=geometry_progress)
    return out, scale
