"""Budget and tolerance policies, and the baselines."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.baselines import heuristic_ranking, hull_corners, random_ranking, uniform_selection
from lpnn.quality.placement import policies
from lpnn.quality.metric.metric import ReferenceField, placement_error
from lpnn.quality.placement.policies import (PolicyError, budget_count, place_count, place_tolerance, prefix_selection,
                                             reference_count, reference_tolerance)
from lpnn.quality.placement.policy_rules import SEARCH_RESOLUTION
from lpnn.quality.placement.decimation.reference_fast import fast_decimation

from quality_support import box_grid


def _grid(capture: Capture) -> EvaluationGrid:
    return EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)


@pytest.mark.parametrize("tolerance", [0.2, 0.08, 0.03])
def test_tolerance_policy_meets_tau_and_is_minimal_among_checked_prefixes(
        small_captures: dict[int, Capture], tolerance: float) -> None:
    capture = small_captures[2]
    field = ReferenceField.from_capture(capture)
    select = prefix_selection(_grid(capture), random_ranking(capture.point_count, seed=3))
    placement = place_tolerance(field, select, tolerance)
    assert placement.mean_error <= tolerance
    assert placement.mean_error == pytest.approx(placement_error(field, placement.indices).mean)  # verified
    below = {count: error for count, error in placement.checked.items() if count < placement.requested}
    assert all(error > tolerance for error in below.values())  # every smaller checked prefix failed
    if placement.requested > 4:  # a count within the search's resolution below was checked, and failed
        window = max(1, placement.requested // SEARCH_RESOLUTION)
        assert any(placement.requested - window <= count < placement.requested for count in below)
    assert len(placement.checked) <= 2 * int(np.log2(capture.point_count)) + 2  # exponential + bisection


def test_above_the_resolution_the_search_stops_at_a_fraction_of_the_count(monkeypatch: pytest.MonkeyPatch) -> None:
    """The C# case of ToleranceTests (same curve, same answer and evaluations): a smooth error whose smallest passing
    count is 7,779 of 10^6; the unit search takes 24 evaluations, this one 20, and keeps at most 1/256 more probes."""
    true_answer = 7779
    monkeypatch.setattr(policies, "mean_placement_error",
                        lambda field_, indices, metric: 0.05 * math.sqrt(true_answer / indices.shape[0]))
    placement = policies.place_tolerance(SimpleNamespace(point_count=1_000_000), lambda count: np.arange(count), 0.05)
    assert placement.requested == 7792 and len(placement.checked) == 20
    assert true_answer <= placement.requested <= true_answer + true_answer // SEARCH_RESOLUTION
    assert not policies.search_resolved(4096, 8192)
    assert policies.search_resolved(7776, 7806) and not policies.search_resolved(7776, 7807)  # 30 x 256 <= 7806 < 31 x 256
    assert policies.search_resolved(200, 201) and not policies.search_resolved(199, 201)  # to the unit below 256
    # With a bound just above the answer the resolved bracket would end at largest + 1 (7,791); the search narrows it
    # to the unit instead of giving up, and finds the answer below the bound.
    bounded = policies.bounded_tolerance(SimpleNamespace(point_count=1_000_000), lambda count: np.arange(count), 0.05,
                                         largest=7790)
    assert bounded is not None and true_answer <= bounded.requested <= 7790  # 7,783 here: resolved again below it
    assert policies.bounded_tolerance(SimpleNamespace(point_count=1_000_000), lambda count: np.arange(count), 0.05,
                                      largest=true_answer - 1) is None


def test_tolerance_on_a_reference_is_the_exact_smallest_prefix(small_field: ReferenceField) -> None:
    decimation = fast_decimation(small_field, workers=1)
    curve = decimation.error_curve
    for tolerance in (0.15, 0.05, 0.01):
        placement = reference_tolerance(decimation, tolerance)
        count = placement.indices.shape[0]
        assert curve[count] <= tolerance
        assert np.all(curve[4:count] > tolerance)
        assert placement.mean_error == pytest.approx(placement_error(small_field, placement.indices).mean, abs=1e-12)


def test_budget_policy_is_the_prefix_completed_to_a_tetrahedron() -> None:
    positions = box_grid(4, 4, 3)
    ids = positions.astype(np.int32)
    grid = EvaluationGrid(cell_size=1.0, ids=ids)
    field = ReferenceField.from_sh(positions, np.random.default_rng(0).uniform(0, 1, (48, 27)))
    flat_first = np.concatenate([np.flatnonzero(positions[:, 2] == 0), np.flatnonzero(positions[:, 2] > 0)])
    placement = place_count(field, prefix_selection(grid, flat_first), 6)  # the top 6 are coplanar
    assert placement.indices.shape[0] == 7 and placement.added_for_tetrahedron == 1
    assert set(flat_first[:6].tolist()) <= set(placement.indices.tolist())
    decimation = fast_decimation(field, workers=1)
    assert reference_count(decimation, 2).indices.shape[0] == 4  # floor of 4


def test_budget_count_rounds_like_the_percentile_policy() -> None:
    assert budget_count(0.1, 100) == 10
    assert budget_count(0.2, 48) == 10  # 9.6 -> 10
    assert budget_count(0.001, 48) == 1
    with pytest.raises(PolicyError, match=r"\(0, 1\]"):
        budget_count(0.0, 48)


def test_policy_parameters_are_checked(small_field: ReferenceField, small_captures: dict[int, Capture]) -> None:
    select = prefix_selection(_grid(small_captures[1]), np.arange(small_field.point_count))
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(PolicyError, match="tolerance"):
            place_tolerance(small_field, select, bad)


# ------------------------------------------------------------------------------------- baselines

def test_uniform_subsample_is_exact_deterministic_and_the_lattice_when_it_fits() -> None:
    ids = box_grid(9, 9, 9).astype(np.int32)
    lattice = np.flatnonzero(np.all(ids % 2 == 0, axis=1))  # 125 points
    np.testing.assert_array_equal(uniform_selection(ids, 125), lattice)
    for count in (1, 7, 60, 125, 200, 729):
        chosen = uniform_selection(ids, count)
        assert chosen.shape[0] == count and np.unique(chosen).shape[0] == count
        np.testing.assert_array_equal(chosen, uniform_selection(ids, count))
        assert np.all(np.diff(chosen) > 0)


def test_random_baseline_is_seeded() -> None:
    np.testing.assert_array_equal(random_ranking(100, 5), random_ranking(100, 5))
    assert not np.array_equal(random_ranking(100, 5), random_ranking(100, 6))
    np.testing.assert_array_equal(np.sort(random_ranking(100, 5)), np.arange(100))


def test_heuristic_is_deterministic_starts_with_the_hull_and_spreads_out(small_captures: dict[int, Capture]) -> None:
    capture = small_captures[1]
    grid = _grid(capture)
    ranking = heuristic_ranking(grid, capture.sh, capture.lighting_scale)
    np.testing.assert_array_equal(ranking, heuristic_ranking(grid, capture.sh, capture.lighting_scale))
    np.testing.assert_array_equal(np.sort(ranking), np.arange(capture.point_count))
    corners = hull_corners(grid.positions)
    assert set(ranking[: corners.shape[0]].tolist()) == set(corners.tolist())


def test_heuristic_beats_random_on_a_synthetic_room(medium_capture: Capture) -> None:
    # A fair baseline: the network has to beat something clearly better than chance. (On rooms only
    # 2-3 cells deep the hull corners use most of a small budget and chance does as well.)
    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    heuristic = prefix_selection(grid, heuristic_ranking(grid, medium_capture.sh, medium_capture.lighting_scale))
    for fraction in (0.1, 0.2, 0.3):
        count = budget_count(fraction, medium_capture.point_count)
        chance = np.mean([placement_error(field, prefix_selection(grid, random_ranking(field.point_count, seed))(count)).mean
                          for seed in range(5)])
        assert placement_error(field, heuristic(count)).mean < chance
