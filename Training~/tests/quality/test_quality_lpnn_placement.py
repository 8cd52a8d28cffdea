"""LPNN placement tiers (quality.md §4): spread ranking, tolerance, seeded exact refinement, top-K."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.core.selection import ensure_tetrahedron, rank
from lpnn.core.spread import spread_ranking
from lpnn.quality.placement.batched_refinement import batched_refinement
from lpnn.quality.placement.insertion import InsertionOrder, guide_weights, insertion_ranking
from lpnn.quality.placement.lpnn_placement import largest_seeded_count, lpnn_placement, seed_count
from lpnn.quality.placement.refined_insertion import budget_seed_count
from lpnn.quality.metric.metric import MetricError, ReferenceField, placement_error
from lpnn.quality.placement.refined_insertion import refined_insertion
from lpnn.quality.placement.policies import (PolicyError, bounded_tolerance, budget_count, place_tolerance,
                                             prefix_selection)
from lpnn.quality.placement.decimation.reference_fast import fast_decimation
from lpnn.train.placement_metric import PLACEMENT_ERROR_20, PLACEMENT_ERROR_TOPK_20


class StubScorer:
    """Stands in for OnnxScorer: a score that favours bright points (any deterministic score will do)."""

    calls = 0

    def score_capture(self, capture: Capture, name: str = "") -> np.ndarray:
        StubScorer.calls += 1
        luminance = capture.sh[:, 0].astype(np.float64)
        return (luminance / luminance.max()).astype(np.float32)


def _grid(capture: Capture) -> EvaluationGrid:
    return EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)


def test_budget_tier_is_the_spread_prefix_and_topk_the_score_prefix(small_captures: dict[int, Capture]) -> None:
    capture = replace(small_captures[2], source={**small_captures[2].source, "feature_seconds": 0.125})
    scores = StubScorer().score_capture(capture)
    count = budget_count(0.25, capture.point_count)
    spread = spread_ranking(capture.positions, scores)
    placed = lpnn_placement(capture, StubScorer(), budget=0.25)
    np.testing.assert_array_equal(placed.ranking, spread)
    np.testing.assert_array_equal(placed.indices, ensure_tetrahedron(_grid(capture), spread, spread[:count])[0])
    field = ReferenceField.from_capture(capture)
    assert placed.mean_error == pytest.approx(placement_error(field, placed.indices).mean)
    assert placed.timing.features == 0.125 and placed.timing.inference > 0.0 and placed.timing.refinement == 0.0
    assert placed.timing.total >= placed.timing.features + placed.timing.inference + placed.timing.selection
    top = lpnn_placement(capture, scores=scores, budget=0.25, topk=True)
    np.testing.assert_array_equal(top.indices, np.sort(rank(scores)[:count]))
    assert top.timing.inference == 0.0 and top.timing.features == 0.125


def test_tolerance_tier_is_the_search_over_spread_prefixes(small_captures: dict[int, Capture]) -> None:
    capture = small_captures[1]
    field = ReferenceField.from_capture(capture)
    scores = StubScorer().score_capture(capture)
    placed = lpnn_placement(capture, scores=scores, tolerance=0.05, reference=field)
    expected = place_tolerance(field, prefix_selection(_grid(capture), spread_ranking(capture.positions, scores)), 0.05)
    np.testing.assert_array_equal(placed.indices, expected.indices)
    assert placed.mean_error <= 0.05 and placed.checked == expected.checked and placed.requested == expected.requested


def test_refined_budget_is_the_seeded_decimation_down_to_k(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    n = medium_capture.point_count
    scores = StubScorer().score_capture(medium_capture)
    count = budget_count(0.2, n)
    placed = lpnn_placement(medium_capture, scores=scores, budget=0.2, refine=2.0, reference=field)
    guided = insertion_ranking(field, _grid(medium_capture), guide=guide_weights(scores))  # the seed's ranking
    seed = ensure_tetrahedron(_grid(medium_capture), guided, guided[:seed_count(2.0, count, n)])[0]
    assert placed.seed_count == seed.shape[0] == 2 * count
    expected = fast_decimation(field, initial=seed, min_count=count)
    np.testing.assert_array_equal(placed.indices, expected.prefix(count))
    assert placed.indices.shape[0] == count and set(placed.indices.tolist()) <= set(seed.tolist())
    assert placed.timing.refinement > 0.0
    # What the tier is for: on this room the refined placement beats the plain spread prefix and guided insertion.
    plain = lpnn_placement(medium_capture, scores=scores, budget=0.2, reference=field)
    unrefined = lpnn_placement(medium_capture, scores=scores, budget=0.2, guided=True, reference=field)
    assert placed.mean_error < unrefined.mean_error and placed.mean_error < plain.mean_error
    same = lpnn_placement(medium_capture, scores=scores, budget=0.2, refine=2.0, guided=True, reference=field)
    np.testing.assert_array_equal(same.indices, placed.indices)  # guided + refine is the refine tier itself
    # topk keeps its own ranking as the seed (kept for comparison).
    top = lpnn_placement(medium_capture, scores=scores, budget=0.2, refine=2.0, topk=True, reference=field)
    ranked = rank(scores)
    top_seed = ensure_tetrahedron(_grid(medium_capture), ranked, ranked[:seed_count(2.0, count, n)])[0]
    np.testing.assert_array_equal(top.indices, fast_decimation(field, initial=top_seed, min_count=count).prefix(count))


def test_refined_tolerance_reads_the_exact_smallest_count_from_the_seeded_curve(small_captures: dict[int, Capture]) -> None:
    capture = small_captures[3]
    field = ReferenceField.from_capture(capture)
    scores = StubScorer().score_capture(capture)
    plain = lpnn_placement(capture, scores=scores, tolerance=0.04, guided=True, reference=field)  # K0 and the seed
    refined = lpnn_placement(capture, scores=scores, tolerance=0.04, refine=2.0, reference=field)
    assert refined.mean_error <= 0.04 and refined.indices.shape[0] < plain.indices.shape[0]
    guided = plain.ranking
    start = seed_count(2.0, plain.indices.shape[0], capture.point_count)
    seed = ensure_tetrahedron(_grid(capture), guided, guided[:start])[0]
    curve = fast_decimation(field, initial=seed).error_curve
    within = np.flatnonzero(curve <= 0.04)  # NaN compares false
    assert refined.indices.shape[0] == min(within[0], plain.indices.shape[0])


def test_the_batched_tier_is_guided_insertion_refined_in_batches(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    n = medium_capture.point_count
    scores = StubScorer().score_capture(medium_capture)
    count = budget_count(0.1, n)
    placed = lpnn_placement(medium_capture, scores=scores, budget=0.1, refine=2.0, batched=True, reference=field)
    guided = insertion_ranking(field, _grid(medium_capture), guide=guide_weights(scores))
    assert (n, count, budget_seed_count(2.0, count, n)) == (616, 62, 186)  # the budget path's seed: 3K (quality.md §5.3)
    seed = ensure_tetrahedron(_grid(medium_capture), guided, guided[:186])[0]
    np.testing.assert_array_equal(placed.indices, batched_refinement(field, seed, count=count).indices)
    assert placed.seed_count == seed.shape[0] and placed.timing.refinement > 0.0
    unrefined = lpnn_placement(medium_capture, scores=scores, budget=0.1, guided=True, reference=field)
    assert placed.mean_error < unrefined.mean_error
    within = lpnn_placement(medium_capture, scores=scores, tolerance=0.05, refine=2.0, batched=True, reference=field)
    searched = lpnn_placement(medium_capture, scores=scores, tolerance=0.05, guided=True, reference=field)
    assert within.mean_error <= 0.05 and within.indices.shape[0] < searched.indices.shape[0]
    assert within.checked == {within.requested: pytest.approx(within.mean_error)}
    with pytest.raises(PolicyError, match="batched is a way to refine"):
        lpnn_placement(medium_capture, scores=scores, budget=0.1, batched=True)


def test_refined_insertion_never_keeps_more_than_insertions_tolerance_answer(small_captures: dict[int, Capture]) -> None:
    for capture in small_captures.values():
        field = ReferenceField.from_capture(capture)
        grid = _grid(capture)
        searched = place_tolerance(field, InsertionOrder(field, grid).selection(), 0.03)
        refined = refined_insertion(field, grid, tolerance=0.03)
        assert refined.mean_error <= 0.03 and refined.indices.shape[0] <= searched.indices.shape[0]
        assert refined.mean_error == pytest.approx(placement_error(field, refined.indices).mean)
    with pytest.raises(MetricError, match="refine 1 must be a factor > 1"):
        refined_insertion(field, grid, budget=0.2, refine=1)


def test_parameters_are_checked(small_captures: dict[int, Capture]) -> None:
    capture = small_captures[1]
    scores = np.ones(capture.point_count, dtype=np.float32)
    with pytest.raises(PolicyError, match="exactly one of budget"):
        lpnn_placement(capture, scores=scores, budget=0.2, tolerance=0.02)
    with pytest.raises(PolicyError, match="exactly one of scorer"):
        lpnn_placement(capture, StubScorer(), scores=scores, budget=0.2)
    with pytest.raises(PolicyError, match="refine 1.0 must be a factor > 1"):
        lpnn_placement(capture, scores=scores, budget=0.2, refine=1.0)
    with pytest.raises(PolicyError, match="one score per point"):
        lpnn_placement(capture, scores=scores[:-1], budget=0.2)
    with pytest.raises(PolicyError, match="budget"):
        lpnn_placement(capture, scores=scores, budget=1.5)
    with pytest.raises(PolicyError, match="guided insertion ranks by itself"):
        lpnn_placement(capture, scores=scores, budget=0.2, guided=True, topk=True)


def test_guided_tier_is_the_guided_insertion_order_read_only_as_far_as_the_policy_needs(medium_capture: Capture) -> None:
    capture = medium_capture
    field = ReferenceField.from_capture(capture)
    grid = _grid(capture)
    scores = StubScorer().score_capture(capture)
    full = insertion_ranking(field, grid, guide=guide_weights(scores))
    count = budget_count(0.1, capture.point_count)
    placed = lpnn_placement(capture, scores=scores, budget=0.1, guided=True, reference=field, full_ranking=False)
    np.testing.assert_array_equal(placed.indices, np.sort(full[:count]))
    assert count <= placed.ranking.shape[0] < capture.point_count  # lazily: only the rounds the budget needs
    np.testing.assert_array_equal(placed.ranking, full[:placed.ranking.shape[0]])
    expected = place_tolerance(field, prefix_selection(grid, full), 0.05)
    reported: list[tuple[int, int]] = []
    searched = lpnn_placement(capture, scores=scores, tolerance=0.05, guided=True, reference=field,
                              progress=lambda done, total: reported.append((done, total)))
    np.testing.assert_array_equal(searched.indices, expected.indices)
    np.testing.assert_array_equal(searched.ranking, full)  # full_ranking=True: the whole order
    assert reported and all(done <= total for done, total in reported)


def test_validation_metric_scores_the_spread_placement(small_captures: dict[int, Capture]) -> None:
    capture = small_captures[2]
    scores = StubScorer().score_capture(capture)
    cloud = SimpleNamespace(capture=capture)
    field = ReferenceField.from_capture(capture)
    spread = lpnn_placement(capture, scores=scores, budget=0.2, reference=field).mean_error
    top = lpnn_placement(capture, scores=scores, budget=0.2, topk=True, reference=field).mean_error
    assert PLACEMENT_ERROR_20.name == "placement_error_20"
    assert PLACEMENT_ERROR_20.per_capture(cloud, scores) == pytest.approx(spread)
    assert PLACEMENT_ERROR_TOPK_20.per_capture(cloud, scores) == pytest.approx(top)
    assert np.isnan(PLACEMENT_ERROR_20.per_capture(cloud, scores[:-1]))  # a crop: not the whole capture


def test_refine_runs_the_full_reference_when_the_seed_would_hold_most_points(medium_capture: Capture) -> None:
    """A seed of 2 x 30 % = 60 % of the points costs more than the full reference (oa_dm1: 1.4x its
    time at 70 %): the tier runs the full reference instead and gets exactly its answer."""
    field = ReferenceField.from_capture(medium_capture)
    n = medium_capture.point_count
    scores = StubScorer().score_capture(medium_capture)
    count = budget_count(0.3, n)
    assert count > largest_seeded_count(2.0, n)
    placed = lpnn_placement(medium_capture, scores=scores, budget=0.3, refine=2.0, reference=field)
    assert placed.seed_count == n
    assert placed.ranking.shape[0] < count  # no guided insertion rounds up to K: the full reference ignores them
    full = fast_decimation(field, min_count=count)
    np.testing.assert_array_equal(placed.indices, full.prefix(count))


def test_refined_tolerance_with_a_large_answer_stops_searching_and_runs_the_full_reference(
        medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    n = medium_capture.point_count
    scores = StubScorer().score_capture(medium_capture)
    tau = 0.004  # guided insertion needs far more than 0.4 N / 2 points for it on this room
    largest = largest_seeded_count(2.0, n)
    plain = lpnn_placement(medium_capture, scores=scores, tolerance=tau, guided=True, reference=field)
    spread = lpnn_placement(medium_capture, scores=scores, tolerance=tau, reference=field)
    assert plain.requested > largest and spread.requested > largest
    refined = lpnn_placement(medium_capture, scores=scores, tolerance=tau, refine=2.0, reference=field)
    # The spread ranking's search (milliseconds) already shows the answer is too large: no guided insertion search.
    assert refined.seed_count == n and refined.checked == {}
    full = fast_decimation(field)
    best = full.smallest_count_within(tau)
    np.testing.assert_array_equal(refined.indices, full.prefix(best))
    assert refined.mean_error <= tau


def test_bounded_tolerance_gives_up_above_its_bound_without_evaluating_beyond_it(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    scores = StubScorer().score_capture(medium_capture)
    select = prefix_selection(_grid(medium_capture), spread_ranking(medium_capture.positions, scores))
    unbounded = place_tolerance(field, select, 0.02)
    assert unbounded.requested > 10
    evaluated: list[int] = []

    def counted(count: int) -> np.ndarray:
        evaluated.append(count)
        return select(count)

    assert bounded_tolerance(field, counted, 0.02, largest=unbounded.requested - 1) is None
    assert max(evaluated) <= unbounded.requested
    same = bounded_tolerance(field, select, 0.02, largest=medium_capture.point_count)
    assert same is not None and same.requested == unbounded.requested
    np.testing.assert_array_equal(same.indices, unbounded.indices)
    # Any bound: an answer keeps the search's guarantee (within tau, one fewer checked and failing).
    for largest in range(unbounded.requested - 3, unbounded.requested + 40, 7):
        found = bounded_tolerance(field, select, 0.02, largest=largest)
        if found is not None:
            assert found.requested <= largest and found.mean_error <= 0.02
            assert found.checked[found.requested - 1] > 0.02


def test_a_tiny_budget_seeds_the_refinement_with_at_least_64_points(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    scores = StubScorer().score_capture(medium_capture)
    count = budget_count(0.01, medium_capture.point_count)
    assert 2 * count < 64
    placed = lpnn_placement(medium_capture, scores=scores, budget=0.01, refine=2.0, reference=field)
    assert placed.seed_count == 64
    guided = insertion_ranking(field, _grid(medium_capture), guide=guide_weights(scores))
    expected = fast_decimation(field, initial=guided[:64], min_count=count)
    np.testing.assert_array_equal(placed.indices, expected.prefix(count))


def test_above_the_guided_point_limit_the_guided_tier_is_plain_insertion(medium_capture: Capture,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """quality.md §5.2: the network's guide is used on volumes of at most GUIDED_POINT_LIMIT points (32,768), plain
    insertion above. Shown with the limit lowered to just below and at this room's point count."""
    import lpnn.quality.placement.insertion as insertion

    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    scores = StubScorer().score_capture(medium_capture)
    n = medium_capture.point_count
    plain = prefix_selection(grid, insertion_ranking(field, grid))
    guided = prefix_selection(grid, insertion_ranking(field, grid, guide=guide_weights(scores)))
    count = budget_count(0.2, n)
    assert not np.array_equal(plain(count), guided(count))  # the guide matters on this room
    assert insertion.GUIDED_POINT_LIMIT == 32_768
    assert insertion.guide_of(np.ones(32_769)) is None and insertion.guide_of(np.ones(32_768)) is not None
    for limit, expected in ((n - 1, plain), (n, guided)):
        monkeypatch.setattr(insertion, "GUIDED_POINT_LIMIT", limit)
        placed = lpnn_placement(medium_capture, scores=scores, budget=0.2, guided=True, reference=field)
        np.testing.assert_array_equal(placed.indices, expected(count), err_msg=f"limit {limit}")
