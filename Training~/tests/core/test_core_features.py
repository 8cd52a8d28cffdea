"""lpnn.core.features against Documentation~/features.md: analytic cases, a naive reference, invariances."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lpnn.core import sh as shmath
from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AnalyticScene, AxisBox
from lpnn.core.features import (
    D14,
    D26,
    EPSILON,
    FeatureError,
    Raycaster,
    extract_features,
    geometry_features,
    lighting_features,
    scene_scale,
)
from lpnn.core.grid import EvaluationGrid
from lpnn.core.grid_box import Box
from lpnn.core.grid_builder import build_grid
from lpnn.core.schema import LPNN_V1

W = (0.2126, 0.7152, 0.0722)
NAMES = {name: index for index, name in enumerate(LPNN_V1.names)}


class NoSurfaces:
    def cast(self, origins, directions, max_distance):
        return np.full(origins.shape[0], np.inf), np.zeros_like(origins)


def cube_grid(n: int, h: float = 0.5) -> EvaluationGrid:
    return build_grid([Box.axis_aligned([0, 0, 0], [(n - 1) * h] * 3)], h)


# ------------------------------------------------------------------------------------- constants

def test_direction_sets_are_unit_and_in_spec_order():
    s3, s2 = 1 / math.sqrt(3), 1 / math.sqrt(2)
    assert D14.shape == (14, 3) and D26.shape == (26, 3)
    assert np.allclose(np.linalg.norm(D26, axis=1), 1.0, atol=1e-15)
    assert D14[:6].tolist() == [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    assert np.allclose(D14[6], [s3, s3, s3]) and np.allclose(D14[7], [s3, s3, -s3])
    assert np.allclose(D14[8], [s3, -s3, s3]) and np.allclose(D14[13], [-s3, -s3, -s3])
    assert np.array_equal(D26[:14], D14)
    assert np.allclose(D26[14], [s2, s2, 0]) and np.allclose(D26[15], [s2, -s2, 0])
    assert np.allclose(D26[18], [s2, 0, s2]) and np.allclose(D26[25], [0, -s2, -s2])


def test_scene_scale_is_the_median_of_positive_dc_luminance():
    def grey(values):
        return np.concatenate([shmath.ambient(np.array([[v, v, v]]) ) for v in values]).astype(np.float32)

    assert scene_scale(grey([-5.0, 0.0, 1.0, 2.0, 10.0])) == pytest.approx(2.0)
    assert scene_scale(grey([1.0, 2.0, 4.0, 10.0])) == pytest.approx(3.0)  # mean of the middle two
    assert scene_scale(grey([0.0, -1.0])) == 1.0
    red = np.zeros((1, 27), np.float32)
    red[0, 0] = 2.0
    assert scene_scale(red) == pytest.approx(2.0 * 0.2126)


# ---------------------------------------------------------------------------- analytic lighting

def test_constant_ambient_field():
    grid = cube_grid(4)
    r, g, b = 0.3, 0.5, 0.2
    sh = np.repeat(shmath.ambient(np.array([[r, g, b]])), grid.point_count, axis=0).astype(np.float32)
    features = lighting_features(grid, sh, scene_scale(sh))
    y0 = W[0] * r + W[1] * g + W[2] * b
    r, g, b = (float(np.float32(v)) for v in (r, g, b))
    floor = y0 * (1 + EPSILON)
    assert np.allclose(features[:, 0], math.log(1 + EPSILON))
    assert np.allclose(features[:, 1], (r - b) / 2 / floor)
    assert np.allclose(features[:, 2], (-r / 4 + g / 2 - b / 4) / floor)
    for name in ("directionality", "change_1", "change_2", "change_4", "curvature_1", "curvature_2", "curvature_4"):
        assert np.all(features[:, NAMES[name]] == 0.0), name
    for name in ("light_variance", "rgb_variance_r", "rgb_variance_g", "rgb_variance_b"):
        assert np.all(np.abs(features[:, NAMES[name]]) <= 1e-15), name  # the mean of 14 equal values rounds


def test_linear_field_has_no_curvature_inside_and_known_change():
    grid = cube_grid(9)
    i = grid.ids[:, 0].astype(np.float64)
    grey_dc = 100.0 + 4.0 * i  # exactly representable: linear in float32 too
    sh = np.zeros((grid.point_count, 27), np.float32)
    sh[:, [0, 9, 18]] = grey_dc[:, None]
    sh[:, [1, 10, 19]] = 7.0 + i[:, None]  # a linear L1 term as well
    features = lighting_features(grid, sh, scene_scale(sh))
    for k, name in ((1, "curvature_1"), (2, "curvature_2"), (4, "curvature_4")):
        interior = (grid.ids[:, 0] >= k) & (grid.ids[:, 0] <= 8 - k)
        # E is rounded to float32, so "exact" linear interpolation holds to float32 rounding (~6e-8 relative)
        assert np.all(np.abs(features[interior, NAMES[name]]) <= 1e-7), name
        # elsewhere only the y and z axes have both neighbours, and the field is constant along them
        assert np.all(features[~interior, NAMES[name]] == 0.0)
    # change_k along x for the point with i = 4: the larger of the two neighbours' rel (the smaller DC one)
    centre = grid.index_of(np.array([[4, 4, 4]]))[0]
    for k, name in ((1, "change_1"), (2, "change_2"), (4, "change_4")):
        e_p = reference_light(sh[centre])
        candidates = [reference_rel(reference_light(sh[grid.index_of(np.array([[4 + s * k, 4, 4]]))[0]]), e_p,
                                    scene_scale(sh)) for s in (1, -1)]
        assert features[centre, NAMES[name]] == pytest.approx(max(candidates), rel=1e-12)


def test_boundary_counts_missing_face_neighbours():
    grid = cube_grid(3)
    features = lighting_features(grid, np.ones((27, 27), np.float32), 1.0)
    boundary = features[:, NAMES["boundary"]]
    for index, (i, j, k) in enumerate(grid.ids.tolist()):
        missing = sum(c in (0, 2) for c in (i, j, k))
        assert boundary[index] == pytest.approx(missing / 6)
    single = build_grid([Box.axis_aligned([0, 0, 0], [0, 0, 0])], 1.0)
    assert lighting_features(single, np.ones((1, 27), np.float32), 1.0)[0, NAMES["boundary"]] == 1.0


# ------------------------------------------------------------------------ naive reference (spec)

def reference_light(s: np.ndarray) -> np.ndarray:
    """E over D14, 42 values direction-major, with the sh.md polynomials written out, rounded to float32
    as features.md "Precision" specifies."""
    out = []
    for x, y, z in D14.tolist():
        poly = [1, y, z, x, x * y, y * z, 3 * z * z - 1, x * z, x * x - y * y]
        out.extend(sum(float(s[c * 9 + i]) * poly[i] for i in range(9)) for c in range(3))
    return np.array(out).astype(np.float32).astype(np.float64)


def reference_rel(a: np.ndarray, b: np.ndarray, scale: float) -> float:
    return float(np.sum(np.abs(a - b)) / (np.sum(np.abs(a) + np.abs(b)) + 42 * EPSILON * scale))


def reference_lighting(grid: EvaluationGrid, sh: np.ndarray) -> np.ndarray:
    table = {tuple(r): n for n, r in enumerate(grid.ids.tolist())}
    y0s = [W[0] * float(s[0]) + W[1] * float(s[9]) + W[2] * float(s[18]) for s in sh]
    positive = sorted(y for y in y0s if y > 0)
    scale = 1.0 if not positive else (positive[len(positive) // 2] if len(positive) % 2
                                      else (positive[len(positive) // 2 - 1] + positive[len(positive) // 2]) / 2)
    light = [reference_light(s) for s in sh]
    rows = []
    for index, ident in enumerate(grid.ids.tolist()):
        s = [float(v) for v in sh[index]]
        y0 = y0s[index]
        floor = max(y0, 0) + EPSILON * scale
        l1 = [W[0] * s[1 + a] + W[1] * s[10 + a] + W[2] * s[19 + a] for a in range(3)]
        e = light[index].reshape(14, 3)
        lum = e @ np.array(W)
        row = [math.log(max(y0, 0) / scale + EPSILON), (s[0] - s[18]) / 2 / floor,
               (-s[0] / 4 + s[9] / 2 - s[18] / 4) / floor, math.sqrt(sum(v * v for v in l1)) / floor,
               float(np.mean((lum - lum.mean()) ** 2)) / floor**2]
        row += [float(np.mean((e[:, c] - e[:, c].mean()) ** 2)) / floor**2 for c in range(3)]

        def at(axis, offset, ident=ident):
            moved = list(ident)
            moved[axis] += offset
            return table.get(tuple(moved))

        row.append(sum(at(a, o) is None for a in range(3) for o in (1, -1)) / 6)
        changes, curvatures = [], []
        for k in (1, 2, 4):
            rels = [reference_rel(light[q], light[index], scale) for a in range(3) for o in (k, -k)
                    if (q := at(a, o)) is not None]
            changes.append(max(rels, default=0.0))
            curves = [reference_rel(light[index], (light[at(a, k)] + light[at(a, -k)]) / 2, scale)
                      for a in range(3) if at(a, k) is not None and at(a, -k) is not None]
            curvatures.append(max(curves, default=0.0))
        rows.append(row + changes + curvatures)
    return np.array(rows)


def test_lighting_matches_a_naive_reference_on_an_irregular_grid():
    scene = AnalyticScene.random(seed=11)
    boxes = [Box.axis_aligned([0, 0, 0], [2.0, 1.5, 1.0]),
             Box(center=[2.6, 0.4, 0.3], half_edges=[[0.6, 0.6, 0], [-0.5, 0.5, 0], [0, 0, 0.3]])]
    grid = build_grid(boxes, 0.5)
    sh = scene.light_field.sample(grid.positions * 0.9 - 1.0)
    actual = lighting_features(grid, sh, scene_scale(sh), chunk_points=7)  # odd chunks: boundaries exercised
    expected = reference_lighting(grid, sh)
    assert grid.point_count > 60
    assert np.allclose(actual, expected, rtol=1e-10, atol=1e-12)
    assert np.array_equal(actual, lighting_features(grid, sh, scene_scale(sh)))  # chunking never changes a bit


# ----------------------------------------------------------------------------------- invariances

def test_exposure_invariance_from_1e_minus_6_to_1e6():
    scene = AnalyticScene.random(seed=5)
    grid = scene.grid()
    sh = scene.light_field.sample(grid.positions)
    base, _ = extract_features(grid, sh, scene.raycaster)
    for factor in (1e-6, 1e6):
        scaled, scale = extract_features(grid, (sh.astype(np.float64) * factor).astype(np.float32), scene.raycaster)
        assert np.allclose(scaled, base, rtol=1e-5, atol=2e-5), factor
        assert scale == pytest.approx(scene_scale(sh) * factor, rel=1e-6)


def test_hdr_lighting_spanning_twelve_decades_stays_finite_and_bounded():
    grid = cube_grid(6)
    rng = np.random.default_rng(2)
    magnitude = 10.0 ** rng.uniform(-6, 6, grid.point_count)
    sh = shmath.ambient(rng.uniform(0.1, 1.0, (grid.point_count, 3))) * magnitude[:, None]
    sh += shmath.directional(np.array([0.0, 0.6, 0.8]), np.ones(3), 1.0)[None, :] * magnitude[:, None] * 0.5
    features, _ = extract_features(grid, sh.astype(np.float32), NoSurfaces())
    assert features.dtype == np.float32 and np.all(np.isfinite(features))
    relatives = [NAMES[n] for n in ("change_1", "change_2", "change_4", "curvature_1", "curvature_2", "curvature_4")]
    assert np.all((features[:, relatives] >= 0) & (features[:, relatives] <= 1))
    assert features[:, NAMES["change_1"]].max() > 0.9  # neighbours differ by decades


def test_non_finite_sh_is_reported_with_point_id_position_and_count():
    grid = cube_grid(3)
    sh = np.ones((27, 27), np.float32)
    sh[5, 11] = np.nan
    sh[9, 0] = np.inf
    with pytest.raises(FeatureError) as error:
        extract_features(grid, sh, NoSurfaces())
    message = str(error.value)
    i, j, k = grid.ids[5]
    assert f"point 5 (id {i},{j},{k}, position {i * 0.5:g},{j * 0.5:g},{k * 0.5:g})" in message
    assert "sh[g,2]" in message and "2 of 27 points" in message and "re-bake" in message.lower()
    with pytest.raises(FeatureError, match="26 rows but the grid has 27 points"):
        extract_features(grid, np.ones((26, 27), np.float32), NoSurfaces())  # one row short


# -------------------------------------------------------------------------------------- geometry

def one_point(position, h: float) -> EvaluationGrid:
    return EvaluationGrid(cell_size=h, ids=np.array([np.round(np.array(position) / h)], dtype=np.int32))


def geometry_of(point, h, raycaster: Raycaster) -> dict[str, float]:
    values = geometry_features(one_point(point, h), raycaster)[0]
    return dict(zip(("near", "far", "nearest", "spread"), values.tolist()))


def test_centre_of_an_empty_room_sees_nothing():
    room = AnalyticBoxRaycaster(room=AxisBox([-50, -50, -50], [50, 50, 50]))
    assert geometry_of([0, 0, 0], 0.5, room) == {"near": 0.0, "far": 0.0, "nearest": 1.0, "spread": 0.0}


def test_point_near_one_wall():
    # wall x = 0.3 at h = 0.5 (R = 2): +x hits at 0.3, 4 edge rays at 0.3*sqrt2 = 0.42 (<= h),
    # 4 corner rays at 0.3*sqrt3 = 0.52 (<= R only)
    room = AnalyticBoxRaycaster(room=AxisBox([-50, -50, -50], [0.3, 50, 50]))
    result = geometry_of([0, 0, 0], 0.5, room)
    assert result["near"] == pytest.approx(5 / 26)
    assert result["far"] == pytest.approx(9 / 26)
    assert result["nearest"] == pytest.approx(0.3 / 2.0)
    assert result["spread"] == pytest.approx(0.0, abs=1e-15)


def test_point_in_a_corner_mixes_normals():
    # walls x = 0.3 and y = 0.3: 9 rays hit the x wall (corner ties go to x), 6 the y wall
    room = AnalyticBoxRaycaster(room=AxisBox([-5, -5, -5], [0.3, 0.3, 5]))
    result = geometry_of([0, 0, 0], 0.5, room)
    assert result["far"] == pytest.approx(15 / 26)
    assert result["spread"] == pytest.approx(1 - math.sqrt(9**2 + 6**2) / 15)


class Rewired:
    """Wraps a raycaster: flips every normal, or zeroes them."""

    def __init__(self, inner, mode: str):
        self.inner, self.mode = inner, mode

    def cast(self, origins, directions, max_distance):
        t, n = self.inner.cast(origins, directions, max_distance)
        return t, (-n if self.mode == "flip" else np.zeros_like(n))


def test_normals_are_reoriented_and_zero_normals_only_skip_the_spread():
    room = AnalyticBoxRaycaster(room=AxisBox([-5, -5, -5], [0.3, 0.3, 5]))
    base = geometry_of([0, 0, 0], 0.5, room)
    assert geometry_of([0, 0, 0], 0.5, Rewired(room, "flip")) == base
    zero = geometry_of([0, 0, 0], 0.5, Rewired(room, "zero"))
    assert zero == {**base, "spread": 0.0}


# ------------------------------------------------------------------------------------ extraction

def test_extract_features_shape_progress_and_determinism():
    scene = AnalyticScene.random(seed=1)
    grid = scene.grid()
    sh = scene.light_field.sample(grid.positions)
    calls: list[tuple[int, int]] = []
    features, scale = extract_features(grid, sh, scene.raycaster, progress=lambda d, t: calls.append((d, t)))
    assert features.shape == (grid.point_count, 19) and features.dtype == np.float32
    assert scale == pytest.approx(scene_scale(sh))
    assert calls[-1] == (2 * grid.point_count, 2 * grid.point_count)
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:]))
    again, _ = extract_features(grid, sh.copy(), scene.raycaster)
    assert again.tobytes() == features.tobytes()
    assert np.all(np.isfinite(features))
    occlusion = features[:, NAMES["occlusion_far"]]
    assert occlusion.min() >= 0 and occlusion.max() <= 1 and occlusion.max() > 0


def test_raycaster_contract_is_checked():
    class Broken:
        def cast(self, origins, directions, max_distance):
            return np.full(origins.shape[0], np.nan), np.zeros_like(origins)

    with pytest.raises(FeatureError, match="raycaster returned distance nan"):
        geometry_features(cube_grid(2), Broken())


@pytest.mark.slow
def test_a_million_points_extract_within_bounded_memory():
    import tracemalloc

    grid = build_grid([Box.axis_aligned([0, 0, 0], [49.5, 49.5, 49.5])], 0.5)
    rng = np.random.default_rng(0)
    sh = rng.uniform(0.0, 1.0, size=(grid.point_count, 27)).astype(np.float32)
    tracemalloc.start()
    try:
        features, _ = extract_features(grid, sh, NoSurfaces())
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert features.shape == (1_000_000, 19) and np.all(np.isfinite(features))
    assert peak < 2 * 2**30, f"peak {peak / 2**30:.2f} GiB"  # E cache (336 MB) + chunks, not per-point blow-up
    assert features[0, NAMES["boundary"]] == 0.5 and features[555_555, NAMES["boundary"]] == 0.0
