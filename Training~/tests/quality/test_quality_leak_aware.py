"""Leak-aware placement (leak_aware.py; refined_insertion(..., leaks=raycaster)) on two rooms split by a wall."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core import sh as shmath
from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AxisBox
from lpnn.core.grid import EvaluationGrid
from lpnn.core.grid_box import Box
from lpnn.core.grid_builder import build_grid
from lpnn.quality.placement.batched_refinement import BatchedRefinement, batched_refinement, greedy_independent_set
from lpnn.quality.placement.batched_state import evaluate, trial_of, without
from lpnn.quality.placement.leak_aware import LeakWeighting, leak_repaired
from lpnn.quality.metric.leaks import leaking_points
from lpnn.quality.metric.metric import MetricError, ReferenceField, mean_placement_error, point_errors
from lpnn.quality.placement.pins import PinError, Pins, pin_probes
from lpnn.quality.placement.refined_insertion import refined_insertion

TOLERANCE = 0.05
# Lattice x = -4, -3.5, ..., 4 (cell 0.5): the wall lies between x = 0 and x = 0.5, so no point is inside it.
WALL_FROM, WALL_TO = 0.1, 0.4
WALLED = AnalyticBoxRaycaster(obstacles=(AxisBox(min=[WALL_FROM, -10.0, -10.0], max=[WALL_TO, 10.0, 10.0]),))
OPEN = AnalyticBoxRaycaster()


def _two_rooms() -> tuple[ReferenceField, EvaluationGrid]:
    """A warm room (x < the wall) and a cool one half as bright, each varying smoothly: a tetrahedron across the wall
    blends the two, so a leak is an error, yet one small enough that today's default keeps some leaks at tau."""
    grid = build_grid((Box.axis_aligned(np.array([-4.0, 0.0, 0.0]), np.array([4.0, 2.5, 2.5])),), 0.5, 100_000)
    positions = grid.positions.astype(np.float64)
    lit = positions[:, 0] < WALL_FROM
    x, z = positions[:, 0], positions[:, 2]
    bright = shmath.ambient(np.array([1.0, 0.9, 0.7]))[None, :] * (1.0 + 0.3 * np.sin(x) * np.cos(z))[:, None]
    dim = shmath.ambient(np.array([0.35, 0.4, 0.5]))[None, :] * (1.0 + 0.2 * np.cos(x) * np.sin(z))[:, None]
    sh = np.where(lit[:, None], bright, dim)
    return ReferenceField.from_sh(positions, sh), grid


@pytest.fixture(scope="module")
def rooms() -> tuple[ReferenceField, EvaluationGrid]:
    return _two_rooms()


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
