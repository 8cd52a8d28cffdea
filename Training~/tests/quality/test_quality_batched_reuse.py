"""Batched refinement keeps the fresh costs of probes off the boundary instead of re-measuring them (batched_refinement.py
step 2, batched_state.boundary_vertices / removal_fills): the same answers as re-measuring every cost, the kept costs
equal to a new trial's, and a commit of probes the round's trial left out equal to a fresh evaluation."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.placement import batched_refinement as batched_refinement_module
from lpnn.quality.placement.batched_refinement import batched_refinement, greedy_independent_set
from lpnn.quality.placement.batched_state import (boundary_vertices, evaluate, removal_fills, trial_of,
                                                  without)
from lpnn.quality.placement.insertion import InsertionOrder

from quality_support import box_grid


def _state(capture: Capture, count: int):
    field = ReferenceField.from_capture(capture)
    probes = InsertionOrder(field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)).selection()(count)
    return field, evaluate(field, probes)


def _independent(state, field: ReferenceField) -> np.ndarray:
    rank = np.full(field.point_count, np.iinfo(np.int64).max, dtype=np.int64)
    rank[state.probes] = np.arange(state.probes.shape[0])
    return greedy_independent_set(state.probes, state.edges, rank)


def test_the_boundary_is_every_probe_on_a_hull_face() -> None:
    positions = box_grid(3, 3, 3, 1.0)
    field = ReferenceField.from_sh(positions, np.random.default_rng(1).uniform(0.2, 1.0, (positions.shape[0], 27)))
    state = evaluate(field, np.arange(positions.shape[0]))
    centre = np.flatnonzero(np.all(positions == positions.mean(axis=0), axis=1))
    assert centre.shape[0] == 1
    expected = np.ones(positions.shape[0], dtype=bool)
    expected[centre] = False
    np.testing.assert_array_equal(boundary_vertices(state), expected)


def test_a_kept_fresh_cost_off_the_boundary_is_what_a_new_trial_measures(medium_capture: Capture) -> None:
    field, state = _state(medium_capture, 145)
    candidates = _independent(state, field)
    first = dict(zip(candidates.tolist(), trial_of(field, state, candidates).costs.tolist()))
    removed = candidates[:12]
    after = without(field, state, removed)
    gone = np.zeros(field.point_count, dtype=bool)
    gone[removed] = True
    stale = np.zeros(field.point_count, dtype=bool)
    stale[state.edges[gone[state.edges[:, 0]], 1]] = True  # batched_refinement's step 4
    fresh = candidates[~gone[candidates] & ~stale[candidates] & ~boundary_vertices(after)[candidates]]
    assert fresh.shape[0] >= 5, "too few fresh interior candidates to tell"
    again = trial_of(field, after, fresh).costs
    np.testing.assert_allclose(again, [first[c] for c in fresh.tolist()], rtol=1e-9, atol=1e-12)


def test_a_commit_of_probes_the_trial_left_out_equals_a_fresh_evaluation(medium_capture: Capture) -> None:
    field, state = _state(medium_capture, 145)
    candidates = _independent(state, field)
    half = candidates.shape[0] // 2
    trial = trial_of(field, state, candidates[:half])
    removed = np.concatenate([candidates[:5], candidates[half:half + 5]])
    assert removal_fills(field, state, removed, trial) is not None, "the refills made for the rest"
    fresh = evaluate(field, np.setdiff1d(state.probes, removed))
    for updated in (without(field, state, removed, trial), without(field, state, removed, None)):
        np.testing.assert_array_equal(updated.probes, fresh.probes)
        np.testing.assert_allclose(updated.errors, fresh.errors, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(updated.edges, fresh.edges)


def _half_even_field() -> ReferenceField:
    """Half the room evenly lit (removal costs tie at 0 up to rounding), half varied."""
    positions = box_grid(10, 6, 5, 0.5)
    rng = np.random.default_rng(3)
    sh = np.where(positions[:, :1] < 2.25, 0.7, rng.uniform(0.2, 1.0, (positions.shape[0], 27)))
    return ReferenceField.from_sh(positions, sh)


@pytest.mark.parametrize("goal", [{"count": 60}, {"tolerance": 0.08}, {"tolerance": 0.03}])
@pytest.mark.parametrize("which", ["medium room", "half even"])
def test_keeping_fresh_costs_gives_the_answer_of_re_measuring_every_cost(
        monkeypatch: pytest.MonkeyPatch, medium_capture: Capture, goal: dict, which: str) -> None:
    if which == "medium room":
        field = ReferenceField.from_capture(medium_capture)
        seed = InsertionOrder(field, EvaluationGrid(cell_size=medium_capture.cell_size,
                                                    ids=medium_capture.ids)).selection()(400)
    else:
        field = _half_even_field()
        seed = np.arange(field.point_count)
    measured, round_candidates = [], []
    original_trial, original_set = batched_refinement_module.trial_of, batched_refinement_module.greedy_independent_set

    def independent(*args):
        round_candidates.append(original_set(*args))
        return round_candidates[-1]

    def counted(field_, state, candidates):
        # every boundary probe among the round's candidates is measured again (boundary_vertices' text)
        boundary = round_candidates[-1][boundary_vertices(state)[round_candidates[-1]]]
        assert np.isin(boundary, candidates).all()
        measured.append(candidates.shape[0])
        return original_trial(field_, state, candidates)

    monkeypatch.setattr(batched_refinement_module, "greedy_independent_set", independent)
    monkeypatch.setattr(batched_refinement_module, "trial_of", counted)
    kept = batched_refinement(field, seed, **goal)
    spared = sum(measured)
    measured.clear()
    monkeypatch.setattr(batched_refinement_module, "REMEASURE_FRESH_COSTS", True)
    every = batched_refinement(field, seed, **goal)
    np.testing.assert_array_equal(kept.indices, every.indices)
    assert kept.rounds == every.rounds and kept.stop_reason == every.stop_reason
    assert kept.mean_error == pytest.approx(every.mean_error, rel=1e-12)
    assert spared < sum(measured), "no fresh cost was kept: the test does not test the rule"
