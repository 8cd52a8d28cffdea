"""segments_free and its compiled ray setup (core/segments.py, core/segments_kernel.py): the rays are numpy's formulas'
bit for bit, and a segment is blocked exactly when a wall lies on it, with either raycaster protocol."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.segments import segments_free
from lpnn.core.segments_kernel import unit_segments

WALL_X = 0.5  # the test raycasters' one surface: the plane x = WALL_X, both sides facing


class _Wall:
    """A raycaster of the plane x = WALL_X: the plain protocol (one maximum distance per call)."""

    def __init__(self) -> None:
        self.rays = 0

    def _hits(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        self.rays += origins.shape[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (WALL_X - origins[:, 0]) / directions[:, 0]
        return np.where(np.isfinite(t) & (t >= 0.0), t, np.inf)

    def cast(self, origins: np.ndarray, directions: np.ndarray, max_distance: float) -> tuple[np.ndarray, np.ndarray]:
        t = self._hits(origins, directions)
        t = np.where(t <= max_distance, t, np.inf)
        return t, np.tile([1.0, 0.0, 0.0], (origins.shape[0], 1))


class _WallToOwnEnds(_Wall):
    """The same plane, each ray cast to its own end (the Embree raycaster's protocol)."""

    def first_hit_distances(self, origins: np.ndarray, directions: np.ndarray, ends: np.ndarray) -> np.ndarray:
        t = self._hits(origins, directions)
        return np.where(t <= ends, t, np.inf)


def _segments(count: int, scale: float, offset: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    starts = offset + scale * rng.uniform(-1.0, 1.0, (count, 3))
    ends = offset + scale * rng.uniform(-1.0, 1.0, (count, 3))
    ends[::7] = starts[::7]  # zero-length segments among them
    return starts, ends


@pytest.mark.parametrize("scale, offset", [(1.0, 0.0), (1e-4, 0.0), (1e4, 0.0), (3.0, 1e6)])
def test_the_compiled_setup_gives_numpys_lengths_and_directions(scale: float, offset: float) -> None:
    starts, ends = _segments(5000, scale, offset, seed=1)
    offsets = ends - starts
    expected_lengths = np.sqrt(np.sum(offsets * offsets, axis=1))
    moving = expected_lengths > 0.0
    directions, lengths = np.empty_like(starts), np.empty(starts.shape[0])
    unit_segments(starts, ends, directions, lengths)
    np.testing.assert_array_equal(lengths, expected_lengths)
    np.testing.assert_array_equal(directions[moving], offsets[moving] / expected_lengths[moving, None])
    assert not directions[~moving].any() and (~moving).sum() > 0


@pytest.mark.parametrize("raycaster", [_Wall, _WallToOwnEnds])
def test_a_segment_is_free_unless_it_crosses_the_wall(raycaster) -> None:
    starts, ends = _segments(3000, 1.0, 0.5, seed=2)
    caster = raycaster()
    free = segments_free(caster, starts, ends)
    crosses = (np.minimum(starts[:, 0], ends[:, 0]) <= WALL_X) & (np.maximum(starts[:, 0], ends[:, 0]) >= WALL_X)
    moving = np.any(starts != ends, axis=1)
    np.testing.assert_array_equal(free, ~(crosses & moving))
    assert 0 < np.count_nonzero(~free) < free.shape[0]
    assert caster.rays == np.count_nonzero(moving)  # no ray for a segment of length 0


def test_segments_of_length_zero_cast_nothing() -> None:
    caster = _WallToOwnEnds()
    points = np.array([[0.0, 0.0, 0.0], [WALL_X, 1.0, 2.0]])
    np.testing.assert_array_equal(segments_free(caster, points, points), [True, True])
    assert caster.rays == 0


def test_no_segments_cast_nothing() -> None:
    caster = _Wall()
    assert segments_free(caster, np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)
    assert caster.rays == 0


def test_starts_and_ends_of_other_shapes_are_refused() -> None:
    with pytest.raises(ValueError, match="differ in shape"):
        segments_free(_Wall(), np.zeros((3, 3)), np.zeros((2, 3)))
