"""Labels from a ground-truth probe set (Documentation~/selection.md, "Labels"), O(points + probes).

A point is positive when at least one probe lies in its cell. Cells are half-open, [p - h/2, p + h/2)
per axis, so each probe belongs to exactly one cell: probe q maps to id floor(q/h + 0.5), looked up in
the grid's id index.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInputError
from .grid import EvaluationGrid

# Lattice coordinates beyond this cannot be grid ids (|id| <= 2^30); clipping keeps the int64
# conversion defined for probes arbitrarily far away.
_FAR_OUTSIDE = 2.0**40


class LabelError(InvalidInputError):
    """The probe positions cannot be used as labels; the message names the probe and the fix."""


@dataclass(frozen=True)
class LabelStats:
    probes_matched: int  # probes whose cell is a grid point
    probes_outside: int  # probes whose cell is not a grid point (reported, not an error)
    positive_points: int  # grid points with at least one probe in their cell


def probe_lattice_ids(probe_positions: np.ndarray, cell_size: float) -> np.ndarray:
    """floor(q/h + 0.5) per axis, (P, 3) int64 (clipped far outside the +-2^30 id range)."""
    q = np.asarray(probe_positions, dtype=np.float64)
    if q.ndim != 2 or q.shape[1] != 3:
        raise LabelError(f"probe positions need shape (P, 3), got {list(q.shape)}")
    bad = np.flatnonzero(~np.all(np.isfinite(q), axis=1))
    if bad.shape[0]:
        first = int(bad[0])
        raise LabelError(f"probe {first} has a non-finite position {q[first].tolist()} ({bad.shape[0]:,} of "
                         f"{q.shape[0]:,} probes are bad); fix or remove those probes and label again")
    lattice = np.floor(q / cell_size + 0.5)
    return np.clip(lattice, -_FAR_OUTSIDE, _FAR_OUTSIDE).astype(np.int64)


def labels_from_probes(grid: EvaluationGrid, probe_positions: np.ndarray) -> tuple[np.ndarray, LabelStats]:
    """labels (N,) uint8 (1 = a probe lies in the point's cell) and counts of matched/outside probes."""
    found = grid.index_of(probe_lattice_ids(probe_positions, grid.cell_size))
    matched = found[found >= 0]
    labels = np.zeros(grid.point_count, dtype=np.uint8)
    labels[matched] = 1
    stats = LabelStats(probes_matched=int(matched.shape[0]), probes_outside=int(found.shape[0] - matched.shape[0]),
                       positive_points=int(np.count_nonzero(labels)))
    return labels, stats
