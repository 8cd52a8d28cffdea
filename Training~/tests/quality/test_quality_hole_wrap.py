"""Gift-wrapped holes (hole_wrap.py) against re-tetrahedralising the whole set."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.placement.decimation import decimation_state
from lpnn.quality.placement.decimation.decimation_state import DecimationState
from lpnn.quality.placement.decimation.hole_wrap import HOLE_WEIGHT, HULL_VERTEX, MAX_LINK, wrap_hole_runs, wrap_holes
from lpnn.quality.metric.metric_kernel import PARALLEL_ROWS
from lpnn.quality.metric.metric import PRIMARY_METRIC, ReferenceField, placement_error
from lpnn.quality.placement.decimation.reference_fast import fast_decimation
from lpnn.quality.metric.triangulation import tetrahedralize

from quality_support import box_grid, linear_sh, room_capture


def _state(positions: np.ndarray) -> DecimationState:
    sh = linear_sh(positions) + 0.3 * np.sin(positions[:, :1] * 1.7) * np.cos(positions[:, 1:2] * 0.9)
    return DecimationState(ReferenceField.from_sh(positions, sh), PRIMARY_METRIC)


def _not_hull_vertices(state: DecimationState) -> list[int]:
    return [v for v in np.flatnonzero(state.alive).tolist() if not state.extreme[v]]


def _new_tetrahedra_without(state: DecimationState, v: int) -> set[tuple[int, ...]]:
    """Ground truth: tetrahedralise every probe but v and keep the tetrahedra that are new."""
    probes = np.flatnonzero(state.alive)
    probes = probes[probes != v]
    tets = probes[tetrahedralize(state.field.world[probes], state.field.frame).tets]
    before = set(map(tuple, np.sort(state.tets[:state.tet_count], axis=1).tolist()))
    return set(map(tuple, np.sort(tets, axis=1).tolist())) - before


@pytest.mark.parametrize("jitter", [0.0, 0.2])
def test_wrapped_holes_are_the_tetrahedra_a_full_retetrahedralisation_creates(jitter: float) -> None:
    # jitter 0: a lattice, where every hole is cospherical and only the tie-break decides, and the
    # probes on the box's faces lie exactly on the hull (their holes end on it).
    rng = np.random.default_rng(3)
    positions = box_grid(6, 5, 5, spacing=0.5) + rng.uniform(-jitter, jitter, (150, 3)) * 0.5
    state = _state(positions + np.array([2.0e4, -1.0e3, 5.0e2]))  # far from the origin
    vertices = _not_hull_vertices(state)
    on_hull = [bool(state.hull_degree[v]) for v in vertices]
    assert len(vertices) >= 30 and (sum(on_hull) >= 20 if jitter == 0.0 else True)
    holes = wrap_holes(state.local, state.tie, vertices, [state.tets[state._star_of(v)] for v in vertices], on_hull)
    for v, hole in zip(vertices, holes):
        assert hole is not None, v
        assert set(map(tuple, np.sort(hole, axis=1).tolist())) == _new_tetrahedra_without(state, v), v


@pytest.mark.parametrize("jitter, wrapped_at_least", [(0.0, 7), (0.2, 35)])
def test_a_hull_vertex_s_wrapped_hole_is_what_a_full_retetrahedralisation_creates(jitter: float,
                                                                                   wrapped_at_least: int) -> None:
    """HULL_VERTEX: the star's boundary faces may end on the new hull too, so the wrapping keeps only the part of the star
    the hull still holds. Each wrapped hole must be exactly the new tetrahedra; a hole it refuses (a lattice corner whose
    link has a point in a face's on-plane band) is left to the caller's Qhull."""
    rng = np.random.default_rng(3)
    positions = box_grid(6, 5, 5, spacing=0.5) + rng.uniform(-jitter, jitter, (150, 3)) * 0.5
    state = _state(positions + np.array([2.0e4, -1.0e3, 5.0e2]))  # far from the origin
    vertices = [v for v in np.flatnonzero(state.alive).tolist() if state.extreme[v]]
    stars = [state.tets[state._star_of(v)] for v in vertices]
    star_start = np.concatenate([[0], np.cumsum([star.shape[0] for star in stars])])
    out, out_start, counts = wrap_hole_runs(state.local, state.tie, np.asarray(vertices, dtype=np.int64),
                                            np.concatenate(stars), star_start, np.full(len(vertices), HULL_VERTEX))
    assert np.count_nonzero(counts > 0) >= wrapped_at_least
    for k, v in enumerate(vertices):
        if counts[k] > 0:
            hole = out[out_start[k]:out_start[k] + counts[k]]
            assert set(map(tuple, np.sort(hole, axis=1).tolist())) == _new_tetrahedra_without(state, v), v


def test_a_hole_too_large_to_wrap_is_left_to_qhull_and_the_decimation_stays_exact() -> None:
    # A centre point surrounded by more than MAX_LINK points on a sphere: its link is too large.
    rng = np.random.default_rng(5)
    directions = rng.normal(size=(MAX_LINK + 20, 3))
    sphere = directions / np.linalg.norm(directions, axis=1, keepdims=True)
    positions = np.concatenate([np.zeros((1, 3)), sphere, 1.6 * sphere[:12]])
    state = _state(positions)
    assert 0 in _not_hull_vertices(state) and not state.hull_degree[0]
    assert wrap_holes(state.local, state.tie, [0], [state.tets[state._star_of(0)]]) == [None]
    field = state.field
    fast = fast_decimation(field, workers=1)
    for count in (4, 20, 60, field.point_count - 1):
        assert fast.error_curve[count] == pytest.approx(placement_error(field, fast.prefix(count)).mean, rel=1e-9)


def test_the_decimation_is_the_same_with_every_hole_left_to_qhull(monkeypatch: pytest.MonkeyPatch) -> None:
    field = ReferenceField.from_capture(room_capture(2, (2.5, 2.0, 1.5), 0.4))
    wrapped = fast_decimation(field, workers=1)
    monkeypatch.setattr(decimation_state, "wrap_holes", lambda local, tie, vertices, stars, on_hull: [None] * len(stars))
    qhull = fast_decimation(field, workers=1)
    np.testing.assert_array_equal(wrapped.removed, qhull.removed)
    np.testing.assert_allclose(wrapped.error_curve, qhull.error_curve, rtol=1e-12, atol=1e-15)


def test_many_holes_wrapped_in_parallel_slices_are_each_hole_wrapped_alone() -> None:
    """wrap_hole_runs slices enough holes across threads (HOLE_WEIGHT): every hole's tetrahedra, in their order, are those
    of wrapping it alone, twice over (the same arrays: no state shared between holes or runs)."""
    rng = np.random.default_rng(11)
    positions = box_grid(6, 5, 5, spacing=0.5) + rng.uniform(-0.2, 0.2, (150, 3)) * 0.5
    state = _state(positions)
    vertices = _not_hull_vertices(state)
    repeats = -(-4 * PARALLEL_ROWS // (HOLE_WEIGHT * len(vertices)))  # enough holes for several parallel slices
    holes = np.asarray(vertices * repeats, dtype=np.int64)
    stars = [state.tets[state._star_of(int(v))] for v in holes]
    on_hull = np.asarray([bool(state.hull_degree[v]) for v in holes])
    star_start = np.concatenate([[0], np.cumsum([star.shape[0] for star in stars])])
    first = wrap_hole_runs(state.local, state.tie, holes, np.concatenate(stars), star_start, on_hull)
    again = wrap_hole_runs(state.local, state.tie, holes, np.concatenate(stars), star_start, on_hull)
    out, out_start, counts = first
    assert holes.shape[0] * HOLE_WEIGHT >= 4 * PARALLEL_ROWS and np.all(counts > 0)
    np.testing.assert_array_equal(counts, again[2])
    for k in range(holes.shape[0]):
        alone = wrap_holes(state.local, state.tie, [int(holes[k])], [stars[k]], [bool(on_hull[k])])[0]
        np.testing.assert_array_equal(out[out_start[k]:out_start[k] + counts[k]], alone)
        np.testing.assert_array_equal(again[0][out_start[k]:out_start[k] + counts[k]], alone)


def test_no_holes_wrap_to_empty_runs() -> None:
    state = _state(box_grid(3, 3, 3, spacing=0.5))
    out, out_start, counts = wrap_hole_runs(state.local, state.tie, np.zeros(0, dtype=np.int64),
                                            np.zeros((0, 4), dtype=np.int64), np.zeros(1, dtype=np.int64),
                                            np.zeros(0, dtype=bool))
    assert out.shape == (0, 4) and out_start.tolist() == [0] and counts.shape == (0,)
    assert wrap_holes(state.local, state.tie, [], []) == []
