"""The in-use rule's behaviour (Documentation~/in-use.md) on small designed scenes, its errors and its extremes.

Scenes are boxes for the exact analytic raycaster, laid out in cells: every face sits a quarter or an eighth of a
cell off the lattice, so no decision is near its threshold at any scale."""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest

from lpnn.core import in_use
from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AxisBox
from lpnn.core.grid import EvaluationGrid
from lpnn.core.in_use import (
    RULES,
    InUseError,
    InUseParameters,
    in_band,
    in_use_mask,
    profile_intervals,
    reachable,
)
from lpnn.errors import InvalidInputError


def lattice(x: range, y: range, z: range, offset=(0, 0, 0)) -> np.ndarray:
    ids = np.array([(i + offset[0], j + offset[1], k + offset[2]) for k in z for j in y for i in x], dtype=np.int32)
    return ids.reshape(-1, 3)


def grid_outside(boxes: list[AxisBox], h: float, x: range, y: range, z: range, offset=(0, 0, 0)) -> EvaluationGrid:
    """The lattice points not inside any box (as the validity step would leave them)."""
    ids = lattice(x, y, z, offset)
    p = ids.astype(np.float64) * h
    inside = np.zeros(ids.shape[0], dtype=bool)
    for b in boxes:
        inside |= np.all((p >= b.min) & (p <= b.max), axis=1)
    return EvaluationGrid(h, ids[~inside])


def cells(h: float, lo, hi, origin=(0.0, 0.0, 0.0)) -> AxisBox:
    """A box given in cells, scaled by h and moved to origin (metres)."""
    o = np.asarray(origin, dtype=np.float64)
    return AxisBox(o + h * np.asarray(lo, dtype=np.float64), o + h * np.asarray(hi, dtype=np.float64))


def at(grid: EvaluationGrid, i: int, j: int, k: int = 0, offset=(0, 0, 0)) -> int:
    index = int(grid.index_of(np.array([[i + offset[0], j + offset[1], k + offset[2]]]))[0])
    assert index >= 0, (i, j, k)
    return index


def parameters(h: float = 1.0, band=2.5, slope=45.0, step=0.5) -> InUseParameters:
    """Parameters in cells (band and step scale with h; the slope does not)."""
    return InUseParameters(band_height=band * h, slope_limit_degrees=slope, step_height=step * h)


def floor_and(h: float, *others: tuple, origin=(0.0, 0.0, 0.0)) -> AnalyticBoxRaycaster:
    """A floor whose top is 0.375 cells below the j = 0 points (x -1..21, z -1..3 cells) and other boxes in cells."""
    floor = cells(h, (-1.125, -2.0, -1.125), (21.125, -0.375, 3.125), origin)
    return AnalyticBoxRaycaster(None, (floor,) + tuple(cells(h, lo, hi, origin) for lo, hi in others))


class CountingRaycaster:
    def __init__(self, inner) -> None:
        self.inner, self.rays, self.calls = inner, 0, 0

    def cast(self, origins, directions, max_distance):
        self.rays += origins.shape[0]
        self.calls += 1
        return self.inner.cast(origins, directions, max_distance)


# -------------------------------------------------------------------------------------------- parameters

def test_parameters_defaults_are_the_specs() -> None:
    p = InUseParameters()
    assert (p.band_height, p.slope_limit_degrees, p.step_height) == (3.0, 45.0, 0.5)
    assert RULES == ("reachable", "band", "all")
    assert p.walkable_cosine == pytest.approx(math.sqrt(0.5))
    assert p.rise_limit(0.5) == pytest.approx(0.5 + 0.25 * 1.0)


@pytest.mark.parametrize("field, value, fragment", [
    ("band_height", 0.0, "(0, 10000] metres"), ("band_height", -1.0, "(0, 10000]"), ("band_height", 1e4 + 1, "10000"),
    ("band_height", math.nan, "nan"), ("band_height", math.inf, "inf"), ("band_height", "high", "'high' is not a number"),
    ("slope_limit_degrees", 90.0, "[0, 90) degrees"), ("slope_limit_degrees", -0.5, "[0, 90)"),
    ("slope_limit_degrees", math.nan, "nan"), ("step_height", -0.01, "[0, 10000] metres"),
    ("step_height", math.inf, "inf"), ("step_height", 1e4 * 1.0001, "[0, 10000]"),
])
def test_parameters_out_of_range_name_the_value_and_the_range(field: str, value, fragment: str) -> None:
    with pytest.raises(InUseError, match=field) as error:
        InUseParameters(**{field: value})
    assert fragment in str(error.value)
    assert isinstance(error.value, InvalidInputError) and isinstance(error.value, ValueError)


def test_parameters_at_the_ends_of_their_ranges_are_accepted() -> None:
    InUseParameters(band_height=1e4, slope_limit_degrees=0.0, step_height=0.0)
    InUseParameters(band_height=1e-9, slope_limit_degrees=89.999, step_height=1e4)


@pytest.mark.parametrize("h, m", [(1e-4, 1), (0.25, 1), (0.2501, 2), (0.5, 2), (1.0, 4), (16.0, 64), (1e4, 64)])
def test_profile_intervals_stay_in_one_to_64(h: float, m: int) -> None:
    assert profile_intervals(h) == m


# ---------------------------------------------------------------------------------------------- the band

def test_band_is_the_points_within_h_above_a_floor_and_their_floor_height() -> None:
    h = 1.0
    raycaster = floor_and(h)
    grid = grid_outside([], h, range(3), range(5), range(1))
    band, floor = in_band(grid, raycaster, parameters(h, band=2.5))
    heights = grid.ids[:, 1] + 0.375  # above the floor, in cells
    assert np.array_equal(band, heights <= 2.5)
    assert np.allclose(floor[band], -0.375) and np.all(np.isnan(floor[~band]))


def test_a_steep_surface_is_not_a_floor() -> None:
    """Floor rays on tilted planes: 40 degrees is walkable under a 45-degree limit, 50 degrees is not; at 35 degrees
    neither is (a box raycaster has only flat floors, so this uses planes)."""
    grid = grid_outside([], 1.0, range(-3, 4), range(1), range(1))
    for tilt, limit, walkable in [(40.0, 45.0, True), (50.0, 45.0, False), (40.0, 35.0, False), (0.0, 0.0, True)]:
        band, _ = in_band(grid, TiltedPlane(tilt, -4.5), parameters(1.0, band=10.0, slope=limit))
        assert band.all() == walkable and band.any() == walkable, (tilt, limit)


class TiltedPlane:
    """The plane y = tan(tilt) * x + height (either facing), for floor and segment rays."""

    def __init__(self, tilt_degrees: float, height: float) -> None:
        t = math.radians(tilt_degrees)
        self.normal = np.array([-math.sin(t), math.cos(t), 0.0])
        self.offset = height * math.cos(t)  # normal . p = offset on the plane

    def cast(self, origins, directions, max_distance):
        toward = directions @ self.normal
        side = origins @ self.normal - self.offset
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(toward != 0.0, -side / toward, np.inf)
        hit = (t >= 0.0) & (t <= max_distance)
        return np.where(hit, t, np.inf), np.where(hit[:, None], self.normal[None, :], 0.0)


def test_a_walkable_ramp_is_climbed_only_within_the_slope_part_of_the_allowance() -> None:
    """With no step allowance the rise over one profile interval is (h/M) tan(tilt): a 40-degree ramp is climbed
    under a 45-degree limit; with a 39-degree limit the surface is not even walkable."""
    grid = grid_outside([], 1.0, range(0, 6), range(0, 8), range(1))
    ramp = TiltedPlane(40.0, -0.5)
    seed = np.array([[0.0, 0.0, 0.0]])
    reached = reachable(grid, ramp, parameters(1.0, band=2.2, slope=45.0, step=0.0), seed)
    top = at(grid, 5, 4)  # 5 tan 40 - 0.5 = 3.70 below it: 0.30 above the ramp
    assert reached[top]
    with pytest.raises(InUseError, match="no point in use|attaches"):
        reachable(grid, ramp, parameters(1.0, band=2.2, slope=39.0, step=0.0), seed)


# ---------------------------------------------------------------------------------------------- reachable

def test_a_wall_top_two_metres_up_is_in_band_but_not_reachable() -> None:
    h = 0.5
    block = ((4.25, -0.375, -1.125), (6.75, 3.875, 3.125))  # 4.25 cells = 2.125 m above the floor, cells 5 and 6
    raycaster = floor_and(h, block)
    grid = grid_outside(list(raycaster.obstacles), h, range(0, 12), range(0, 7), range(0, 3))
    p = parameters(h, band=6.0, step=1.0)
    band, _ = in_band(grid, raycaster, p)
    reached = reachable(grid, raycaster, p, np.array([[0.0, 0.25, 0.5]]))
    on_top = at(grid, 5, 4, 1)
    assert band[on_top] and not reached[on_top]
    beside = at(grid, 3, 4, 1)
    assert band[beside] and reached[beside]
    assert not reached[at(grid, 9, 0, 1)]  # behind the block, the corridor is closed
    # A seed on the block reaches its top and, dropping off, the floor on both sides.
    from_top = reachable(grid, raycaster, p, np.array([[2.75, 2.125, 0.5]]))
    assert from_top[on_top] and from_top[at(grid, 9, 0, 1)] and from_top[at(grid, 0, 0, 1)]


def test_stairs_are_climbed_and_a_wall_of_their_height_is_not() -> None:
    h = 0.5
    # Eight risers of 0.3 cells (0.15 m) every half cell, then a landing 2.4 cells up.
    stairs = [((4.25 + 0.5 * k, -0.375, -1.125), (4.75 + 0.5 * k, -0.375 + 0.3 * (k + 1), 3.125)) for k in range(7)]
    stairs.append(((7.75, -0.375, -1.125), (12.25, -0.375 + 2.4, 3.125)))
    raycaster = floor_and(h, *stairs)
    grid = grid_outside(list(raycaster.obstacles), h, range(0, 14), range(0, 7), range(0, 2))
    p = parameters(h, band=5.0, slope=45.0, step=0.5)
    seed = np.array([[0.5, 0.25, 0.0]])
    landing = at(grid, 10, 3, 0)
    assert reachable(grid, raycaster, p, seed)[landing]
    wall = floor_and(h, ((4.25, -0.375, -1.125), (12.25, 2.025, 3.125)))
    grid = grid_outside(list(wall.obstacles), h, range(0, 14), range(0, 7), range(0, 2))
    reached = reachable(grid, wall, p, seed)
    assert in_band(grid, wall, p)[0][at(grid, 10, 3, 0)] and not reached[at(grid, 10, 3, 0)]


def test_a_thin_wall_between_rooms_blocks_and_the_rooms_join_without_it() -> None:
    """The wall is thinner than a profile interval and between its samples: only the segment test sees it."""
    h = 1.0
    wall = ((4.6, -0.375, -1.125), (4.7, 10.0, 3.125))
    for walls, joined in [((wall,), False), ((), True)]:
        raycaster = floor_and(h, *walls)
        grid = grid_outside(list(raycaster.obstacles), h, range(0, 10), range(0, 2), range(0, 3))
        reached = reachable(grid, raycaster, parameters(h), np.array([[1.0, 0.25, 1.0]]))
        assert reached[at(grid, 2, 0, 1)]
        assert reached[at(grid, 7, 1, 2)] == joined


def test_moves_are_directed_a_ledge_is_left_but_not_climbed() -> None:
    h = 1.0
    ledge = ((-1.125, -0.375, -1.125), (3.5, 1.625, 3.125))  # 2 cells up, x up to 3.5
    raycaster = floor_and(h, ledge)
    grid = grid_outside(list(raycaster.obstacles), h, range(0, 8), range(0, 5), range(0, 2))
    p = parameters(h, band=3.0, step=0.5)
    on_ledge, below = at(grid, 1, 2, 0), at(grid, 6, 0, 0)
    from_ledge = reachable(grid, raycaster, p, np.array([[1.0, 2.0, 0.0]]))
    assert from_ledge[on_ledge] and from_ledge[below]
    from_floor = reachable(grid, raycaster, p, np.array([[6.0, 0.25, 0.0]]))
    assert from_floor[below] and not from_floor[on_ledge]


def test_a_slab_between_two_layers_blocks_the_vertical_move() -> None:
    h = 1.0
    slab = ((-1.125, 0.375, -1.125), (2.5, 0.625, 3.125))  # between the layers j = 0 and 1, x up to 2.5 cells
    grid = grid_outside([], h, range(0, 6), range(0, 3), range(0, 2))
    seed = np.array([[0.0, 0.125, 0.0]])
    for boxes, up in [((slab,), False), ((), True)]:
        raycaster = floor_and(h, *boxes)
        band, _ = in_band(grid, raycaster, parameters(h, band=2.5))
        reached = reachable(grid, raycaster, parameters(h, band=2.5), seed)
        assert band[at(grid, 0, 1, 0)] and reached[at(grid, 0, 0, 0)]
        assert reached[at(grid, 0, 1, 0)] == up


def test_a_pit_deeper_than_the_band_and_a_narrow_gap_both_block() -> None:
    h = 1.0
    left = ((-1.125, -2.0, -1.125), (4.375, -0.375, 3.125))  # the gap: x 4.375..4.625 cells, under the sample 4.5
    right = ((4.625, -2.0, -1.125), (21.125, -0.375, 3.125))
    bottom = ((-1.125, -9.0, -1.125), (21.125, -8.0, 3.125))  # 7.6 cells below the floor
    grid = grid_outside([], h, range(0, 10), range(0, 2), range(0, 2))
    for gap_bottom in [(bottom,), ()]:
        raycaster = AnalyticBoxRaycaster(None, tuple(cells(h, lo, hi) for lo, hi in (left, right) + gap_bottom))
        for band in (2.5, 9.0):  # the second band reaches the bottom: the rise out of the gap blocks instead
            reached = reachable(grid, raycaster, parameters(h, band=band, step=0.5), np.array([[1.0, 0.25, 0.0]]))
            assert reached[at(grid, 4, 0, 0)] and not reached[at(grid, 5, 0, 0)], (gap_bottom, band)


def test_a_seed_attaches_within_two_cells_and_not_through_a_wall() -> None:
    h = 1.0
    wall = ((4.6, -0.375, -1.125), (4.7, 10.0, 3.125))
    raycaster = floor_and(h, wall)
    grid = grid_outside(list(raycaster.obstacles), h, range(0, 10), range(0, 2), range(0, 1))
    band, _ = in_band(grid, raycaster, parameters(h))
    starts = in_use._seed_starts(grid, raycaster, band, np.array([[4.5, 0.25, 0.0]]), None)
    xs = sorted({int(grid.ids[s, 0]) for s in starts})
    assert xs == [3, 4]  # |q - s| <= 2: x 3..6, but 5 and 6 lie behind the wall
    with pytest.raises(InUseError, match="none of the 1 seeds attaches") as error:
        reachable(grid, raycaster, parameters(h), np.array([[4.5, 6.0, 0.0]]))
    assert "'band'" in str(error.value) and "2 cells" in str(error.value)


# ------------------------------------------------------------------------------------ rules, errors, progress

def test_all_needs_no_rays_and_band_needs_only_the_floor_rays() -> None:
    h = 1.0
    grid = grid_outside([], h, range(4), range(4), range(2))
    counting = CountingRaycaster(floor_and(h))
    assert in_use_mask("all", grid, counting, parameters(h)).all() and counting.rays == 0
    mask = in_use_mask("band", grid, counting, parameters(h, band=1.0))
    assert counting.rays == grid.point_count and counting.calls == 1
    assert np.array_equal(mask, grid.ids[:, 1] == 0)


def test_rule_errors_name_the_rule_the_values_and_the_fix() -> None:
    h = 0.5
    grid = grid_outside([], h, range(4), range(1, 3), range(2))
    raycaster = floor_and(h)
    with pytest.raises(InUseError, match="'walk' is not one of reachable, band, all"):
        in_use_mask("walk", grid, raycaster, InUseParameters())
    with pytest.raises(InUseError) as error:
        in_use_mask("band", grid, raycaster, InUseParameters(band_height=0.05))
    message = str(error.value)
    for part in ("'band'", "band height 0.05 m", "cell size 0.5 m", "16 points", "'all'"):
        assert part in message
    with pytest.raises(InUseError, match="'reachable' leaves no point"):
        in_use_mask("reachable", grid, raycaster, InUseParameters(band_height=0.05), np.zeros((1, 3)))
    with pytest.raises(InUseError, match="needs seeds .none given.*'band'"):
        in_use_mask("reachable", grid, raycaster, InUseParameters())
    with pytest.raises(InUseError, match="at least one seed .0 given"):
        reachable(grid, raycaster, InUseParameters(), np.zeros((0, 3)))
    with pytest.raises(InUseError, match=r"seed 1 is \(nan, 0.0, 0.0\), not finite"):
        reachable(grid, raycaster, InUseParameters(), np.array([[0.0, 0.0, 0.0], [math.nan, 0.0, 0.0]]))
    with pytest.raises(InUseError, match="shape"):
        reachable(grid, raycaster, InUseParameters(), np.zeros((2, 2)))
    with pytest.raises(InUseError, match="band needs"):
        reachable(grid, raycaster, InUseParameters(), np.zeros((1, 3)), band=(np.ones(3, bool), np.zeros(3)))


def test_progress_reports_every_stage_to_its_end() -> None:
    h = 1.0
    raycaster = floor_and(h)
    grid = grid_outside([], h, range(6), range(3), range(3))
    reports: list[tuple[str, int, int]] = []
    in_use_mask("reachable", grid, raycaster, parameters(h), np.array([[2.0, 0.25, 1.0]]),
                progress=lambda stage, done, total: reports.append((stage, done, total)))
    last = {stage: (done, total) for stage, done, total in reports}
    assert set(last) == {f"in use: {s}" for s in ("floor rays", "seed attachment rays", "vertical move rays",
                                                  "floor profile rays", "horizontal move rays")}
    assert all(done == total > 0 for done, total in last.values())


# ------------------------------------------------------------------------------------------------ extremes

SCALED_WALL = ((4.6, -0.375, -1.125), (4.7, 10.0, 3.125))
SCALED_STEP = ((1.25, -0.375, -1.125), (2.75, -0.075, 3.125))  # 0.3 cells


@pytest.mark.parametrize("h", [1e-4, 0.5, 1e4])
def test_the_rule_scales_with_the_cell(h: float) -> None:
    """One layer of points 0.375 cells above a floor, a 0.3-cell step and a thin wall: the same masks from 1e-4 m
    to 1e4 m cells (M = 1, 2 and 64 profile intervals), parameters in cells (the band at most 1e4 m: 1 cell)."""
    raycaster = floor_and(h, SCALED_STEP, SCALED_WALL)
    grid = grid_outside(list(raycaster.obstacles), h, range(0, 9), range(0, 1), range(0, 2))
    p = parameters(h, band=1.0, step=0.5)
    band, floor = in_band(grid, raycaster, p)
    on_step = (grid.ids[:, 0] >= 2) & (grid.ids[:, 0] <= 2)
    assert band.all()
    assert np.allclose(floor, np.where(on_step, -0.075, -0.375) * h, rtol=1e-5, atol=0.0)
    reached = reachable(grid, raycaster, p, np.array([[0.0, 0.125 * h, 0.5 * h]]))
    assert np.array_equal(reached, grid.ids[:, 0] <= 4)


def test_far_from_the_origin_gives_the_same_masks() -> None:
    """1e5 m away (float32 positions 0.0078 m apart there): a 0.5 m cell's lattice is still exact."""
    h = 0.5
    shift = (200_000, 2, -200_000)  # ids: 1e5 m, 1 m, -1e5 m
    origin = tuple(float(s) * h for s in shift)
    near = floor_and(h, SCALED_STEP, SCALED_WALL)
    far = floor_and(h, SCALED_STEP, SCALED_WALL, origin=origin)
    grids = [grid_outside(list(r.obstacles), h, range(0, 9), range(0, 2), range(0, 2), offset=o)
             for r, o in ((near, (0, 0, 0)), (far, shift))]
    p = parameters(h, band=2.0, step=0.5)
    seeds = np.array([[0.0, 0.0625, 0.25]])
    masks = [reachable(g, r, p, seeds + np.asarray(o)) for g, r, o in ((grids[0], near, (0.0, 0.0, 0.0)),
                                                                        (grids[1], far, origin))]
    assert grids[0].point_count == grids[1].point_count
    assert np.array_equal(masks[0], masks[1]) and 0 < masks[0].sum() < grids[0].point_count


def test_one_point() -> None:
    h = 0.5
    grid = EvaluationGrid(h, np.array([[0, 0, 0]], dtype=np.int32))
    raycaster = floor_and(h)
    assert in_use_mask("band", grid, raycaster, InUseParameters()).tolist() == [True]
    assert in_use_mask("reachable", grid, raycaster, InUseParameters(), np.array([0.0, 0.1, 0.0])).tolist() == [True]
    with pytest.raises(InUseError, match="none of the 1 seeds"):
        in_use_mask("reachable", grid, raycaster, InUseParameters(), np.array([[5.0, 0.0, 0.0]]))


def test_seeds_beyond_the_lattice_attach_to_nothing() -> None:
    h = 1e-4
    grid = grid_outside([], h, range(3), range(1), range(1))
    with pytest.raises(InUseError, match="none of the 2 seeds"):
        reachable(grid, floor_and(h), parameters(h), np.array([[1e30, 0.0, 0.0], [-1e300, 0.0, 0.0]]))


def _plain_walk(point_count: int, starts, sources, targets) -> np.ndarray:
    following = [[] for _ in range(point_count)]
    for s, t in zip(sources.tolist(), targets.tolist()):
        following[s].append(t)
    reached = np.zeros(point_count, dtype=bool)
    queue = deque(starts.tolist())
    reached[starts] = True
    while queue:
        for t in following[queue.popleft()]:
            if not reached[t]:
                reached[t] = True
                queue.append(t)
    return reached


@pytest.mark.parametrize("seed", range(5))
def test_the_walk_reaches_what_a_plain_breadth_first_search_reaches(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = 300
    sources, targets = rng.integers(0, n, 400), rng.integers(0, n, 400)
    starts = np.unique(rng.integers(0, n, 3))
    assert np.array_equal(in_use._walk(n, starts, sources, targets), _plain_walk(n, starts, sources, targets))
