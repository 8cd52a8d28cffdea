"""Gift-wrapped holes (hole_wrap.py) against re-tetrahedralising the whole set."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.placement.decimation import decimation_state
from lpnn.quality.placement.decimation.decimation_state import DecimationState
from lpnn.quality.placement.decimation.hole_wrap import MAX_LINK, wrap_holes
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
