"""The baked light grid: decode cells, sample like the renderer, convert to Unity SH.

Sampling follows ioq3's R_SetupEntityLightingGrid (code/renderergl1/tr_light.c), vectorised over
points: trilinear weights over the 8 surrounding cells with the base cell clamped to the grid,
corners beyond the last cell skipped (ioq3; vanilla Q3 reads past the array there), cells whose
ambient R+G+B is 0 ("in a wall") skipped, ambient/directed renormalised when 0 < W < 0.99, and the
direction the normalised w-weighted sum of the cells' directions.

Units (Documentation~/openarena.md): the stored bytes are linear light in "full texture
brightness" units, 2^mapOverBrightBits / 255 = 4/255 per byte: what q3map2 baked. The engine's
r_ambientScale (0.6), its +32 ambient floor and its byte clamps are display choices made at run
time, not baked data, so they are not applied. Angles are decoded exactly (2*pi/256 per step);
the engine's 1024-entry sine table (divisor 1023) differs by ~0.1% and is not reproduced.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..core.sh import SH_FLOATS, ambient_plus_directed
from .bsp import Bsp, LightGridLayout
from .coords import quake_to_unity, unity_to_quake
from .errors import BspError

MAP_OVERBRIGHT_BITS = 2
LINEAR_PER_BYTE = 2.0 ** MAP_OVERBRIGHT_BITS / 255.0
# ioq3 renormalises partial weights only below this total (tr_light.c)
RENORMALISE_BELOW = 0.99
POINTS_PER_CHUNK = 65_536
# Positions this close to a node plane (in cells; 0.006 units at 64) are put on it: float32 metres
# are off by up to ~1e-5 cells across a 400 m level.
SNAP_TO_NODE = 1e-4


@dataclass(frozen=True)
class GridLight:
    """Light at points in the renderer's byte units (before LINEAR_PER_BYTE), Quake axes."""

    ambient: np.ndarray  # (N, 3) float64
    directed: np.ndarray  # (N, 3) float64
    direction: np.ndarray  # (N, 3) float64 unit toward the light, or zero when no direction
    weight: np.ndarray  # (N,) float64 total weight W of the valid corners (0: no valid corner)


class LightGrid:
    def __init__(self, layout: LightGridLayout, records: np.ndarray) -> None:
        records = np.asarray(records, dtype=np.uint8)
        if records.shape != (layout.point_count, 8):
            raise ValueError(f"light grid records {records.shape} do not match the layout's "
                             f"{layout.point_count} points x 8 bytes")
        self.layout = layout
        self.valid = records[:, 0:3].astype(np.int64).sum(axis=1) > 0
        # One row per cell, gathered once per corner: ambient (3), directed (3), direction (3),
        # zeroed for cells "in a wall", and the validity as the last column.
        cells = np.concatenate([records[:, 0:6].astype(np.float64), decode_directions(records[:, 6], records[:, 7]),
                                np.ones((len(records), 1))], axis=1)
        self._cells = np.where(self.valid[:, None], cells, 0.0)

    @classmethod
    def from_bsp(cls, bsp: Bsp) -> "LightGrid":
        if bsp.light_grid is None:
            raise BspError(f"{bsp.name}: lump 15 (lightgrid) is empty: the level was compiled without light "
                           f"(q3map2 -light), so it has no baked probe lighting to import")
        return cls(bsp.light_grid_layout, bsp.light_grid)

    def sample(self, points: np.ndarray) -> GridLight:
        """R_SetupEntityLightingGrid at points (N, 3) in Quake units, without r_ambientScale."""
        points = np.asarray(points, dtype=np.float64)
        if points.ndim != 2 or points.shape[1] != 3 or not np.isfinite(points).all():
            raise ValueError(f"light grid sample positions must be finite (N, 3), got shape {points.shape}")
        sums = np.zeros((len(points), 10))
        # chunks keep the temporaries small and reused: big fresh arrays cost page faults here
        for start in range(0, len(points), POINTS_PER_CHUNK):
            stop = min(start + POINTS_PER_CHUNK, len(points))
            sums[start:stop] = self._weighted_sums(points[start:stop])
        total = sums[:, 9]
        partial = (total > 0) & (total < RENORMALISE_BELOW)
        scale = np.where(partial, 1.0 / np.where(partial, total, 1.0), 1.0)[:, None]
        return GridLight(ambient=sums[:, 0:3] * scale, directed=sums[:, 3:6] * scale,
                         direction=_normalised(sums[:, 6:9]), weight=total)

    def _weighted_sums(self, points: np.ndarray) -> np.ndarray:
        """Sum over the 8 corners of w * (ambient, directed, direction, 1) for used corners: (N, 10)."""
        dims = self.layout.dims
        v = (points - self.layout.origin) / self.layout.cell_size
        # Lattice points meant to sit on grid nodes come back from float32 metres slightly off; with
        # the renormalisation, a corner weighted 1e-7 would then decide the whole value.
        nearest = np.rint(v)
        v = np.where(np.abs(v - nearest) <= SNAP_TO_NODE, nearest, v)
        base = np.floor(v)
        frac = v - base  # taken before clamping, as the engine does
        base = np.clip(base, 0, dims - 1).astype(np.int64)
        strides = np.array([1, dims[0], dims[0] * dims[1]], dtype=np.int64)
        base_index = base @ strides
        sums = np.zeros((len(points), 10))
        for corner in range(8):
            upper = np.array([(corner >> axis) & 1 for axis in range(3)], dtype=bool)
            weight = np.prod(np.where(upper, frac, 1.0 - frac), axis=1)
            # ioq3: ignore corners beyond the last cell (their weight is dropped, not clamped)
            inside = np.all(base[:, upper] < dims[upper] - 1, axis=1)
            index = np.where(inside, base_index + strides[upper].sum(), 0)
            # invalid cells hold zeros, so they add nothing, not even to the weight total
            sums += np.where(inside, weight, 0.0)[:, None] * self._cells[index]
        return sums

    def sh_at(self, unity_positions: np.ndarray,
              progress: Callable[[int, int], None] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Unity SphericalHarmonicsL2 (N, 27) float64 at positions in Unity metres, and (N,) bool
        "lit": at least one valid corner. Points with no valid corner get all-zero (black) SH.
        progress(done, total), if given, is called after every chunk.
        """
        positions = np.asarray(unity_positions)
        sh = np.empty((len(positions), SH_FLOATS))
        lit = np.empty(len(positions), dtype=bool)
        for start in range(0, len(positions), POINTS_PER_CHUNK):
            chunk = slice(start, min(start + POINTS_PER_CHUNK, len(positions)))
            light = self.sample(unity_to_quake(positions[chunk]))
            sh[chunk] = ambient_plus_directed(
                LINEAR_PER_BYTE * light.ambient,
                LINEAR_PER_BYTE * light.directed,
                quake_to_unity(light.direction, scale=1.0),
            )
            lit[chunk] = light.weight > 0
            if progress is not None:
                progress(chunk.stop, len(positions))
        return sh, lit


def decode_directions(theta_bytes: np.ndarray, phi_bytes: np.ndarray) -> np.ndarray:
    """Byte 6 = polar angle from +Z, byte 7 = azimuth from +X toward +Y, 2*pi/256 per step -> unit (N, 3)."""
    theta = np.asarray(theta_bytes, dtype=np.float64) * (2.0 * np.pi / 256.0)
    phi = np.asarray(phi_bytes, dtype=np.float64) * (2.0 * np.pi / 256.0)
    return np.stack([np.cos(phi) * np.sin(theta), np.sin(phi) * np.sin(theta), np.cos(theta)], axis=1)


def _normalised(vectors: np.ndarray) -> np.ndarray:
    """Unit vectors; zero stays zero (VectorNormalize2 semantics)."""
    lengths = np.linalg.norm(vectors, axis=1, keepdims=True)
    return np.divide(vectors, lengths, out=np.zeros_like(vectors), where=lengths > 0)
