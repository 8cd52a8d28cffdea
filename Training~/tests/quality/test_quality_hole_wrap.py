"""Gift-wrapped holes (hole_wrap.py) against the lower hull of the lifted link (one Qhull call)."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.decimation_state import DecimationState
from lpnn.quality.hole_wrap import MAX_LINK, wrap_holes
from lpnn.quality.metric import PRIMARY_METRIC, ReferenceField, placement_error
from lpnn.quality.reference_fast import fast_decimation

from quality_support import box_grid, linear_sh


def _state(positions: np.ndarray) -> DecimationState:
    sh = linear_sh(positions) + 0.3 * np.sin(positions[:, :1] * 1.7) * np.cos(positions[:, 1:2] * 0.9)
    return DecimationState(ReferenceField.from_sh(positions, sh), PRIMARY_METRIC)


def _interior(state: DecimationState) -> list[int]:
    return [v for v in np.flatnonzero(state.alive).tolist() if not (state.extreme[v] or state.hull_degree[v])]


def _qhull_hole(state: DecimationState, v: int) -> set[tuple[int, ...]]:
    candidates, conflict = state._hole_candidates(v, state._star_of(v))
    return set(map(tuple, np.sort(candidates[conflict > 0.0], axis=1).tolist()))


@pytest.mark.parametrize("jitter", [0.0, 0.2])
def test_wrapped_holes_are_the_lower_hull_of_the_lifted_link(jitter: float) -> None:
    # jitter 0: a lattice, where every hole is cospherical and only the tie-break decides.
    rng = np.random.default_rng(3)
    positions = box_grid(6, 5, 5, spacing=0.5) + rng.uniform(-jitter, jitter, (150, 3)) * 0.5
    state = _state(positions + np.array([2.0e4, -1.0e3, 5.0e2]))  # far from the origin
    vertices = _interior(state)
    assert len(vertices) >= 30
    holes = wrap_holes(state.local, state.tie, vertices, [state.tets[state._star_of(v)] for v in vertices])
    for v, hole in zip(vertices, holes):
        assert hole is not None, v
        assert set(map(tuple, np.sort(hole, axis=1).tolist())) == _qhull_hole(state, v), v


def test_a_hole_too_large_to_wrap_is_left_to_qhull_and_the_decimation_stays_exact() -> None:
    # A centre point surrounded by more than MAX_LINK points on a sphere: its link is too large.
    rng = np.random.default_rng(5)
    directions = rng.normal(size=(MAX_LINK + 20, 3))
    sphere = directions / np.linalg.norm(directions, axis=1, keepdims=True)
    positions = np.concatenate([np.zeros((1, 3)), sphere, 1.6 * sphere[:12]])
    state = _state(positions)
    assert 0 in _interior(state)
    assert wrap_holes(state.local, state.tie, [0], [state.tets[state._star_of(0)]]) == [None]
    field = state.field
    fast = fast_decimation(field, workers=1)
    for count in (4, 20, 60, field.point_count - 1):
        assert fast.error_curve[count] == pytest.approx(placement_error(field, fast.prefix(count)).mean, rel=1e-9)
