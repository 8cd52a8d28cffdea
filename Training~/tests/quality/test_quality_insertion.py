"""Error-driven insertion (quality/placement/insertion.py): the non-learned lighting-driven yardstick."""

from __future__ import annotations

import numpy as np

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.baselines import heuristic_ranking, random_ranking, uniform_selector
import pytest

from lpnn.core import sh as shmath
from lpnn.quality.placement import insertion
from lpnn.quality.placement.insertion import (EXACT, EXTREME_DIRECTIONS, TIE, InsertionOrder, extreme_points,
                                              guide_weights, insertion_batch, insertion_ranking, insertion_start,
                                              largest_first, largest_first_head, median_deviations,
                                              typical_tetrahedron)
from lpnn.quality.placement.insertion_kernel import first_per_cell
from lpnn.quality.metric.metric import POINT_ERRORS, MetricError, ReferenceField, placement_error, probe_stencil
from lpnn.quality.placement.policies import budget_count, place_tolerance, prefix_selection
from lpnn.quality.metric.triangulation import flatness

from quality_support import MEDIUM_ROOM, room_capture


def _grid(capture: Capture) -> EvaluationGrid:
    return EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)


def test_insertion_is_a_deterministic_permutation_starting_from_a_typical_tetrahedron(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    ranking = insertion_ranking(field, grid)
    np.testing.assert_array_equal(np.sort(ranking), np.arange(medium_capture.point_count))
    np.testing.assert_array_equal(ranking, insertion_ranking(field, grid))
    start = typical_tetrahedron(field, grid)
    # The ranking starts with it, then the grid's extreme points along the 8 diagonals (the room's corners here).
    corners = [int(np.flatnonzero((grid.ids == [[hi if s > 0 else lo for s, lo, hi in zip(signs, grid.ids.min(axis=0),
                                                                                    grid.ids.max(axis=0))]]).all(axis=1))[0])
               for signs in EXTREME_DIRECTIONS.tolist()]
    np.testing.assert_array_equal(ranking[:start.shape[0]], start)
    np.testing.assert_array_equal(insertion_start(field, grid), start.tolist() + [c for c in corners if c not in start])
    np.testing.assert_array_equal(ranking[:len(insertion_start(field, grid))], insertion_start(field, grid))
    assert start.shape[0] == 4 and flatness(field.local[start]) is None
    # Its lighting is among the 10 % nearest the median lighting.
    median = np.median(field.light, axis=0, keepdims=True)
    deviation = POINT_ERRORS["irradiance"](np.broadcast_to(median, field.light.shape), field.light, field.scale)
    assert np.all(deviation[start] <= np.quantile(deviation, 0.1) + 1e-12)


def test_insertion_beats_the_heuristic_random_and_uniform_at_a_20_percent_budget() -> None:
    """Measured: irradiance error 0.029 / 0.025 / 0.033 against the heuristic's 0.042 / 0.028 / 0.045 (ratios 0.68 /
    0.90 / 0.74). Seed 4's ratio moves between machines (0.86 on one, 0.90 on another): the regular triangulation
    resolves the lattice's co-spherical ties by rounding, which differs with the CPU's vector width. So each seed
    must beat the heuristic, and the seeds together by 15 %."""
    ratios = []
    for seed in (3, 4, 5):
        capture = room_capture(seed, MEDIUM_ROOM, 0.4)
        field = ReferenceField.from_capture(capture)
        grid = _grid(capture)
        count = budget_count(0.2, capture.point_count)
        inserted = placement_error(field, prefix_selection(grid, insertion_ranking(field, grid))(count)).mean
        heuristic = placement_error(field, prefix_selection(grid, heuristic_ranking(grid, capture.sh,
                                                                                     capture.lighting_scale))(count)).mean
        random = placement_error(field, prefix_selection(grid, random_ranking(capture.point_count))(count)).mean
        uniform = placement_error(field, uniform_selector(grid)(count)).mean
        assert inserted < heuristic and inserted < 0.7 * random and inserted < 0.7 * uniform, seed
        ratios.append(inserted / heuristic)
    assert np.mean(ratios) < 0.85, ratios


def test_the_lazy_order_gives_the_full_rankings_selections_with_fewer_rounds(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    full = insertion_ranking(field, grid)
    eager = prefix_selection(grid, full)
    lazy_order = InsertionOrder(field, grid)
    lazy = lazy_order.selection()
    count = budget_count(0.05, medium_capture.point_count)
    np.testing.assert_array_equal(lazy(count), eager(count))
    rounds_for_budget = lazy_order.rounds
    for k in (1, 2, 3, 4, 5, count // 2, count, 3 * count, medium_capture.point_count):
        np.testing.assert_array_equal(lazy(k), eager(k), err_msg=f"count {k}")
    everything = InsertionOrder(field, grid)
    everything.prefix(medium_capture.point_count)
    assert rounds_for_budget < everything.rounds / 2  # a 5 % budget needs well under half the rounds
    # The tolerance policy's answer is the same, found without ranking every point.
    searched = InsertionOrder(field, grid)
    assert place_tolerance(field, searched.selection(), 0.05).requested == place_tolerance(field, eager, 0.05).requested
    assert searched.prefix(1).shape[0] == 1 and searched.rounds < everything.rounds


# ------------------------------------------------------------------------------------ guided insertion

def _first_round(field: ReferenceField, order: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The other points, their errors and their cells for the probes `order` (what a round sees)."""
    values = field.values("irradiance")
    indices, others, stencil = probe_stencil(field, order)
    errors = POINT_ERRORS["irradiance"](shmath.blend(values[indices], stencil.vertices, stencil.weights),
                                        values[others], field.scale)
    return others, errors, stencil.cell


def test_equal_guide_weights_give_the_unguided_ranking(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    plain = insertion_ranking(field, grid)
    for weight in (1e-3, 1.0, 7.5):
        np.testing.assert_array_equal(insertion_ranking(field, grid, guide=np.full(medium_capture.point_count, weight)),
                                      plain, err_msg=f"weight {weight}")
    np.testing.assert_array_equal(guide_weights(np.full(medium_capture.point_count, 0.3)), 1.0)


def test_a_guide_picks_the_cells_badly_interpolated_point_it_rates_highest(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    start = typical_tetrahedron(field, _grid(medium_capture))
    others, errors, cells = _first_round(field, start)
    # A cell with two points above EXACT: its worst point `a` and a less wrong one `b`.
    cell = next(c for c in np.unique(cells) if np.count_nonzero((cells == c) & (errors > EXACT)) >= 2)
    members = np.flatnonzero((cells == cell) & (errors > EXACT))
    a = others[members[np.argmax(errors[members])]]
    b = others[members[np.argmin(errors[members])]]
    assert a in insertion_batch(field, start) and b not in insertion_batch(field, start)
    guide = np.ones(field.point_count)
    guide[b] = 2.0 * errors[others == a][0] / errors[others == b][0]  # b's error x weight now beats a's
    guided = insertion_batch(field, start, guide=guide)
    assert b in guided and a not in guided
    # The guide never changes which cells need a point or their order: same batch length, same cells.
    cell_of = dict(zip(others.tolist(), cells.tolist()))
    assert [cell_of[p] for p in guided] == [cell_of[p] for p in insertion_batch(field, start)]


def test_a_guide_never_inserts_an_exactly_interpolated_point(medium_capture: Capture) -> None:
    """Uniform lighting: every point is interpolated exactly from the start, whatever the weights say."""
    sh = np.broadcast_to(medium_capture.sh[:1], medium_capture.sh.shape).copy()
    field = ReferenceField.from_sh(medium_capture.positions, sh)
    start = typical_tetrahedron(field, _grid(medium_capture))
    guide = np.random.default_rng(0).uniform(1.0, 1e9, medium_capture.point_count)
    assert insertion_batch(field, start, guide=guide).shape[0] == 0


def test_a_good_guide_beats_plain_insertion() -> None:
    """The mechanism, with the best guide there is: the fast reference's own ranking (rank r of N -> score
    1 - r / N). On three rooms it must lower the error at a 20 % budget, by 1 % on average (each room's ratio can
    move by a few per cent between CPUs: test_insertion_beats_the_heuristic... says why); an ignored guide gives
    exactly 1, an inverted one more.
    Measured (seeds 3, 4, 5; the start with the extreme points, 2026-11-27): guided 0.0261 / 0.0237 / 0.0298, insertion
    0.0265 / 0.0232 / 0.0316, inverted guide 0.0345 / 0.0268 / 0.0361 (the reference itself: 0.0204 / 0.0176 / 0.0228).
    With the typical tetrahedron alone as the start insertion was 0.0282 / 0.0248 / 0.0351 and the guide gained 9 %."""
    from lpnn.quality.placement.decimation.reference_fast import fast_decimation

    ratios = []
    for seed in (3, 4, 5):
        capture = room_capture(seed, MEDIUM_ROOM, 0.4)
        field = ReferenceField.from_capture(capture)
        grid = _grid(capture)
        n = capture.point_count
        rank = np.empty(n)
        rank[fast_decimation(field).ordering] = np.arange(n)
        count = budget_count(0.2, n)
        plain = placement_error(field, prefix_selection(grid, insertion_ranking(field, grid))(count)).mean
        guide = guide_weights(1.0 - rank / n)
        guided = placement_error(field, prefix_selection(grid, insertion_ranking(field, grid, guide=guide))(count)).mean
        inverted = guide_weights(rank / n + 1e-3)
        misled = placement_error(field, prefix_selection(grid, insertion_ranking(field, grid, guide=inverted))(count)).mean
        assert guided < misled and plain < misled, (seed, guided, plain, misled)
        ratios.append(guided / plain)
    assert np.mean(ratios) < 0.99, ratios  # measured 0.98


@pytest.mark.parametrize("guide, message", [
    (np.ones(3), "one number per point"),
    (np.r_[np.nan, np.ones(599)], "guide weight 0 = nan must be a finite number > 0"),
    (np.r_[np.ones(5), 0.0, np.ones(594)], "guide weight 5 = 0.0 must be a finite number > 0"),
])
def test_bad_guide_weights_are_refused_by_name(medium_capture: Capture, guide: np.ndarray, message: str) -> None:
    field = ReferenceField.from_capture(medium_capture)
    weights = guide if guide.shape[0] == 3 else np.resize(guide, medium_capture.point_count)
    with pytest.raises(MetricError, match=message):
        InsertionOrder(field, _grid(medium_capture), guide=weights)


def test_the_lazy_selection_completes_a_flat_head_of_the_start_as_the_whole_ranking_does() -> None:
    """A start of 5 points whose first 4 lie in one plane (the golden's `plane` construction: a lattice lit by layer):
    the lazy selection at 4 probes must add the fifth, as prefix_selection over the whole ranking does; it returned the
    4 flat points before, and `lpnn place --method insertion --tolerance` failed on such levels (dm4ish whole)."""
    k, j, i = np.meshgrid(np.arange(5), np.arange(5), np.arange(5), indexing="ij")
    ids = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.int32)
    sh = np.zeros((ids.shape[0], 27), dtype=np.float32)
    layer = ids[:, 2].astype(np.float64)
    for c in (0, 9, 18):
        sh[:, c] = 1.0 + 0.5 * layer * layer
    sh[:, 1] = 0.25 * layer
    grid = EvaluationGrid(cell_size=0.25, ids=ids)
    field = ReferenceField.from_sh(grid.positions, sh)
    start = typical_tetrahedron(field, grid)
    assert start.shape[0] == 5 and flatness(field.local[start[:4]]) is not None  # the case's premise
    eager = prefix_selection(grid, insertion_ranking(field, grid))
    lazy = InsertionOrder(field, grid).selection()
    for count in (1, 2, 3, 4, 5, 6, 20):
        np.testing.assert_array_equal(lazy(count), eager(count), err_msg=f"count {count}")
    assert lazy(4).shape[0] == 5 and flatness(field.local[lazy(4)]) is None
    assert place_tolerance(field, lazy, 0.05).indices.shape[0] >= 4  # the search starts at 4 probes: no flat error


def test_the_compiled_per_cell_candidate_is_the_numpy_formulations() -> None:
    """insertion_kernel.first_per_cell gives, per cell, the lowest row whose key is within TIE of the cell's largest (a
    numpy formulation), with many equal keys, keys a hair below the largest (within TIE: ties) or a little more (not),
    and cells without rows."""
    rng = np.random.default_rng(4)
    cell = rng.integers(0, 300, 5000)
    key = rng.integers(0, 6, 5000).astype(np.float64) / 4.0  # few distinct values: ties everywhere
    key -= rng.choice([0.0, 0.3 * TIE, 3.0 * TIE], 5000)
    largest = np.full(400, -np.inf)
    np.maximum.at(largest, cell, key)
    within = np.flatnonzero(key >= largest[cell] - TIE)
    expected = within[np.unique(cell[within], return_index=True)[1]]
    np.testing.assert_array_equal(first_per_cell(cell, key, 400, TIE), expected)
    assert np.any(key[expected] < largest[cell[expected]])  # some candidates are not the strict largest


def test_largest_first_joins_values_within_tie_and_orders_them_by_index() -> None:
    values = np.array([1.0, 2.0, 1.0 + 0.5 * TIE, 2.0 - 0.4 * TIE, 2.0 - 0.8 * TIE, 1.0 - 2.0 * TIE, 0.0])
    index = np.array([7, 5, 3, 9, 1, 0, 2])
    # 2 and 2 - 0.4 TIE and 2 - 0.8 TIE chain into one run (each within TIE of the next larger), ordered by index;
    # 1 + 0.5 TIE and 1 likewise; 1 - 2 TIE is a run of its own.
    assert index[largest_first(values, index)].tolist() == [1, 5, 9, 3, 7, 0, 2]


def test_the_head_of_largest_first_sorts_only_near_values_yet_equals_the_whole_sorts() -> None:
    """largest_first_head(values, index, count) is largest_first(values, index)[:count]: on random values, on a chain of
    values each within TIE of the next that straddles the count-th (the head must widen its margin until the chain
    ends), with equal values, and with a NaN (the full sort)."""
    rng = np.random.default_rng(7)
    chain = 0.5 - np.arange(20_000) * 0.9 * TIE  # one run spanning 1.8e-5, far wider than the first margin
    values = np.concatenate([rng.uniform(0.0, 1.0, 30_000), chain, np.full(500, 0.25)])
    index = rng.permutation(values.shape[0])
    for count in (1, 17, 9_000, 14_000, 25_000, values.shape[0] - 1, values.shape[0]):
        np.testing.assert_array_equal(largest_first_head(values, index, count), largest_first(values, index)[:count],
                                      err_msg=f"count {count}")
    cut = int(np.sum(values > 0.5)) + 10_000  # mid-chain
    head = largest_first_head(values, index, cut)
    np.testing.assert_array_equal(head, largest_first(values, index)[:cut])
    assert np.sort(index[head[-10_000:]]).tolist() == index[head[-10_000:]].tolist()  # the chain goes by index
    with_nan = values.copy()
    with_nan[3] = np.nan
    np.testing.assert_array_equal(largest_first_head(with_nan, index, 9_000), largest_first(with_nan, index)[:9_000])


@pytest.mark.parametrize("metric", ["irradiance", "smape"])
def test_median_deviations_are_the_metrics_errors_bit_for_bit(medium_capture: Capture, metric: str) -> None:
    """insertion_kernel.median_deviation gives POINT_ERRORS[metric] of the per-value median against every row, bit for
    bit, on a room and on random values spanning 8 decades (rows with zeros and tiny values: the floor decides), on one
    thread and on the parallel path (more than 2 x PARALLEL_ROWS rows)."""
    field = ReferenceField.from_capture(medium_capture)
    rng = np.random.default_rng(3)
    wide = rng.uniform(-1.0, 1.0, (20_000, 42)) * 10.0 ** rng.uniform(-6, 2, (20_000, 1))
    wide[:50] = 0.0
    for values, scale in ((field.values(metric), field.scale), (wide, 0.7)):
        median = np.median(values, axis=0)
        expected = POINT_ERRORS[metric](np.broadcast_to(median[None, :], values.shape), values, scale)
        got = median_deviations(values, median, scale, metric)
        np.testing.assert_array_equal(got.view(np.int64), expected.view(np.int64))


@pytest.mark.parametrize("head", [4, 5])
def test_the_start_reads_only_the_spread_head_yet_equals_the_whole_rankings(monkeypatch, medium_capture: Capture,
                                                                         head: int) -> None:
    """typical_tetrahedron ranks STARTING_SPREAD candidates first and all of them only when the tetrahedron guarantee
    reaches past that head: the same start as with the whole ranking, on a room (the head suffices) and on a slab
    one point thick but for one point off its plane (the head is flat: the whole ranking is needed)."""
    def start(field, grid, spread):
        monkeypatch.setattr(insertion, "STARTING_SPREAD", spread)
        return typical_tetrahedron(field, grid)

    field, grid = ReferenceField.from_capture(medium_capture), _grid(medium_capture)
    np.testing.assert_array_equal(start(field, grid, head), start(field, grid, 10**9))
    ids = np.stack(np.meshgrid(np.arange(12), np.arange(12), [0], indexing="ij"), axis=-1).reshape(-1, 3)
    ids = np.concatenate([ids, [[11, 11, 1]]])
    ids = ids[np.lexsort((ids[:, 0], ids[:, 1], ids[:, 2]))]
    sh = np.zeros((ids.shape[0], shmath.SH_FLOATS), dtype=np.float32)
    sh[:, 0:27:9] = 1.0 + 0.01 * ids[:, :1]  # lighting varies along x only: the candidates are a strip of the slab
    slab = ReferenceField.from_sh(ids * 0.5, sh)
    slab_grid = EvaluationGrid(cell_size=0.5, ids=ids)
    whole = start(slab, slab_grid, 10**9)
    assert flatness(slab.local[whole]) is None
    np.testing.assert_array_equal(start(slab, slab_grid, head), whole)


@pytest.mark.parametrize("jitter", [0.0, 0.03])
def test_rounds_located_incrementally_equal_fresh_locations(medium_capture: Capture, jitter: float) -> None:
    """InsertionOrder locates each round incrementally (insertion_state.py); on the lattice (points on faces, edges and
    hull vertices shared by several tetrahedra: the tie rule) and on jittered positions (no ties) its order is
    insertion_batch's, every round located from scratch, exactly."""
    positions = medium_capture.positions.astype(np.float64)
    positions = positions + np.random.default_rng(2).uniform(-jitter, jitter, positions.shape) * medium_capture.cell_size
    field = ReferenceField.from_sh(positions, medium_capture.sh, medium_capture.lighting_scale)
    grid = _grid(medium_capture)
    incremental = InsertionOrder(field, grid).prefix(600)
    fresh = insertion_start(field, grid).astype(np.int64)
    while fresh.shape[0] < 600:
        fresh = np.concatenate([fresh, insertion_batch(field, fresh)])
    np.testing.assert_array_equal(incremental, fresh[:600])


def test_extreme_points_take_the_lower_index_among_equal_values() -> None:
    """The C# core's ExtremePointsAreABoxsCornersAndTiesGoToTheLowerIndex case: a diamond in the plane k = 0 and one
    point above; along (+, +, -) three ids tie at i + j - k = 2 and the lowest index wins; each direction's answer is
    checked against every point."""
    ids = np.array([[1, 0, 0], [0, 1, 0], [2, 0, 0], [1, 1, 0], [0, 2, 0], [1, 1, 1]])
    ids = ids[np.lexsort((ids[:, 0], ids[:, 1], ids[:, 2]))]
    grid = EvaluationGrid(cell_size=1.0, ids=ids.astype(np.int32))
    extremes = extreme_points(grid)
    for direction, chosen in zip(EXTREME_DIRECTIONS.tolist(), extremes.tolist()):
        values = [sum(s * int(v) for s, v in zip(direction, row)) for row in ids]
        assert chosen == values.index(max(values)), direction
    assert sum(1 for row in ids.tolist() if row[0] + row[1] == 2 and row[2] == 0) == 3  # the tie exists


# ------------------------------------------------------------------------------------ a head (the network-seed experiment)

def test_a_head_that_is_the_orders_own_rounds_continues_it_exactly(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    plain = InsertionOrder(field, grid)
    start = plain.computed  # the start alone: no round has run yet
    plain.prefix(60)
    done = plain.computed  # a round boundary: the next round starts from exactly these points
    assert done > 60 > start
    headed = InsertionOrder(field, grid, head=plain.prefix(done)[start:])
    assert headed.computed == done and headed.rounds == 0  # the head is ranked without any round
    n = medium_capture.point_count
    np.testing.assert_array_equal(headed.prefix(n), plain.prefix(n))


def test_a_head_follows_the_start_in_its_own_order_without_repeating_a_start_point(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    plain = InsertionOrder(field, grid)
    start = plain.computed
    first = plain.prefix(start)
    free = np.setdiff1d(np.arange(medium_capture.point_count), first)
    head = np.array([free[7], first[2], free[3], free[30]])
    headed = InsertionOrder(field, grid, head=head)
    np.testing.assert_array_equal(headed.prefix(start + 3), np.concatenate([first, [free[7], free[3], free[30]]]))
    ranking = headed.prefix(medium_capture.point_count)
    np.testing.assert_array_equal(np.sort(ranking), np.arange(medium_capture.point_count))  # still every point once


@pytest.mark.parametrize("head, message", [(np.array([0, 0]), "distinct"), (np.array([-1]), "must lie in"),
                                           (np.array([10 ** 9]), "must lie in")])
def test_bad_heads_are_refused_by_name(medium_capture: Capture, head: np.ndarray, message: str) -> None:
    field = ReferenceField.from_capture(medium_capture)
    with pytest.raises(MetricError, match=message):
        InsertionOrder(field, _grid(medium_capture), head=head)
