"""Leak-aware placement (leak_aware.py; refined_insertion(..., leaks=raycaster)) on two rooms split by a wall."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AxisBox
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.batched_refinement import BatchedRefinement, batched_refinement, greedy_independent_set
from lpnn.quality.placement.batched_state import evaluate, trial_of, without
from lpnn.quality.placement import leak_aware
from lpnn.quality.placement.leak_aware import LeakWeighting, leak_repaired
from lpnn.quality.metric.leak_rule import SegmentVisibility, stencil_leaks
from lpnn.quality.metric.leaks import leaking_points
from lpnn.quality.metric.metric import (MetricError, ReferenceField, evaluate_placement, evaluated, mean_placement_error,
                                        point_errors)
from lpnn.quality.placement.pins import PinError, Pins, pin_probes
from lpnn.quality.placement.refined_insertion import refined_insertion

from quality_support import OPEN, WALLED, two_rooms

TOLERANCE = 0.05


@pytest.fixture(scope="module")
def rooms() -> tuple[ReferenceField, EvaluationGrid]:
    return two_rooms()


def _corners(field: ReferenceField) -> np.ndarray:
    """The 8 corners of the whole box: every tetrahedron spans the wall."""
    lo, hi = field.world.min(axis=0), field.world.max(axis=0)
    at_corner = np.all(np.isclose(field.world, lo) | np.isclose(field.world, hi), axis=1)
    return np.flatnonzero(at_corner)


def test_the_weighting_multiplies_only_the_errors_of_leaking_points(rooms) -> None:
    field, _ = rooms
    probes = _corners(field)
    leaking, errors = leaking_points(field, probes, WALLED)
    assert leaking.any() and (errors[leaking] > 0).any()
    state = evaluate(field, probes, LeakWeighting(WALLED, 3.0))
    assert np.allclose(state.errors, np.where(leaking, 3.0 * errors, errors), rtol=1e-12, atol=0.0)
    assert state.error_sum == pytest.approx(float(state.errors.sum()))
    assert np.allclose(evaluate(field, probes, LeakWeighting(OPEN, 3.0)).errors, errors)  # no wall, no weight


@pytest.mark.parametrize("weight", [0.5, float("nan"), float("inf")])
def test_a_weight_below_one_or_not_finite_is_refused(weight: float) -> None:
    with pytest.raises(MetricError, match="leak weight"):
        LeakWeighting(WALLED, weight)


def test_trial_costs_and_removals_keep_the_weighting(rooms) -> None:
    """The incremental state (only the points whose stencil changed re-evaluated) equals a fresh weighted evaluation:
    a point whose stencil is unchanged keeps its leak."""
    field, _ = rooms
    weighting = LeakWeighting(WALLED, 4.0)
    seed = np.arange(0, field.point_count, 7)
    state = evaluate(field, seed, weighting)
    rank = np.full(field.point_count, np.iinfo(np.int64).max, dtype=np.int64)
    rank[seed] = np.arange(seed.shape[0])
    candidates = greedy_independent_set(seed, state.edges, rank)[:8]
    trial = trial_of(field, state, candidates)
    following = without(field, state, candidates, trial)
    remaining = np.setdiff1d(seed, candidates)
    fresh = evaluate(field, remaining, weighting)
    changed = np.flatnonzero(~np.isclose(following.errors, state.errors, rtol=0.0, atol=1e-12))
    assert np.any(leaking_points(field, remaining, WALLED)[0][changed])  # re-evaluated points that leak: weighted
    assert np.allclose(following.errors, fresh.errors, atol=1e-9)
    assert following.error_sum - state.error_sum == pytest.approx(float(trial.costs.sum()), abs=1e-9)


def test_repair_puts_a_probe_in_each_leaking_tetrahedron_and_the_leaks_drop(rooms) -> None:
    field, _ = rooms
    probes = _corners(field)
    before = int(leaking_points(field, probes, WALLED)[0].sum())
    once = leak_repaired(field, probes, WALLED, rounds=1)
    added = np.setdiff1d(once, probes)
    assert added.shape[0] > 0 and np.all(leaking_points(field, probes, WALLED)[0][added])  # only leaking points
    twice = leak_repaired(field, probes, WALLED, rounds=2)
    assert np.all(np.isin(once, twice)) and int(leaking_points(field, twice, WALLED)[0].sum()) < before
    assert np.array_equal(leak_repaired(field, probes, WALLED, rounds=0), np.sort(probes))
    assert np.array_equal(leak_repaired(field, probes, OPEN, rounds=3), np.sort(probes))  # nothing leaks: nothing added
    with pytest.raises(MetricError, match="rounds"):
        leak_repaired(field, probes, WALLED, rounds=-1)


def test_the_leak_aware_default_leaks_less_within_the_tolerance(rooms) -> None:
    field, grid = rooms
    plain = refined_insertion(field, grid, tolerance=TOLERANCE)
    aware = refined_insertion(field, grid, tolerance=TOLERANCE, leaks=WALLED)
    plain_leaks = int(leaking_points(field, plain.indices, WALLED)[0].sum())
    aware_leaks = int(leaking_points(field, aware.indices, WALLED)[0].sum())
    assert plain_leaks > 0 and aware_leaks < plain_leaks
    # The reported error is the plain metric's, and within tau; the weighted one is within tau too.
    assert aware.mean_error == pytest.approx(mean_placement_error(field, aware.indices))
    assert aware.mean_error <= TOLERANCE
    weighted = evaluate(field, aware.indices, LeakWeighting(WALLED)).error_sum / field.point_count
    assert weighted <= TOLERANCE + 1e-12
    # Without a wall nothing leaks: the option changes nothing but the (repair-free) seed's refinement.
    assert np.array_equal(refined_insertion(field, grid, tolerance=TOLERANCE, leaks=OPEN).indices, plain.indices)


def test_the_option_is_off_by_default_and_refinement_without_it_is_unchanged(rooms) -> None:
    field, grid = rooms
    seed = np.arange(0, field.point_count, 2)
    plain = batched_refinement(field, seed, tolerance=TOLERANCE)
    assert plain.mean_error == pytest.approx(float(point_errors(field, plain.indices).mean()))
    weighted = batched_refinement(field, seed, tolerance=TOLERANCE, leaks=LeakWeighting(WALLED))
    assert int(leaking_points(field, weighted.indices, WALLED)[0].sum()) < int(
        leaking_points(field, plain.indices, WALLED)[0].sum())
    budget = refined_insertion(field, grid, budget=0.1, leaks=WALLED)
    assert budget.indices.shape[0] == round(0.1 * field.point_count)  # a count stays a count
    assert budget.mean_error == pytest.approx(mean_placement_error(field, budget.indices))


def _pins_by_the_wall(field: ReferenceField, grid: EvaluationGrid) -> Pins:
    """Two pins on lattice points just below the wall (x = 0), with a keep distance of 1.5 cells: points on both sides
    of the wall near them are blocked, some of which the corners' stencils make leak."""
    at = [int(np.flatnonzero(np.all(np.isclose(field.world, p), axis=1))[0]) for p in ((0.0, 1.0, 1.0), (0.0, 0.5, 2.0))]
    return pin_probes(field.world[at], field.world, grid.cell_size, 1.5 * grid.cell_size)


def test_with_pins_the_repair_adds_no_probe_within_their_keep_distance(rooms) -> None:
    field, grid = rooms
    pins = _pins_by_the_wall(field, grid)
    probes = np.union1d(_corners(field), pins.indices)
    leaking = leaking_points(field, probes, WALLED)[0]
    assert (leaking & pins.blocked).any()  # a leaking point near a pin: the case the rule is for
    unpinned = np.setdiff1d(leak_repaired(field, probes, WALLED, rounds=1), probes)
    assert pins.blocked[unpinned].any()  # without the pins' blocked points, the repair would put a probe there
    pinned = np.setdiff1d(leak_repaired(field, probes, WALLED, rounds=1, blocked=pins.blocked), probes)
    assert pinned.shape[0] > 0 and not pins.blocked[pinned].any() and np.all(leaking[pinned])
    # Each leaking tetrahedron gets its worst leaking point among those that may become probes: the same choice as an
    # unblocked repair wherever that worst point is free.
    assert np.all(np.isin(unpinned[~pins.blocked[unpinned]], pinned))
    with pytest.raises(MetricError, match="blocked must flag each"):
        leak_repaired(field, probes, WALLED, blocked=pins.blocked[:-1])


def test_leaks_and_pins_together_keep_the_pins_count_them_and_leak_less(rooms) -> None:
    field, grid = rooms
    pins = _pins_by_the_wall(field, grid)
    at_tau = refined_insertion(field, grid, tolerance=TOLERANCE, leaks=WALLED, pins=pins)
    plain = refined_insertion(field, grid, tolerance=TOLERANCE, pins=pins)
    for placed in (at_tau, plain):
        assert np.all(np.isin(pins.indices, placed.indices)) and placed.mean_error <= TOLERANCE
        new = np.setdiff1d(placed.indices, pins.indices)
        assert not pins.blocked[new].any()  # no new probe near a pin, repaired or inserted
    assert int(leaking_points(field, at_tau.indices, WALLED)[0].sum()) < int(
        leaking_points(field, plain.indices, WALLED)[0].sum())
    budget = refined_insertion(field, grid, budget=0.1, leaks=WALLED, pins=pins)
    assert budget.indices.shape[0] == round(0.1 * field.point_count)  # the pins count in the budget
    assert np.all(np.isin(pins.indices, budget.indices)) and not pins.blocked[np.setdiff1d(budget.indices, pins.indices)].any()
    with pytest.raises(PinError, match="raise the budget"):
        refined_insertion(field, grid, budget=1.0 / field.point_count, leaks=WALLED, pins=pins)


@pytest.mark.parametrize("leaks", [None, WALLED])
def test_a_refined_set_whose_fresh_error_exceeds_tau_is_not_the_answer(rooms, monkeypatch, leaks) -> None:
    """The refinement's incremental error can disagree with the metric's fresh one (leaks.md "A leak-aware default":
    ctf_compromise); refined_insertion takes the refined set only when its error, evaluated afresh, is within tau."""
    import lpnn.quality.placement.refined_insertion as module

    field, grid = rooms
    corners = _corners(field)  # 8 probes: far above tau, whatever the refinement believes
    assert mean_placement_error(field, corners) > TOLERANCE
    monkeypatch.setattr(module, "batched_refinement", lambda *args, **kwargs: BatchedRefinement(
        indices=corners, mean_error=0.0, rounds=1, stop_reason="tolerance", seconds=0.0))
    fooled = refined_insertion(field, grid, tolerance=TOLERANCE, leaks=leaks)
    assert not np.array_equal(fooled.indices, corners)  # the search's answer instead
    assert fooled.mean_error == pytest.approx(mean_placement_error(field, fooled.indices)) and fooled.mean_error <= TOLERANCE


# Remembered segments (metric/leak_rule.py SegmentVisibility): the same answers as casting every segment anew, with
# fewer rays.

class CountingRaycaster:
    """A raycaster that counts the rays it is asked to cast."""

    def __init__(self, inner) -> None:
        self.inner = inner
        self.rays = 0

    def cast(self, origins: np.ndarray, directions: np.ndarray, max_distance: float):
        self.rays += int(origins.shape[0])
        return self.inner.cast(origins, directions, max_distance)


def _stencils(rng: np.random.Generator, points: int, probes: int, rows: int):
    """Random stencils over few points and probes, so pairs repeat and points get more partners than slots."""
    at = rng.integers(0, points, rows)
    vertices = np.stack([rng.choice(probes, 4, replace=False) for _ in range(rows)])
    weights = rng.dirichlet(np.ones(4), rows)
    weights[rng.random((rows, 4)) < 0.2] = 0.0  # zero weights: not cast, not leaking
    return at, vertices, weights


@pytest.mark.parametrize("slots", [4, 8])
def test_remembered_segments_answer_as_a_fresh_cast_in_any_order(slots: int) -> None:
    rng = np.random.default_rng(7)
    # Points on both sides of the wall (x in [0.1, 0.4]) and probes among them.
    positions = np.column_stack([rng.uniform(-2.0, 2.0, 60), rng.uniform(0.0, 2.0, 60), rng.uniform(0.0, 2.0, 60)])
    positions = positions[(positions[:, 0] < 0.05) | (positions[:, 0] > 0.45)]
    counting = CountingRaycaster(WALLED)
    memo = SegmentVisibility(counting, positions, slots=slots)
    probes = np.arange(12)
    asked = 0
    for _ in range(30):
        points = np.arange(12, positions.shape[0])
        at, vertices, weights = _stencils(rng, points.shape[0], probes.shape[0], 40)
        expected = stencil_leaks(positions[points[at]], positions[probes], vertices, weights, WALLED)
        assert np.array_equal(memo.stencil_leaks(points[at], probes, vertices, weights), expected)
        asked += int(np.count_nonzero(weights > 1e-6))
    assert expected.any() and not expected.all()  # both answers were exercised
    assert memo.asked == asked and counting.rays == memo.rays < asked  # remembered: fewer rays than segments asked
    # No more pairs exist than points x probes: with a slot per probe nothing is cast twice.
    if slots >= probes.shape[0]:
        assert memo.rays <= (positions.shape[0] - 12) * probes.shape[0]


def test_fewer_than_four_slots_are_refused() -> None:
    with pytest.raises(ValueError, match="slots"):
        SegmentVisibility(WALLED, np.zeros((5, 3)), slots=3)


def test_the_memo_must_be_of_the_weighting_s_raycaster_and_field(rooms) -> None:
    field, _ = rooms
    other = AnalyticBoxRaycaster(obstacles=(AxisBox(min=[0.1, -10.0, -10.0], max=[0.4, 10.0, 10.0]),))
    with pytest.raises(MetricError, match="own raycaster"):
        LeakWeighting(WALLED, 8.0, SegmentVisibility(other, field.world))
    with pytest.raises(MetricError, match="raycaster the repair"):
        leak_repaired(field, _corners(field), WALLED, visibility=SegmentVisibility(other, field.world))
    with pytest.raises(MetricError, match="remember them for this field"):
        leak_repaired(field, _corners(field), WALLED, visibility=SegmentVisibility(WALLED, field.world[:-1]))


def _placed(field, grid, monkeypatch, remember: bool, **options):
    """The leak-aware default with (remember) or without the memo (every segment cast anew, as before it), and the
    rays it cast."""
    counting = CountingRaycaster(WALLED)
    with monkeypatch.context() as patch:
        if not remember:
            patch.setattr(leak_aware.LeakWeighting, "remembering", lambda self, field: self)
        placed = refined_insertion(field, grid, leaks=counting, **options)
    return placed, counting.rays


@pytest.mark.parametrize("options", [{"tolerance": TOLERANCE}, {"budget": 0.1}], ids=["tolerance", "budget"])
def test_the_leak_aware_default_places_the_same_probes_with_fewer_rays(rooms, monkeypatch, options) -> None:
    field, grid = rooms
    fresh, fresh_rays = _placed(field, grid, monkeypatch, False, **options)
    remembered, rays = _placed(field, grid, monkeypatch, True, **options)
    assert np.array_equal(remembered.indices, fresh.indices)
    assert remembered.rounds == fresh.rounds and remembered.seed_count == fresh.seed_count
    assert remembered.mean_error == fresh.mean_error
    assert 0 < rays < fresh_rays / 2, (rays, fresh_rays)


def test_pinned_leak_aware_placement_is_unchanged_by_the_memo(rooms, monkeypatch) -> None:
    field, grid = rooms
    pins = _pins_by_the_wall(field, grid)
    fresh, _ = _placed(field, grid, monkeypatch, False, tolerance=TOLERANCE, pins=pins)
    remembered, _ = _placed(field, grid, monkeypatch, True, tolerance=TOLERANCE, pins=pins)
    assert np.array_equal(remembered.indices, fresh.indices)


def test_a_headed_default_searches_from_its_head_and_meets_the_tolerance(rooms) -> None:
    """refined_insertion(..., head=): insertion starts from the head (Tools~/experiments/network-seed.py), so the
    search's answer and the refinement's seed hold it, and the answer is still within tau, leak-aware or not."""
    field, grid = rooms
    head = np.arange(3, field.point_count, 9)
    for leaks in (None, WALLED):
        headed = refined_insertion(field, grid, tolerance=TOLERANCE, leaks=leaks, head=head, refine=1.2)
        assert headed.seed_count >= head.shape[0]
        assert mean_placement_error(field, headed.indices) <= TOLERANCE
        assert headed.mean_error == pytest.approx(mean_placement_error(field, headed.indices))


def _same_quality(a, b) -> None:
    for name in ("irradiance", "smape"):
        assert getattr(a, name).mean == getattr(b, name).mean and getattr(a, name).p95 == getattr(b, name).p95
        np.testing.assert_array_equal(getattr(a, name).per_point, getattr(b, name).per_point)
    assert a.probes == b.probes and a.leaking == b.leaking
    assert a.in_use_error == b.in_use_error or (np.isnan(a.in_use_error) and np.isnan(b.in_use_error))


@pytest.mark.parametrize("options", [{"tolerance": TOLERANCE}, {"budget": 0.1}])
def test_the_answer_s_report_reuses_its_fresh_evaluation_and_remembered_segments(rooms, options) -> None:
    """lpnn place reports the default's answer from the evaluation the placement made of it and through its remembered
    segments: the report of a fresh evaluation, number for number, with few segments cast again."""
    field, grid = rooms
    walled = replace(field, geometry=WALLED)
    placed = refined_insertion(walled, grid, leaks=WALLED, **options)
    assert placed.evaluation is not None and placed.segments is not None
    fresh = evaluated(walled, placed.indices)
    np.testing.assert_array_equal(placed.evaluation.errors, fresh.errors)
    assert placed.mean_error == fresh.mean_error == mean_placement_error(walled, placed.indices)
    rays, asked = placed.segments.rays, placed.segments.asked
    _same_quality(evaluate_placement(walled, placed.indices, placed.evaluation, placed.segments),
                  evaluate_placement(walled, placed.indices))
    # Most of the answer's segments were remembered: far fewer cast than asked.
    assert 0 < placed.segments.asked - asked and placed.segments.rays - rays < (placed.segments.asked - asked) / 4
    corners = _corners(walled)  # a placement that leaks: the remembered segments answer as fresh casts
    leaky = evaluate_placement(walled, corners)
    assert 0.0 < leaky.leaking < 1.0
    _same_quality(evaluate_placement(walled, corners, None, placed.segments), leaky)
    with pytest.raises(MetricError, match="another placement"):
        evaluate_placement(walled, placed.indices[1:], placed.evaluation)
    with pytest.raises(MetricError, match="remembered segments"):
        evaluate_placement(walled, placed.indices, None, SegmentVisibility(OPEN, walled.world))


def test_a_leak_blind_answer_brings_no_remembered_segments(rooms) -> None:
    field, grid = rooms
    placed = refined_insertion(field, grid, tolerance=TOLERANCE)
    assert placed.segments is None
    if placed.evaluation is not None:  # the refined set was checked afresh: its evaluation is the answer's
        np.testing.assert_array_equal(placed.evaluation.errors, evaluated(field, placed.indices).errors)
