"""lpnn.core.grid against Documentation~/grid.md: hand-counted cases, brute-force SAT, limits, lookup."""

from __future__ import annotations

import itertools
import re
import time

import numpy as np
import pytest

from lpnn.core.grid import EvaluationGrid, GridError, round_up_significant
from lpnn.core.grid_box import Box
from lpnn.core.grid_builder import build_grid, count_points, fitting_cell_size

aabb = Box.axis_aligned


def grid_ids(boxes, h, **kwargs) -> set[tuple[int, int, int]]:
    return {tuple(int(v) for v in row) for row in build_grid(boxes, h, **kwargs).ids}


def assert_grid_order(ids: np.ndarray) -> None:
    order = np.lexsort((ids[:, 0], ids[:, 1], ids[:, 2]))
    assert np.array_equal(order, np.arange(ids.shape[0]))
    assert len({tuple(r) for r in ids.tolist()}) == ids.shape[0]


# ------------------------------------------------------------------------------- hand-counted sets

@pytest.mark.parametrize(
    "box, h, expected",
    [
        # faces exactly on cell faces (+-0.25 around lattice points 0, 0.5, 1): gains the next layer
        (aabb([0.25] * 3, [0.75] * 3), 0.5, 27),
        (aabb([0, 0, 0], [0, 0, 0]), 0.5, 1),  # a point on a lattice point
        (aabb([0.25, 0, 0], [0.25, 0, 0]), 0.5, 2),  # a point on a cell face: two cells touch it
        (aabb([0.25] * 3, [0.25] * 3), 0.5, 8),  # a point on a cell corner: eight cells
        (aabb([0, 0, 0], [1, 1, 0]), 0.5, 9),  # flat box z = 0 (3 x 3 x 1)
        (aabb([0, 0, 0.25], [1, 1, 0.25]), 0.5, 18),  # flat box on a half-cell plane: two layers
        (aabb([0, 0, 0], [2, 0, 0]), 0.5, 5),  # a line
        (aabb([0.1] * 3, [0.2] * 3), 0.5, 1),  # smaller than a cell
    ],
)
def test_hand_counted_sets(box, h, expected):
    assert count_points([box], h) == expected
    grid = build_grid([box], h)
    assert grid.point_count == expected
    assert_grid_order(grid.ids)


def test_axis_aligned_box_matches_interval_formula():
    # For an axis-aligned box the covered ids per axis are i with |h i - [lo, hi]| <= h/2 (a 1-D interval test).
    lo, hi, h = np.array([-1.3, 0.2, 2.05]), np.array([0.4, 1.9, 2.6]), 0.3
    per_axis = [range(int(np.ceil(l / h - 0.5)), int(np.floor(u / h + 0.5)) + 1) for l, u in zip(lo, hi)]
    expected = [(i, j, k) for k in per_axis[2] for j in per_axis[1] for i in per_axis[0]]
    grid = build_grid([aabb(lo, hi)], h)
    assert [tuple(r) for r in grid.ids.tolist()] == expected  # same set, and grid order (x fastest)
    assert grid.positions.dtype == np.float32
    assert np.array_equal(grid.positions, (np.array(expected, dtype=np.float64) * h).astype(np.float32))


def test_union_merges_overlapping_and_touching_boxes():
    boxes = [aabb([0, 0, 0], [2, 1, 1]), aabb([1, 0.5, 0], [3, 2, 1]), aabb([3.6, 0, 0], [4, 1, 1])]
    union = set().union(*(grid_ids([b], 0.5) for b in boxes))
    grid = build_grid(boxes, 0.5)
    assert {tuple(r) for r in grid.ids.tolist()} == union
    assert grid.point_count == len(union) == count_points(boxes, 0.5)
    assert_grid_order(grid.ids)


# --------------------------------------------------------------------- rotated boxes vs brute force

def random_parallelepiped(rng: np.random.Generator) -> Box:
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    shear = np.eye(3) + np.triu(rng.uniform(-0.4, 0.4, (3, 3)), 1)
    half_edges = (rotation @ shear @ np.diag(rng.uniform(0.0, 1.5, 3))).T
    if rng.random() < 0.3:  # flat boxes too
        half_edges[rng.integers(3)] = 0.0
    return Box(center=rng.uniform(-3, 3, 3), half_edges=half_edges)


def sat_margin(box: Box, points: np.ndarray, h: float) -> np.ndarray:
    """Brute force: min over the 15 SAT axes of (R(a) - |a.(p - c)|) / |a|, per point (>0 inside)."""
    u, v, w = box.half_edges
    axes = list(np.eye(3)) + [np.cross(v, w), np.cross(w, u), np.cross(u, v)]
    axes += [np.cross(e, b) for e in np.eye(3) for b in (u, v, w)]
    margin = np.full(points.shape[0], np.inf)
    for a in axes:
        length = np.linalg.norm(a)
        if length < 1e-9:
            continue
        a = a / length
        radius = abs(a @ u) + abs(a @ v) + abs(a @ w) + h / 2 * np.abs(a).sum()
        margin = np.minimum(margin, radius - np.abs((points - box.center) @ a))
    return margin


@pytest.mark.parametrize("seed", range(6))
def test_rotated_and_sheared_boxes_match_brute_force_sat(seed):
    rng = np.random.default_rng(seed)
    h = float(rng.choice([0.25, 0.5, 0.7]))
    box = random_parallelepiped(rng)
    ids = grid_ids([box], h)
    reach = np.abs(box.half_edges).sum(axis=0) + h
    lo = np.floor((box.center - reach) / h).astype(int) - 1
    hi = np.ceil((box.center + reach) / h).astype(int) + 1
    block = np.array(list(itertools.product(*(range(a, b + 1) for a, b in zip(lo, hi)))))
    margin = sat_margin(box, block * h, h)
    tolerance = 1e-7 * h
    inside = {tuple(r) for r in block[margin > tolerance].tolist()}
    outside = {tuple(r) for r in block[margin < -tolerance].tolist()}
    assert inside, "the test box should cover some points"
    assert inside <= ids
    assert not (outside & ids)
    assert ids <= {tuple(r) for r in block.tolist()}


# ------------------------------------------------------------------------------ extremes of scale

def test_far_from_origin_is_the_translated_grid():
    near = build_grid([aabb([0.1, -0.3, 0.2], [2.3, 1.1, 0.9])], 0.5)
    far = build_grid([aabb([1e6 + 0.1, 1e6 - 0.3, 1e6 + 0.2], [1e6 + 2.3, 1e6 + 1.1, 1e6 + 0.9])], 0.5)
    assert np.array_equal(far.ids.astype(np.int64), near.ids.astype(np.int64) + 2_000_000)
    assert np.array_equal(far.positions, (far.ids.astype(np.float64) * 0.5).astype(np.float32))
    neighbours = far.neighbour(0, 1)
    assert np.array_equal(neighbours, near.neighbour(0, 1))


def test_tiny_and_huge_cell_sizes():
    assert count_points([aabb([0, 0, 0], [1e-5, 1e-5, 1e-5])], 1e-6) == 11**3
    assert count_points([aabb([0, 0, 0], [1, 1, 1])], 1e6) == 1
    # every SAT axis is degenerate at this cell size; the box's own lattice range still bounds the row
    far = build_grid([aabb([1e7, 0, 0], [1e7 + 1, 1, 1])], 1e6)
    assert far.ids.tolist() == [[10, 0, 0]]


def test_id_bound_is_guarded():
    with pytest.raises(GridError, match=r"cell size 1e-09 .*2\^23") as error:
        build_grid([aabb([0, 0, 0], [10, 10, 10])], 1e-9)
    assert "1.2e-06" in str(error.value)  # 10.0000000005 / 2^23 rounded up to 3 digits
    edge = [2.0**23 + 0.4, 0, 0]  # reaches 2^23 + 0.9: lattice range ends exactly at 2^23
    assert build_grid([aabb(edge, edge)], 1.0).ids.tolist() == [[2**23, 0, 0]]
    beyond = [-(2.0**23) - 0.6, 0, 0]  # reaches -2^23 - 1.1: one cell too far
    with pytest.raises(GridError, match=r"bound x = -8\.38861e\+06"):
        build_grid([aabb(beyond, beyond)], 1.0)


def test_far_from_the_origin_neighbouring_points_keep_distinct_float32_positions():
    """At the build bound every point has its own position; one cell size smaller, the grid is refused
    (there, float32 positions of neighbouring points would coincide)."""
    h = 0.3
    near_bound = 2.0**23 * h - 3.0
    grid = build_grid([aabb([near_bound, 0, 0], [near_bound + 2.0, 0.0, 0.0])], h)
    x = grid.positions[:, 0]
    assert x.size >= 6 and np.unique(x).size == x.size and np.all(np.diff(x) > 0)
    with pytest.raises(GridError, match=r"2\^23 .*float32"):
        build_grid([aabb([4 * near_bound, 0, 0], [4 * near_bound + 2.0, 0.0, 0.0])], h)


@pytest.mark.parametrize("h", [0.0, -0.5, float("nan"), float("inf"), "abc"])
def test_invalid_cell_size(h):
    with pytest.raises(GridError, match="cell size"):
        build_grid([aabb([0, 0, 0], [1, 1, 1])], h)


def test_invalid_boxes():
    with pytest.raises(GridError, match="add at least one box"):
        build_grid([], 0.5)
    with pytest.raises(GridError, match="not finite"):
        Box(center=[0, 0, float("nan")], half_edges=np.eye(3))
    with pytest.raises(GridError, match="not finite"):
        Box(center=[0, 0, 0], half_edges=[[1, 0, 0], [0, float("inf"), 0], [0, 0, 1]])
    with pytest.raises(GridError, match="exceeds max corner"):
        aabb([0, 1, 0], [1, 0, 1])


# ------------------------------------------------------------------------------------------ limits

def test_point_limit_error_states_count_limit_cell_size_and_a_fitting_size():
    boxes = [aabb([0, 0, 0], [10, 10, 10])]
    count = count_points(boxes, 0.25)
    assert count == 41**3  # faces on lattice points, no extra layer: 41 per axis
    with pytest.raises(GridError) as error:
        build_grid(boxes, 0.25, point_limit=10_000)
    message = str(error.value)
    suggestion = fitting_cell_size(boxes, 0.25, 10_000)
    assert f"{count:,}" in message and "10,000" in message and "0.25" in message
    assert f"{suggestion:.3g}" in message
    assert re.fullmatch(r"\d\.\d\d", f"{suggestion / 10 ** np.floor(np.log10(suggestion)):.2f}")
    assert count_points(boxes, suggestion) <= 10_000  # verified by recounting
    smaller = suggestion - 10 ** (np.floor(np.log10(suggestion)) - 2)  # the next 3-digit value down
    assert count_points(boxes, smaller) > 10_000
    assert build_grid(boxes, suggestion, point_limit=10_000).point_count <= 10_000


def test_row_bound_rejects_runaway_inputs_quickly():
    start = time.perf_counter()
    with pytest.raises(GridError, match=r"candidate rows.*cell size of at least") as error:
        count_points([aabb([0, 0, 0], [100, 100, 100])], 0.001, point_limit=1_000)
    assert time.perf_counter() - start < 5.0
    suggestion = float(re.search(r"at least ([0-9.e+-]+)", str(error.value)).group(1))
    assert count_points([aabb([0, 0, 0], [100, 100, 100])], suggestion, point_limit=1_000) <= 1_000


@pytest.mark.parametrize("value, expected", [
    (0.19, 0.19), (0.19000000000000003, 0.191), (0.19999999999999998, 0.2), (1.231, 1.24), (0.5, 0.5),
    (999.5, 1000.0), (9.3132e-09, 9.32e-09),
])
def test_round_up_significant(value, expected):
    assert round_up_significant(value) == expected
    assert round_up_significant(value) >= value


def test_point_limit_must_be_positive():
    with pytest.raises(GridError, match="point limit"):
        build_grid([aabb([0, 0, 0], [1, 1, 1])], 0.5, point_limit=0)


def test_estimate_bytes_formula():
    # 12 ids + 12 positions + 108 SH + 4*19 features + 4 score + 1 label + 32 id lookup + 168 lighting cache
    assert EvaluationGrid.estimate_bytes(1000, 19) == 413_000
    assert EvaluationGrid.estimate_bytes(1000, 30) == 457_000
    assert EvaluationGrid.estimate_bytes(0, 19) == 0


def test_a_million_points_build_in_seconds():
    start = time.perf_counter()
    grid = build_grid([aabb([0, 0, 0], [49.5, 49.5, 49.5])], 0.5)
    assert time.perf_counter() - start < 5.0
    assert grid.point_count == 1_000_000
    assert grid.ids[:2].tolist() == [[0, 0, 0], [1, 0, 0]] and grid.ids[-1].tolist() == [99, 99, 99]
    plus_z = grid.neighbour(2, 4)
    assert plus_z[0] == 40_000 and plus_z[-1] == -1 and np.count_nonzero(plus_z >= 0) == 960_000


# ------------------------------------------------------------------------------------------ lookup

def sorted_grid(ids) -> EvaluationGrid:
    ids = np.asarray(ids, dtype=np.int64)
    return EvaluationGrid(cell_size=1.0, ids=ids[np.lexsort((ids[:, 0], ids[:, 1], ids[:, 2]))])


def test_index_of_and_neighbours_match_a_dictionary():
    rng = np.random.default_rng(3)
    grid = sorted_grid(np.unique(rng.integers(-6, 7, size=(400, 3)), axis=0))
    table = {tuple(r): n for n, r in enumerate(grid.ids.tolist())}
    queries = rng.integers(-9, 10, size=(1000, 3))
    expected = [table.get(tuple(q), -1) for q in queries.tolist()]
    assert grid.index_of(queries).tolist() == expected
    for axis, offset in itertools.product(range(3), (1, -1, 2, -4)):
        moved = grid.ids.astype(np.int64)
        moved[:, axis] += offset
        assert grid.neighbour(axis, offset).tolist() == [table.get(tuple(q), -1) for q in moved.tolist()]


def test_index_of_handles_the_whole_id_range():
    big = 2**30
    grid = sorted_grid([[-big, -big, -big], [big, -big, -big], [0, 0, 0], [big - 1, big, big], [big, big, big]])
    assert grid.index_of(grid.ids).tolist() == [0, 1, 2, 3, 4]
    queries = [[big, big, -big], [2**31 + 5, 0, 0], [-(2**40), 0, 0], [big - 1, big, big - 1]]
    assert grid.index_of(queries).tolist() == [-1, -1, -1, -1]
    assert grid.neighbour(0, 1).tolist() == [-1, -1, -1, 4, -1]
    assert grid.neighbour(0, -1).tolist() == [-1, -1, -1, -1, 3]


def test_subset_keeps_order_and_lookup():
    grid = build_grid([aabb([0, 0, 0], [1, 1, 1])], 0.5)
    keep = np.arange(grid.point_count) % 3 != 0
    part = grid.subset(keep)
    assert np.array_equal(part.ids, grid.ids[keep])
    assert part.index_of(grid.ids[keep]).tolist() == list(range(part.point_count))
    assert part.index_of(grid.ids[~keep]).tolist() == [-1] * int((~keep).sum())
    with pytest.raises(GridError, match="boolean mask"):
        grid.subset(np.ones(3, dtype=bool))
    with pytest.raises(GridError, match="no evaluation point is left after filtering all 27 points"):
        grid.subset(np.zeros(27, dtype=bool))


def test_grid_rejects_ids_out_of_order():
    with pytest.raises(GridError, match="grid order"):
        EvaluationGrid(cell_size=1.0, ids=np.array([[1, 0, 0], [0, 0, 0]]))
    with pytest.raises(GridError, match="grid order"):
        EvaluationGrid(cell_size=1.0, ids=np.array([[0, 0, 0], [0, 0, 0]]))
