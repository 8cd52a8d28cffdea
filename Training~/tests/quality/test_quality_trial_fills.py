"""Batched refinement's trial refills (placement/trial_fills.py): the stars' refills must give exactly the tetrahedra a
global tetrahedralisation of the remaining probes gives, by gift wrapping or by the lifted link, and a refinement must
answer the same with them as with Qhull."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.metric import location
from lpnn.quality.metric.triangulation import INNER_BOUNDARY, assembled
from lpnn.quality.placement import batched_state, trial_fills
from lpnn.quality.placement.batched_refinement import batched_refinement, greedy_independent_set
from lpnn.quality.placement.batched_state import evaluate, trial_of, without
from lpnn.quality.placement.insertion import InsertionOrder
from lpnn.quality.placement.trial_fills import star_fills

from quality_support import MEDIUM_ROOM, room_capture


def _state(capture: Capture, count: int):
    field = ReferenceField.from_capture(capture)
    probes = InsertionOrder(field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)).selection()(count)
    return field, evaluate(field, probes)


def _candidates(field: ReferenceField, state, order: str, seed: int = 0) -> np.ndarray:
    """An independent set, its greedy order putting the volume's corners (hull vertices) first or last, or random."""
    corner = np.all((field.local == field.local.min(axis=0)) | (field.local == field.local.max(axis=0)), axis=1)
    probes = state.probes
    if order == "random":
        ordered = np.random.default_rng(seed).permutation(probes)
    else:
        ordered = probes[np.argsort(~corner[probes] if order == "corners first" else corner[probes], kind="stable")]
    rank = np.full(field.point_count, np.iinfo(np.int64).max, dtype=np.int64)
    rank[ordered] = np.arange(ordered.shape[0])
    return greedy_independent_set(probes, state.edges, rank)


def _qhull_tets(field: ReferenceField, state, candidates: np.ndarray) -> list[tuple[int, ...]]:
    fresh = evaluate(field, np.setdiff1d(state.probes, candidates))
    return sorted(map(tuple, np.sort(fresh.tets, axis=1).tolist()))


def _filled_tets(field: ReferenceField, state, candidates: np.ndarray, fills) -> list[tuple[int, ...]]:
    is_candidate = np.zeros(field.point_count, dtype=bool)
    is_candidate[candidates] = True
    kept = state.tets[~is_candidate[state.tets].any(axis=1)]
    return sorted(map(tuple, np.sort(np.concatenate([kept, fills.tets]), axis=1).tolist()))


@pytest.fixture(scope="module")
def lattice_state():
    """A room's grid (cospherical ties everywhere) and 145 probes of its insertion order: interior probes, probes on
    the hull's faces and the hull's corners. Not 150 or more (the order since the tie rule numbers tetrahedra by point
    index): its 150th point makes four probes collinear on a hull face (points 43, 131, 219 and 307; float32 rounding
    keeps slivers of them), a degenerate star whose refill and Qhull's `Qt` pick different slivers."""
    return _state(room_capture(3, MEDIUM_ROOM, 0.4), 145)


@pytest.mark.parametrize("order", ["corners first", "corners last", "random"])
def test_the_stars_refills_are_the_tetrahedralisation_of_the_remaining_probes(lattice_state, order: str) -> None:
    field, state = lattice_state
    candidates = _candidates(field, state, order)
    fills = star_fills(field, state, candidates)
    assert fills is not None
    assert set(fills.owner.tolist()) <= set(candidates.tolist())
    assert _filled_tets(field, state, candidates, fills) == _qhull_tets(field, state, candidates)
    # Every refill lies in its owner's star: its vertices are the owner's Delaunay neighbours.
    neighbours = {(int(a), int(b)) for a, b in state.edges.tolist()}
    for tet, owner in zip(fills.tets.tolist(), fills.owner.tolist()):
        assert all((owner, v) in neighbours for v in tet)


def test_hull_corners_are_among_the_candidates_and_most_are_wrapped_without_qhull(lattice_state, monkeypatch) -> None:
    """The volume's corners are hull vertices: their stars are gift-wrapped too (hole_wrap.HULL_VERTEX), the lifted link's
    Qhull call left to the holes the wrapping refuses (here 4 of the 8 corners: on the lattice a link point lies in a
    face's on-plane band), and the refills, both ways, are Qhull's tetrahedralisation."""
    field, state = lattice_state
    candidates = _candidates(field, state, "corners first")
    corner = np.all((field.local == field.local.min(axis=0)) | (field.local == field.local.max(axis=0)), axis=1)
    assert np.count_nonzero(corner[candidates]) >= 2
    lifted = []
    original = trial_fills._link_fill
    monkeypatch.setattr(trial_fills, "_link_fill", lambda *args: lifted.append(args[2]) or original(*args))
    fills = star_fills(field, state, candidates)
    corners = candidates[corner[candidates]]
    assert fills is not None and corners.shape[0] == 8
    # _link_fill gets positions in the probes; every one was a corner, and at least half the corners were wrapped.
    lifted_points = state.probes[np.asarray(lifted, dtype=np.int64)]
    assert set(lifted_points.tolist()) <= set(corners.tolist()) and len(lifted) <= 4
    assert set(corners.tolist()) <= set(fills.owner.tolist())
    assert _filled_tets(field, state, candidates, fills) == _qhull_tets(field, state, candidates)


def test_without_the_gift_wrapping_the_lifted_link_alone_gives_the_same_tetrahedra(lattice_state, monkeypatch) -> None:
    field, state = lattice_state
    candidates = _candidates(field, state, "random", seed=3)
    monkeypatch.setattr(trial_fills, "wrap_hole_runs", lambda local, tie, vertices, star_tets, star_start, on_hull: (
        np.zeros((0, 4), dtype=np.int64), np.zeros(len(vertices) + 1, dtype=np.int64),
        np.zeros(len(vertices), dtype=np.int64)))
    fills = star_fills(field, state, candidates)
    assert fills is not None
    assert _filled_tets(field, state, candidates, fills) == _qhull_tets(field, state, candidates)


def test_a_star_next_to_a_crack_falls_back_to_qhull_with_the_same_costs(lattice_state) -> None:
    """A crack (a face a dropped flat tetrahedron leaves without a neighbour) opens a star: no refill, and the trial
    tetrahedralises with Qhull instead, which gives the same costs."""
    field, state = lattice_state
    candidates = _candidates(field, state, "corners last")
    holds = np.isin(state.tets, candidates).any(axis=1)
    cracked = state.mesh.neighbours.copy()
    row = int(np.flatnonzero(holds)[0])
    cracked[row, int(np.argmax(cracked[row] >= 0))] = INNER_BOUNDARY
    opened = dataclasses.replace(state, mesh=dataclasses.replace(state.mesh, neighbours=cracked))
    assert star_fills(field, opened, candidates) is None
    filled = trial_of(field, state, candidates)
    fallback = trial_of(field, opened, candidates)
    assert filled.fills is not None and fallback.fills is None
    np.testing.assert_allclose(fallback.costs, filled.costs, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("mode", [{"tolerance": 0.05}, {"count": 40}])
def test_a_refinement_answers_the_same_with_refills_as_with_qhull(mode: dict, monkeypatch) -> None:
    capture = room_capture(5, MEDIUM_ROOM, 0.4)
    field = ReferenceField.from_capture(capture)
    seed = InsertionOrder(field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)).selection()(200)
    used = []
    monkeypatch.setattr(batched_state, "star_fills",
                        lambda *args: used.append(trial_fills.star_fills(*args)) or used[-1])
    filled = batched_refinement(field, seed, **mode)
    assert sum(fills is not None for fills in used) >= 0.9 * len(used) > 0  # the refills did the rounds
    monkeypatch.setattr(batched_state, "star_fills", lambda field, state, candidates: None)
    qhull = batched_refinement(field, seed, **mode)
    np.testing.assert_array_equal(filled.indices, qhull.indices)
    assert filled.rounds == qhull.rounds and filled.mean_error == pytest.approx(qhull.mean_error, rel=1e-12)


@pytest.mark.parametrize("order", ["corners first", "random"])
def test_the_mesh_derived_from_the_state_is_the_one_assembled_afresh_bit_for_bit(lattice_state, order: str) -> None:
    """batched_state.derived_mesh (triangulation.assembled_after_removal) keeps the kept tetrahedra's transforms and
    neighbours and matches only the open faces: every array must equal assembling the same tetrahedra from scratch."""
    field, state = lattice_state
    candidates = _candidates(field, state, order, seed=7)
    fills = star_fills(field, state, candidates)
    removed = np.zeros(field.point_count, dtype=bool)
    removed[candidates] = True
    remaining = state.probes[~removed[state.probes]]
    tets = np.concatenate([state.tets[~removed[state.tets].any(axis=1)], fills.tets])
    fresh = assembled(field.world[remaining], field.frame, np.searchsorted(remaining, tets))
    # The refills' positions in the state's probes (what derived_mesh takes) are their ids.
    np.testing.assert_array_equal(state.probes[fills.positions], fills.tets)
    derived = batched_state.derived_mesh(field, state, removed, fills.positions)
    assert derived is not None
    for name in ("tets", "neighbours", "inverse", "hull_faces", "hull_face_tets", "points", "world"):
        np.testing.assert_array_equal(getattr(derived, name), getattr(fresh, name), err_msg=name)
    # A face shared by three tetrahedra (a refill listed twice) is not a manifold: no mesh, the round uses Qhull.
    assert batched_state.derived_mesh(field, state, removed,
                                      np.concatenate([fills.positions, fills.positions[:1]])) is None
    # A star left partly empty (one refill missing) leaves a crack inside the hull: not a tetrahedralisation either.
    assert batched_state.derived_mesh(field, state, removed, fills.positions[1:]) is None
    # A refill naming a removed probe is no tetrahedron of the remaining ones.
    naming_a_removed = fills.positions.copy()
    naming_a_removed[0, 0] = np.searchsorted(state.probes, candidates[0])
    assert batched_state.derived_mesh(field, state, removed, naming_a_removed) is None


@pytest.mark.parametrize("order", ["corners first", "random"])
def test_a_trial_located_from_its_refills_is_the_one_located_by_the_coherent_walk(lattice_state, order: str) -> None:
    """trial_of starts each point's walk in the refill of the star it was in (batched_state.refill_starts): the start
    lies in that star's refill, the located point lands in the same star's refill where it stays inside the hull, and
    every array of the trial's evaluation is the coherent walk's."""
    field, state = lattice_state
    candidates = _candidates(field, state, order, seed=3)
    fills = star_fills(field, state, candidates)
    is_candidate = np.zeros(field.point_count, dtype=bool)
    is_candidate[candidates] = True
    mesh = batched_state.derived_mesh(field, state, is_candidate, fills.positions)
    assert mesh is not None
    attributed, star = batched_state.stencils_with_stars(state, candidates, state.owners)
    start = batched_state.refill_starts(mesh, fills.owner, star, state.probes)
    base = mesh.tets.shape[0] - fills.tets.shape[0]
    assert start.min() >= base  # every start is a refill
    # The star each point was in: itself if a candidate, else the candidate its stencil weighed.
    owners = state.owners[attributed]
    held = np.where(owners >= 0, is_candidate[np.maximum(owners, 0)], False)
    star_of = np.where(is_candidate[attributed], attributed, owners[np.arange(owners.shape[0]), np.argmax(held, axis=1)])
    np.testing.assert_array_equal(star, star_of)
    np.testing.assert_array_equal(fills.owner[start - base], star_of)
    owners, first = np.unique(fills.owner, return_index=True)  # the first refill of each star
    np.testing.assert_array_equal(start - base, first[np.searchsorted(owners, star_of)])
    # A star without a refill starts at the first refill; no refill at all, at the last tetrahedron.
    without_first = fills.owner != fills.owner[0]
    lacking = batched_state.refill_starts(mesh, fills.owner[without_first], star, state.probes)
    shifted = mesh.tets.shape[0] - np.count_nonzero(without_first)
    assert np.all(lacking[star == fills.owner[0]] == shifted) and np.any(star == fills.owner[0])
    np.testing.assert_array_equal(batched_state.refill_starts(mesh, fills.owner[:0], star, state.probes),
                                  np.full(star.shape[0], mesh.tets.shape[0] - 1))
    remaining = np.setdiff1d(state.probes, candidates)
    started = batched_state.evaluated_at(field, remaining, attributed, mesh=mesh, start=start)
    walked = batched_state.evaluated_at(field, remaining, attributed, mesh=mesh)
    for name in ("errors", "owners", "touched", "probes"):
        np.testing.assert_array_equal(getattr(started, name), getattr(walked, name), err_msg=name)
    located = location.locate_local(mesh, field.local[attributed], start=start)
    inside = ~located.outside  # outside the hull a cell is the owner of the hull triangle the point projects onto
    assert np.count_nonzero(inside) > 0.5 * attributed.shape[0]
    assert located.cell[inside].min() >= base
    np.testing.assert_array_equal(fills.owner[located.cell[inside] - base], star_of[inside])


def test_a_commit_s_refills_keep_their_positions_when_the_trial_s_and_new_ones_are_joined(lattice_state) -> None:
    """removal_fills joins the trial's refills and those made for removed probes the trial left out: their positions in
    the state's probes must stay aligned with their ids, or every commit's derived mesh would be refused (and Qhull
    would silently take over)."""
    field, state = lattice_state
    candidates = _candidates(field, state, "random", seed=11)
    trial = trial_of(field, state, candidates[: candidates.shape[0] // 2])
    assert trial.fills is not None
    joined = batched_state.removal_fills(field, state, candidates, trial)
    assert joined is not None and joined.tets.shape[0] > trial.fills.tets.shape[0]
    np.testing.assert_array_equal(state.probes[joined.positions], joined.tets)
    gone = np.zeros(field.point_count, dtype=bool)
    gone[candidates] = True
    refilling = gone[joined.owner]
    assert batched_state.derived_mesh(field, state, gone, joined.positions[refilling]) is not None


def test_a_hull_corner_of_three_neighbours_is_refilled_by_nothing_not_by_qhull(monkeypatch) -> None:
    """A hull vertex whose star is one tetrahedron (its link three probes) leaves the hull with its whole star when
    removed: its refill is empty. Qhull cannot tetrahedralise three probes, and before the empty refill the whole round
    went to Qhull (ctf_compromise's 30 % budget: 571 s instead of 60 s). The refills are still Qhull's
    tetrahedralisation of the remaining probes, the trial's costs the Qhull path's, and the committed state a fresh
    evaluation's."""
    capture = room_capture(5, (4.0, 2.5, 3.0), 0.5)
    field, state = _state(capture, 80)
    star = state.tets[np.any(state.tets == 53, axis=1)]  # probe 53, found by search: a corner of one tetrahedron
    assert star.shape[0] == 1
    rank = np.full(field.point_count, np.iinfo(np.int64).max, dtype=np.int64)
    rank[state.probes] = np.arange(state.probes.shape[0]) + 1
    rank[53] = 0
    candidates = greedy_independent_set(state.probes, state.edges, rank)
    assert 53 in candidates.tolist()
    fills = star_fills(field, state, candidates)
    assert fills is not None and 53 not in fills.owner.tolist()
    assert _filled_tets(field, state, candidates, fills) == _qhull_tets(field, state, candidates)
    filled = trial_of(field, state, candidates)
    monkeypatch.setattr(batched_state, "star_fills", lambda *args: None)
    qhull = trial_of(field, state, candidates)
    assert filled.fills is not None and qhull.fills is None
    np.testing.assert_allclose(filled.costs, qhull.costs, rtol=1e-9, atol=1e-12)
    monkeypatch.undo()
    for removed in (np.array([53]), candidates):  # the commit: the corner alone, and every candidate
        updated = without(field, state, removed, filled)
        fresh = evaluate(field, np.setdiff1d(state.probes, removed))
        np.testing.assert_array_equal(updated.probes, fresh.probes)
        np.testing.assert_allclose(updated.errors, fresh.errors, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(updated.edges, fresh.edges)
