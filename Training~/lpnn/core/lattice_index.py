"""Exact lattice id -> point index lookup for the evaluation grid (neighbours, index_of)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def _ranks(values: np.ndarray, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position of each query in sorted unique `values`, and whether it is present."""
    position = np.searchsorted(values, query)
    inside = position < values.shape[0]
    found = np.zeros(query.shape, dtype=bool)
    found[inside] = values[position[inside]] == query[inside]
    return position, found


@dataclass
class IdIndex:
    """Exact id -> index lookup for ids anywhere in int32 range.

    Each coordinate is replaced by its rank among the grid's distinct values on that axis, then each
    (k, j) row by its rank among the grid's distinct rows, giving keys row_rank * n_i + i_rank < N^2
    that increase in grid order: no overflow for any id range, vectorised lookups by binary search.
    The grid points' own ranks are kept, so a neighbour query only re-ranks the shifted axis.
    """

    values: tuple[np.ndarray, np.ndarray, np.ndarray]  # sorted distinct i, j, k
    point_ranks: tuple[np.ndarray, np.ndarray, np.ndarray]  # each point's rank per axis, (N,) int64
    row_values: np.ndarray  # sorted distinct row keys k_rank * n_j + j_rank
    point_rows: np.ndarray  # each point's row position in row_values, (N,) int64
    keys: np.ndarray  # (N,) strictly increasing

    @staticmethod
    def build(ids: np.ndarray) -> "IdIndex":
        columns = [np.ascontiguousarray(ids[:, axis], dtype=np.int64) for axis in range(3)]
        values = tuple(np.unique(column) for column in columns)
        ranks = tuple(np.searchsorted(v, column) for v, column in zip(values, columns))
        row = ranks[2] * np.int64(values[1].shape[0]) + ranks[1]
        row_values = np.unique(row)
        point_rows = np.searchsorted(row_values, row)
        keys = point_rows * np.int64(values[0].shape[0]) + ranks[0]
        return IdIndex(values, ranks, row_values, point_rows, keys)

    def _find(self, i_rank: np.ndarray, row: np.ndarray | None, found: np.ndarray,
              row_position: np.ndarray | None = None) -> np.ndarray:
        """Indices for rank-encoded queries; `row_position` given when the row is known to exist."""
        if row_position is None:
            row_position, row_found = _ranks(self.row_values, row)
            found &= row_found
        key = row_position * np.int64(self.values[0].shape[0]) + i_rank
        position = np.searchsorted(self.keys, key)
        found &= position < self.keys.shape[0]
        found[found] = self.keys[position[found]] == key[found]
        return np.where(found, position, np.int64(-1))

    def lookup(self, query: np.ndarray) -> np.ndarray:
        if self.keys.shape[0] == 0 or query.shape[0] == 0:
            return np.full(query.shape[0], -1, dtype=np.int64)
        ranked = [_ranks(self.values[axis], np.ascontiguousarray(query[:, axis])) for axis in range(3)]
        found = ranked[0][1] & ranked[1][1] & ranked[2][1]
        row = ranked[2][0] * np.int64(self.values[1].shape[0]) + ranked[1][0]
        return self._find(ranked[0][0], row, found)

    def shifted(self, column: np.ndarray, axis: int, offset: int) -> np.ndarray:
        """Indices of the grid's own points moved by offset along axis (`column` = their ids on it)."""
        if self.keys.shape[0] == 0:
            return np.zeros(0, dtype=np.int64)
        rank, found = _ranks(self.values[axis], column + np.int64(offset))
        ranks = list(self.point_ranks)
        ranks[axis] = rank
        if axis == 0:  # same row: its position is known
            return self._find(rank, None, found, row_position=self.point_rows)
        row = ranks[2] * np.int64(self.values[1].shape[0]) + ranks[1]
        return self._find(ranks[0], row, found)
