"""Interpolation as Unity does it: tetrahedra, barycentric weights, projection outside the hull."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core import sh as shmath
from lpnn.quality.metric.interpolation import interpolate_sh, stencil_for
from lpnn.quality.metric.location import barycentric
from lpnn.quality.metric.triangulation import Frame, GeometryError, tetrahedralize

from quality_support import box_grid, linear_sh


def _random_probes(seed: int, count: int = 40) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-1.0, 1.0, (count, 3))


def _inside_points(probes: np.ndarray, count: int, seed: int) -> np.ndarray:
    """Random convex combinations of the probes: inside their hull."""
    rng = np.random.default_rng(seed)
    weights = rng.dirichlet(np.ones(probes.shape[0]) * 0.3, count)
    return weights @ probes


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_linear_field_is_reproduced_exactly_inside_the_hull(seed: int) -> None:
    probes = _random_probes(seed)
    query = _inside_points(probes, 500, seed + 10)
    result = interpolate_sh(probes, linear_sh(probes, seed), query)
    np.testing.assert_allclose(result, linear_sh(query, seed), rtol=0, atol=1e-12)


def test_linear_field_on_a_grid_subset_is_exact_and_grid_has_no_flat_tetrahedra() -> None:
    grid = box_grid(6, 5, 4)
    tri = tetrahedralize(grid)
    volumes = np.abs(np.linalg.det(tri.points[tri.tets[:, 1:]] - tri.points[tri.tets[:, :1]])) / 6.0
    assert volumes.min() > 1e-9  # cospherical grid, yet no zero-volume tetrahedra
    hull_volume = 5 * 4 * 3 / tri.frame.scale**3
    assert volumes.sum() == pytest.approx(hull_volume, rel=1e-12)
    assert np.unique(tri.tets).shape[0] == grid.shape[0]  # every probe kept
    probes = grid[::3]
    query = grid[np.setdiff1d(np.arange(grid.shape[0]), np.arange(0, grid.shape[0], 3))]
    inside = interpolate_sh(probes, linear_sh(probes), query)
    stencil = stencil_for(probes, query)
    np.testing.assert_allclose(inside[~stencil.outside], linear_sh(query)[~stencil.outside], atol=1e-12)


def test_weights_inside_are_non_negative_and_sum_to_one() -> None:
    probes = _random_probes(3, 60)
    stencil = stencil_for(probes, _inside_points(probes, 2000, 4))
    assert not np.any(stencil.outside)
    assert np.all(stencil.weights >= 0.0)
    np.testing.assert_allclose(stencil.weights.sum(axis=1), 1.0, atol=1e-12)
    # The weights reproduce the point itself (barycentric coordinates).
    np.testing.assert_allclose(np.einsum("mk,mkx->mx", stencil.weights, probes[stencil.vertices]),
                               _inside_points(probes, 2000, 4), atol=1e-12)


def test_outside_rule_is_the_nearest_hull_point_with_its_triangle_weights() -> None:
    probes = box_grid(3, 3, 3)  # hull: the cube [0, 2]^3
    query = np.array([[3.0, 1.0, 1.0], [-0.5, 0.25, 1.5], [2.5, 2.5, 2.5], [1.0, -4.0, 3.0]])
    stencil = stencil_for(probes, query)
    assert np.all(stencil.outside)
    expected = np.clip(query, 0.0, 2.0)  # projection onto a box
    projected = np.einsum("mk,mkx->mx", stencil.weights, probes[stencil.vertices])
    np.testing.assert_allclose(projected, expected, atol=1e-12)
    assert np.all(stencil.weights >= 0.0)
    np.testing.assert_allclose(stencil.weights.sum(axis=1), 1.0, atol=1e-12)


def test_outside_rule_is_continuous_at_the_hull() -> None:
    probes = _random_probes(5, 30)
    sh = np.random.default_rng(6).uniform(0.0, 1.0, (30, 27))
    tri = tetrahedralize(probes)
    # Points on the hull surface (centroids of boundary triangles) and an outward normal.
    corners = tri.world[tri.hull_faces]
    on_hull = corners.mean(axis=1)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    jumps = []
    for step in (1e-3, 1e-6, 1e-9):
        outside = interpolate_sh(probes, sh, on_hull + step * normal)
        inside = interpolate_sh(probes, sh, on_hull - step * normal)
        jumps.append(float(np.max(np.abs(outside - inside))))
    # Continuity: the jump across the hull vanishes linearly with the distance (thin boundary
    # tetrahedra make the inside gradient steep, so only the trend is fixed, not the constant).
    assert jumps[1] < jumps[0] / 100.0 and jumps[2] < jumps[1] / 100.0
    assert jumps[2] < 1e-5


def test_far_from_origin_and_any_scale_give_the_same_interpolation() -> None:
    probes = _random_probes(7, 50)
    sh = np.random.default_rng(10).uniform(0.0, 1.0, (50, 27))
    query = np.concatenate([_inside_points(probes, 200, 8), np.random.default_rng(9).uniform(-2, 2, (50, 3))])
    reference = interpolate_sh(probes, sh, query)
    for offset, scale in ((np.array([1e5, -2e5, 3e4]), 1.0), (np.zeros(3), 1e-3), (np.zeros(3), 1e3)):
        moved = interpolate_sh(probes * scale + offset, sh, query * scale + offset)
        np.testing.assert_allclose(moved, reference, atol=1e-6)


def test_four_probes_are_one_tetrahedron_and_triangulation_is_deterministic() -> None:
    four = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    assert tetrahedralize(four).tets.shape == (1, 4)
    grid = box_grid(4, 4, 4)
    np.testing.assert_array_equal(tetrahedralize(grid).tets, tetrahedralize(grid).tets)


def test_subset_triangulations_share_a_frame_consistently() -> None:
    grid = box_grid(5, 5, 5)
    frame = Frame.for_points(grid)
    full = tetrahedralize(grid, frame)
    inverse_error = np.einsum("tij,tjk->tik", full.inverse,
                              np.stack([full.points[full.tets[:, c]] - full.points[full.tets[:, 0]] for c in (1, 2, 3)],
                                       axis=2)) - np.eye(3)
    assert np.abs(inverse_error).max() < 1e-9
    lam = barycentric(full, np.arange(full.tets.shape[0]), full.points[full.tets].mean(axis=1))
    np.testing.assert_allclose(lam, 0.25, atol=1e-12)


@pytest.mark.parametrize("positions, message", [
    (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), "at least 4 probes"),
    (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 3, 0]]), "one plane"),
    (np.array([[0.0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]), "one line"),
    (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0]]), "coincide"),
    (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]]), "not finite"),
])
def test_invalid_probe_sets_are_clear_errors(positions: np.ndarray, message: str) -> None:
    with pytest.raises(GeometryError, match=message):
        tetrahedralize(positions)


def test_duplicates_far_from_origin_are_detected_relative_to_the_extent() -> None:
    base = box_grid(3, 3, 3, 0.5) + 1e5
    with pytest.raises(GeometryError, match="probe positions 0 and 27 coincide"):
        tetrahedralize(np.concatenate([base, base[:1] + 1e-9]))
    tetrahedralize(base)  # the distinct points 0.5 apart at 1e5 are fine


def test_sh_blend_is_linear_so_blending_directional_values_matches() -> None:
    probes = _random_probes(11, 20)
    sh = np.random.default_rng(12).uniform(0, 1, (20, 27))
    query = _inside_points(probes, 50, 13)
    stencil = stencil_for(probes, query)
    directions = np.eye(3)
    blended_then_evaluated = shmath.evaluate(shmath.blend(sh, stencil.vertices, stencil.weights), directions)
    evaluated_then_blended = np.einsum("mk,mkdc->mdc", stencil.weights, shmath.evaluate(sh, directions)[stencil.vertices])
    np.testing.assert_allclose(blended_then_evaluated, evaluated_then_blended, atol=1e-12)
