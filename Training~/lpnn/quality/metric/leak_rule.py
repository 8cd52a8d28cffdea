"""The leak rule's decision (Documentation~/leaks.md), apart from the reports so the metric can apply it too: a point
leaks when a probe of weight > LEAK_MIN_WEIGHT in its stencil is hidden from it (the segment test of in-use.md)."""

from __future__ import annotations

import numpy as np

from ...core.features import Raycaster
from ...core.segments import segments_free

# Stencil weights at or below this are round-off (a point on a shared face gets weights within 1e-9 of zero), not light.
LEAK_MIN_WEIGHT = 1e-6


def stencil_leaks(points: np.ndarray, probe_positions: np.ndarray, vertices: np.ndarray, weights: np.ndarray,
                  raycaster: Raycaster) -> np.ndarray:
    """(M,) bool: the points (M, 3) whose stencil (vertices (M, 4) into probe_positions, weights (M, 4)) holds a
    probe of weight > LEAK_MIN_WEIGHT that the point cannot see. One batched cast for every weighing pair."""
    rows, columns = np.nonzero(np.asarray(weights) > LEAK_MIN_WEIGHT)
    leaking = np.zeros(np.asarray(points).shape[0], dtype=bool)
    if rows.shape[0] == 0:
        return leaking
    starts = np.asarray(points, dtype=np.float64)[rows]
    ends = np.asarray(probe_positions, dtype=np.float64)[np.asarray(vertices)[rows, columns]]
    blocked = ~segments_free(raycaster, starts, ends)
    leaking[rows[blocked]] = True
    return leaking
