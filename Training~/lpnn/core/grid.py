"""Evaluation grid (Documentation~/grid.md): lattice points whose cell touches the union of boxes.

The lattice is anchored at the world origin: id (i, j, k) sits at (h*i, h*j, h*k); the grid keeps its points in
grid order (k, then j, then i) with an exact id -> index lookup. Mirrors the C# core (Lpnn.Probes.Core.Grid), file
for file: `grid_box.py` (GridBox), `box_coverage.py` (BoxCoverage: which points a box covers, row by row),
`grid_builder.py` (GridBuilder: build, count, cell-size suggestions), `lattice_index.py` (the id lookup), and
here the grid itself (EvaluationGrid), its error and the cell-size rules shared by all of them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InvalidInputError
from .lattice_index import IdIndex

ID_BOUND = 2**30  # |i|, |j|, |k| <= 2^30 so neighbour offsets never overflow int32
SIGNIFICANT_DIGITS = 3  # cell-size suggestions
# grid.md "Memory estimate": ids + positions + SH + score + label + id lookup + lighting cache; features add 4*F.
BYTES_PER_POINT_FIXED = 12 + 12 + 108 + 4 + 1 + 32 + 168
BYTES_PER_FEATURE = 4


class GridError(InvalidInputError):
    """The grid cannot be built as asked; the message names the bad value and what to change."""


def validate_cell_size(cell_size: float) -> float:
    try:
        h = float(cell_size)
    except (TypeError, ValueError) as exc:
        raise GridError(f"cell size {cell_size!r} is not a number; use a positive cell size such as 0.5") from exc
    if not (math.isfinite(h) and h > 0.0):
        raise GridError(f"cell size {cell_size!r} must be a finite number > 0; use a positive cell size such as 0.5")
    return h


def round_up_significant(value: float, digits: int = SIGNIFICANT_DIGITS) -> float:
    """`value` rounded up to `digits` significant digits, without binary noise (0.19, not 0.19000000000000003)
    and never below `value` (the C# core's InvariantFormat.RoundUpSignificant, step for step)."""
    if not (math.isfinite(value) and value > 0.0):
        return value
    magnitude = 10.0 ** (math.floor(math.log10(value)) - (digits - 1))
    rounded = math.ceil(value / magnitude) * magnitude
    trimmed = float(f"{rounded:.{digits}g}")
    return trimmed if trimmed >= value else rounded


@dataclass
class EvaluationGrid:
    """Grid points in grid order (k, then j, then i ascending); index = position in that order."""

    cell_size: float
    ids: np.ndarray  # (N, 3) int32
    _index: IdIndex | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.cell_size = validate_cell_size(self.cell_size)
        ids = np.asarray(self.ids)
        if ids.ndim != 2 or ids.shape[1] != 3:
            raise GridError(f"grid ids need shape (N, 3), got {list(ids.shape)}")
        if ids.shape[0] and (np.abs(ids.astype(np.int64)).max() > ID_BOUND):
            raise GridError(f"grid ids must stay within +-2^30 ({ID_BOUND:,})")
        self.ids = np.ascontiguousarray(ids, dtype=np.int32)
        wide = self.ids.astype(np.int64)
        if wide.shape[0] > 1:
            d = wide[1:] - wide[:-1]
            later = (d[:, 2] > 0) | ((d[:, 2] == 0) & ((d[:, 1] > 0) | ((d[:, 1] == 0) & (d[:, 0] > 0))))
            if not np.all(later):
                bad = int(np.flatnonzero(~later)[0]) + 1
                raise GridError(f"grid ids must be unique and in grid order (k, j, i); id {wide[bad].tolist()} at "
                                f"index {bad} follows {wide[bad - 1].tolist()}")

    @property
    def point_count(self) -> int:
        return int(self.ids.shape[0])

    @property
    def positions(self) -> np.ndarray:
        """(N, 3) float32 world positions h*id, computed in double."""
        return (self.ids.astype(np.float64) * self.cell_size).astype(np.float32)

    def _lookup(self) -> IdIndex:
        if self._index is None:
            self._index = IdIndex.build(self.ids)
        return self._index

    def index_of(self, ids: np.ndarray) -> np.ndarray:
        """Indices (M,) int64 of the points with these ids (M, 3); -1 where an id is not in the grid."""
        query = np.asarray(ids)
        if query.ndim != 2 or query.shape[1] != 3:
            raise GridError(f"index_of needs ids of shape (M, 3), got {list(query.shape)}")
        return self._lookup().lookup(np.asarray(query, dtype=np.int64))

    def neighbour(self, axis: int, offset: int) -> np.ndarray:
        """For every point, the index of the point at id + offset*e_axis, or -1. (N,) int64."""
        if axis not in (0, 1, 2):
            raise GridError(f"neighbour axis {axis!r} must be 0 (x), 1 (y) or 2 (z)")
        return self._lookup().shifted(np.ascontiguousarray(self.ids[:, axis], dtype=np.int64), axis, int(offset))

    def subset(self, mask: np.ndarray) -> "EvaluationGrid":
        """The points where `mask` (N,) is true, keeping grid order (e.g. dropping points inside walls)."""
        keep = np.asarray(mask)
        if keep.dtype != bool or keep.shape != (self.point_count,):
            raise GridError(f"subset needs a boolean mask of shape ({self.point_count},), got {keep.dtype} {list(keep.shape)}")
        if not np.any(keep):
            raise GridError(f"no evaluation point is left after filtering all {self.point_count:,} points")
        return EvaluationGrid(cell_size=self.cell_size, ids=self.ids[keep])

    @staticmethod
    def estimate_bytes(point_count: int, feature_count: int) -> int:
        """grid.md: count x (12 ids + 12 positions + 108 SH + 4F features + 4 score + 1 label + 32 hash)."""
        if point_count < 0 or feature_count < 0:
            raise GridError(f"estimate_bytes needs counts >= 0, got {point_count} points, {feature_count} features")
        return int(point_count) * (BYTES_PER_POINT_FIXED + BYTES_PER_FEATURE * int(feature_count))
