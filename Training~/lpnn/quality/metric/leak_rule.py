"""The leak rule's decision (Documentation~/leaks.md), apart from the reports so the metric can apply it too: a point
leaks when a probe of weight > LEAK_MIN_WEIGHT in its stencil is hidden from it (the segment test of in-use.md)."""

from __future__ import annotations

from typing import Callable

import numpy as np

from ...core.features import Raycaster
from ...core.integer_sets import sorted_unique_first_inverse
from ...core.segments import segments_free
from .leak_rule_kernel import UNKNOWN, blocked_rows, remember, stencil_looked_up
from .metric_kernel import run_rows

# Stencil weights at or below this are round-off (a point on a shared face gets weights within 1e-9 of zero), not light.
LEAK_MIN_WEIGHT = 1e-6
# Partners remembered per point by SegmentVisibility: a stencil (4) and a trial's (batched_refinement.py) fit.
MEMO_SLOTS = 8


def stencil_leaks(points: np.ndarray, probe_positions: np.ndarray, vertices: np.ndarray, weights: np.ndarray,
                  raycaster: Raycaster) -> np.ndarray:
    """(M,) bool: the points (M, 3) whose stencil (vertices (M, 4) into probe_positions, weights (M, 4)) holds a
    probe of weight > LEAK_MIN_WEIGHT that the point cannot see. One batched cast for every weighing pair."""
    rows, columns = np.nonzero(np.asarray(weights) > LEAK_MIN_WEIGHT)
    starts = np.asarray(points, dtype=np.float64)[rows]
    ends = np.asarray(probe_positions, dtype=np.float64)[np.asarray(vertices)[rows, columns]]
    return _leaking_rows(np.asarray(points).shape[0], rows, lambda: segments_free(raycaster, starts, ends))


def _leaking_rows(count: int, rows: np.ndarray, free: Callable[[], np.ndarray]) -> np.ndarray:
    """(count,) bool: the rows of which some weighing pair (`rows`, one entry per pair) is not `free()`."""
    leaking = np.zeros(count, dtype=bool)
    if rows.shape[0]:
        leaking[rows[~free()]] = True
    return leaking


class SegmentVisibility:
    """Whether point i sees point j (the segment test of stencil_leaks, between two points of one field), remembered
    for each point's MEMO_SLOTS most recently tested partners, so a placement that re-evaluates the same stencils round
    after round (batched refinement: a point's new stencil usually shares 3 of its 4 probes with the old one) casts
    each segment about once. A segment's visibility never changes, so the answers are those of stencil_leaks; only
    the number of rays differs (`rays`, `asked`). One per placement call (placement/leak_aware.py): no global state,
    and the slots are replaced in a fixed order (per point, round robin), so the rays cast are deterministic too.

    Memory: 5 bytes a slot and 1 per point (41 bytes a point with 8 slots: 47 MB at 1.15 x 10^6 points)."""

    def __init__(self, raycaster: Raycaster, positions: np.ndarray, slots: int = MEMO_SLOTS) -> None:
        if not 4 <= int(slots) <= 127:
            raise ValueError(f"{slots!r} slots per point: at least a whole stencil (4), at most 127")
        self.raycaster = raycaster
        self.positions = np.asarray(positions, dtype=np.float64)
        count = self.positions.shape[0]
        self._partner = np.full((count, int(slots)), -1, dtype=np.int32)  # -1: an empty slot
        self._sees = np.zeros((count, int(slots)), dtype=bool)
        self._next = np.zeros(count, dtype=np.int8)  # the slot a point's next new partner overwrites
        self.asked = 0  # segments asked for, and of them cast: the memo's effect (tests, benchmarks)
        self.rays = 0

    def _cast(self, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
        """(S,) int8, 1 where the segment starts[k] -> ends[k] is free, 0 where blocked, for segments not remembered:
        one cast per distinct segment (a pair may be asked twice in one call), remembered in key order."""
        keys, first, back = sorted_unique_first_inverse(starts * self.positions.shape[0] + ends)
        new_starts, new_ends = starts[first], ends[first]
        seen = segments_free(self.raycaster, self.positions[new_starts], self.positions[new_ends])
        self.rays += int(keys.shape[0])
        remember(self._partner, self._sees, self._next, new_starts, new_ends.astype(np.int32), seen)
        return seen[back].astype(np.int8)

    def stencil_leaks(self, points: np.ndarray, probes: np.ndarray, vertices: np.ndarray,
                      weights: np.ndarray) -> np.ndarray:
        """stencil_leaks of the points `points` (indices into `positions`) under stencils whose vertices (M, 4) are
        positions in the point indices `probes`: the same answers, each segment cast once while it is remembered."""
        points = np.ascontiguousarray(points, dtype=np.int64)
        probes = np.ascontiguousarray(probes, dtype=np.int64)
        vertices = np.ascontiguousarray(vertices, dtype=np.int64)
        weights = np.ascontiguousarray(weights, dtype=np.float64)
        answers = np.empty(vertices.shape, dtype=np.int8)
        run_rows(stencil_looked_up, points.shape[0], self._partner, self._sees, points, probes, vertices, weights,
                 LEAK_MIN_WEIGHT, answers)
        rows, columns = np.nonzero(answers == UNKNOWN)
        if rows.shape[0]:  # the segments not remembered
            answers[rows, columns] = self._cast(points[rows], probes[vertices[rows, columns]])
        leaking = np.empty(points.shape[0], dtype=bool)
        self.asked += int(blocked_rows(answers, leaking))
        return leaking
