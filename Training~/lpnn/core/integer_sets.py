"""Sets of integers as sorted arrays, by sorting: the placement's hot loops ask for them every round.

    sorted_unique(values)                  # np.unique(values) for a 1-D integer array
    sorted_unique_first_inverse(values)    # np.unique(values, return_index=True, return_inverse=True)
    sorted_contains(values, sorted_set)    # np.isin(values, sorted_set) when sorted_set ascends

Why not np.unique: from NumPy 2.3 on it finds integers' distinct values by hashing, then sorts them; on this machine
(NumPy 2.4, x86-64) that is 10-45x slower than sorting the array and keeping each run's first value (430,000 int64:
166 ms against 3.6 ms; 30,000: 3.1 ms against 0.2 ms). The answers are np.unique's, element for element (tests).
Integers only: np.unique's handling of NaN (equal_nan) is not repeated here.
"""

from __future__ import annotations

import numpy as np


def _checked(values: np.ndarray) -> np.ndarray:
    array = np.asarray(values)
    if array.ndim != 1 or not (np.issubdtype(array.dtype, np.integer) or array.shape[0] == 0):
        raise ValueError(f"expected a 1-D integer array, got {array.dtype} {list(array.shape)}")
    return array


def sorted_unique(values: np.ndarray) -> np.ndarray:
    """The distinct values of a 1-D integer array, ascending (np.unique(values))."""
    ordered = np.sort(_checked(values))
    if ordered.shape[0] < 2:
        return ordered
    starts = np.empty(ordered.shape[0], dtype=bool)
    starts[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=starts[1:])
    return ordered[starts]


def sorted_unique_first_inverse(values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(distinct values ascending, the index of each one's first occurrence, each value's position among them):
    np.unique(values, return_index=True, return_inverse=True) of a 1-D integer array."""
    array = _checked(values)
    order = np.argsort(array, kind="stable")  # stable: a run's first entry is the value's first occurrence
    ordered = array[order]
    starts = np.ones(ordered.shape[0], dtype=bool)
    if ordered.shape[0] > 1:
        np.not_equal(ordered[1:], ordered[:-1], out=starts[1:])
    inverse = np.empty(array.shape[0], dtype=np.int64)
    inverse[order] = np.cumsum(starts) - 1
    return ordered[starts], order[starts].astype(np.int64), inverse


def sorted_contains(values: np.ndarray, sorted_set: np.ndarray) -> np.ndarray:
    """Whether each of `values` is in the ascending integer array `sorted_set` (np.isin's answer, by one binary search
    each instead of np.isin's sort of both: the set is sorted already where the placement asks)."""
    values = np.asarray(values)
    if sorted_set.shape[0] == 0:
        return np.zeros(values.shape, dtype=bool)
    at = np.minimum(np.searchsorted(sorted_set, values), sorted_set.shape[0] - 1)
    return sorted_set[at] == values
