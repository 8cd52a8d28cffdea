"""lpnn.core.selection against Documentation~/selection.md."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from lpnn.core.grid import EvaluationGrid
from lpnn.core.grid_box import Box
from lpnn.core.grid_builder import build_grid
from lpnn.core.selection import (
    SelectionError,
    ensure_tetrahedron,
    percentile_count,
    rank,
    remap,
    select,
)

NAN, INF = float("nan"), float("inf")


def cube(n: int = 4, h: float = 1.0) -> EvaluationGrid:
    return build_grid([Box.axis_aligned([0, 0, 0], [(n - 1) * h] * 3)], h)


def sorted_grid(ids) -> EvaluationGrid:
    ids = np.asarray(ids, dtype=np.int64)
    return EvaluationGrid(cell_size=1.0, ids=ids[np.lexsort((ids[:, 0], ids[:, 1], ids[:, 2]))])


def coplanar(points: np.ndarray) -> bool:
    """Python-integer oracle: are all points on one plane (or line, or point)?"""
    pts = [tuple(int(v) for v in p) for p in points]
    a = pts[0]
    for b, c in itertools.combinations(pts[1:], 2):
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        if any(n):
            return all(sum(n[i] * (p[i] - a[i]) for i in range(3)) == 0 for p in pts)
    return True


# ----------------------------------------------------------------------------------------- ranking

def test_rank_orders_infinities_finite_values_and_nan_with_index_ties():
    scores = np.array([1.0, NAN, INF, -INF, 1.0, 3.0, INF, NAN, -0.0, 0.0])
    assert rank(scores).tolist() == [2, 6, 5, 0, 4, 8, 9, 3, 1, 7]
    assert rank(np.full(5, 0.25, np.float32)).tolist() == [0, 1, 2, 3, 4]


def test_remap():
    assert remap(np.array([2.0, 4.0, 3.0, NAN, INF, -INF])).tolist() == [0.0, 1.0, 0.5, 0.0, 1.0, 0.0]
    assert remap(np.full(4, 7.0)).tolist() == [1.0] * 4  # all equal: nothing is less important
    assert remap(np.array([NAN, -INF])).tolist() == [0.0, 0.0]
    extreme = remap(np.array([-1.7e308, 0.0, 1.7e308]))
    assert extreme.tolist() == [0.0, 0.5, 1.0]


@pytest.mark.parametrize("p, n, k", [(0.9, 100, 10), (0.9, 125, 13), (0.0, 7, 7), (1.0, 7, 0), (0.5, 3, 2), (0.75, 2, 1), (0.9, 0, 0)])
def test_percentile_count(p, n, k):
    assert percentile_count(p, n) == k


@pytest.mark.parametrize("p", [-0.1, 1.1, NAN, INF, "x"])
def test_percentile_out_of_range(p):
    with pytest.raises(SelectionError, match="percentile"):
        percentile_count(p, 10)


# ---------------------------------------------------------------------------------------- policies

def test_percentile_budget_threshold():
    grid = cube()
    scores = np.arange(grid.point_count, dtype=np.float64)  # the best points are the last indices (z = 3 layer)
    top = select(grid, scores, "percentile", 0.7)  # K = floor(0.3 * 64 + 0.5) = 19
    assert top.indices.tolist() == list(range(45, 64)) and top.added_for_tetrahedron == 0
    layer = select(grid, scores, "percentile", 0.75)  # K = 16: exactly the z = 3 layer, one plane
    assert layer.indices.tolist() == list(range(47, 64)) and layer.added_for_tetrahedron == 1
    budget = select(grid, scores, "budget", 20)
    assert budget.indices.tolist() == list(range(44, 64))
    assert select(grid, scores, "budget", 10_000).indices.shape == (64,)
    threshold = select(grid, scores, "threshold", 40 / 63)
    assert threshold.indices.tolist() == list(range(40, 64))


def test_threshold_never_passes_nan_and_all_equal_scores_pass():
    grid = cube()
    scores = np.full(grid.point_count, 3.0)
    scores[5] = NAN
    result = select(grid, scores, "threshold", 0.0)
    assert 5 not in result.indices and result.indices.shape == (63,)
    assert select(grid, np.full(grid.point_count, 3.0), "threshold", 1.0).indices.shape == (64,)


@pytest.mark.parametrize("policy, value, match", [
    ("budget", 0, "budget"), ("budget", 2.5, "budget"), ("threshold", 1.5, "threshold"),
    ("percentile", -1, "percentile"), ("nearest", 1, "unknown selection policy 'nearest'"),
])
def test_policy_parameters_are_validated(policy, value, match):
    with pytest.raises(SelectionError, match=match):
        select(cube(), np.zeros(64), policy, value)


def test_keep_corners_adds_the_eight_corner_points():
    box = Box.axis_aligned([0.2, 0.2, 0.2], [2.7, 2.7, 2.7])  # corners round to lattice 0 and 3
    grid = build_grid([box], 1.0)
    scores = np.zeros(grid.point_count)
    scores[grid.index_of(np.array([[1, 1, 1]]))[0]] = 1.0
    result = select(grid, scores, "budget", 1, keep_corners=True, boxes=[box])
    corner_ids = {tuple(c) for c in itertools.product((0, 3), repeat=3)}
    chosen = {tuple(grid.ids[i]) for i in result.indices}
    assert corner_ids <= chosen and (1, 1, 1) in chosen
    assert result.corners_added == 8 and result.added_for_tetrahedron == 0 and len(chosen) == 9
    with pytest.raises(SelectionError, match="boxes"):
        select(grid, scores, "budget", 1, keep_corners=True)
    # a corner whose point was dropped (e.g. inside a wall) is skipped, not invented
    keep = np.ones(grid.point_count, dtype=bool)
    keep[grid.index_of(np.array([[0, 0, 0]]))[0]] = False
    part = grid.subset(keep)
    partial = select(part, scores[keep], "budget", 1, keep_corners=True, boxes=[box])
    assert partial.corners_added == 7 and (0, 0, 0) not in {tuple(part.ids[i]) for i in partial.indices}


# -------------------------------------------------------------------------------------- tetrahedron

def test_empty_selection_gets_four_top_ranked_non_coplanar_points():
    grid = cube()
    scores = np.arange(grid.point_count, dtype=np.float64)
    result = select(grid, scores, "percentile", 1.0)  # K = 0
    assert result.added_for_tetrahedron == 4
    # 63, 62 (same line, so next: the best off the x line = 59 (3,2,3)); then the best off z = 3: 47
    assert result.indices.tolist() == [47, 59, 62, 63]
    assert not coplanar(grid.ids[result.indices])


def test_single_point_and_collinear_and_coplanar_sets_are_completed():
    grid = cube()
    ranking = rank(np.arange(grid.point_count, dtype=np.float64))
    for start in ([0], [0, 1, 2, 3], [0, 1, 4, 5, 10]):
        indices, added = ensure_tetrahedron(grid, ranking, np.array(start))
        assert not coplanar(grid.ids[indices])
        assert set(start) <= set(indices.tolist()) and added == len(indices) - len(start) and added <= 4
    indices, added = ensure_tetrahedron(grid, ranking, np.array([0, 1, 4, 16]))
    assert added == 0 and indices.tolist() == [0, 1, 4, 16]


@pytest.mark.parametrize("box, kind, axes", [
    (Box.axis_aligned([0, 0, 0], [0, 0, 0]), "a single point", "x, y and z"),
    (Box.axis_aligned([0, 0, 0], [3, 0, 0]), "a line", "y and z"),
    (Box.axis_aligned([0, 0, 0], [0, 0, 3]), "a line", "x and y"),
    (Box.axis_aligned([0, 0, 0], [3, 3, 0]), "one plane", "z"),
    (Box.axis_aligned([0, 0, 0], [3, 0, 3]), "one plane", "y"),
])
def test_flat_grids_are_clear_errors(box, kind, axes):
    grid = build_grid([box], 1.0)
    with pytest.raises(SelectionError) as error:
        select(grid, np.zeros(grid.point_count), "budget", 1)
    assert kind in str(error.value) and f"two cells deep along {axes} or use a smaller cell size" in str(error.value)


def test_coplanarity_is_exact_for_ids_near_two_to_the_thirty():
    rng = np.random.default_rng(8)
    big = 2**26  # the on-plane combinations below reach 11 * 2^26 < 2^30; spans ~2^29 overflow int64 products
    a, b, c = (rng.integers(-big, big, 3) for _ in range(3))
    on_plane = [a + s * (b - a) + t * (c - a) for s, t in ((2, -1), (-1, 2), (3, -2), (1, 1))]
    ids = np.array([a, b, c, *on_plane, a + np.array([1, 0, 0])], dtype=np.int64)
    assert np.abs(ids).max() < 2**30
    grid = sorted_grid(ids)
    index = {tuple(r): n for n, r in enumerate(grid.ids.tolist())}
    scores = np.zeros(grid.point_count)
    for n, p in enumerate(on_plane):  # the on-plane points rank highest, the off-plane point last
        scores[index[tuple(p.tolist())]] = 10 + n
    chosen = np.array([index[tuple(p.tolist())] for p in (a, b, c)])
    result, added = ensure_tetrahedron(grid, rank(scores), chosen)
    assert added == 1
    assert set(result.tolist()) - set(chosen.tolist()) == {index[tuple((a + np.array([1, 0, 0])).tolist())]}


def test_huge_span_grid_uses_exact_big_integers():
    big = 2**30
    ids = [[-big, -big, -big], [big, -big, -big], [-big, big, -big], [big, big, -big], [0, 0, big - 1], [7, 3, big]]
    grid = sorted_grid(ids)
    scores = np.zeros(grid.point_count)
    indices, added = ensure_tetrahedron(grid, rank(scores), np.array([0, 1, 2, 3]))  # the z = -2^30 plane
    assert added == 1 and indices.tolist() == [0, 1, 2, 3, 4]
