"""Compiled per-cell candidate of insertion's rounds (insertion.py).

At 10^6 points a round's lexsort by (cell, -key, index) cost more than its point location; two passes find the rows
quality.md §5.1 asks for: per cell, its largest key, then the first row whose key is within `tie` of it (rows are in
ascending point index, so the first is the lowest index). tests/quality/test_quality_insertion.py compares a numpy
formulation.
Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ...core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit  # noqa: E402  (after the cache folder is chosen)

# Errors (and guided keys, and cell sums) within this of each other count as equal, ties going to the lower point index
# (quality.md §5.1; leak_aware.leak_repaired's per-cell choice too): two languages (or two summation orders) compute
# equal errors a few ulps apart, ~1e-16 (sums of 10^5 errors ~1e-11); errors that differ by less than this are equally
# good to fix. Here, not in insertion.py, so that leak_aware.py can use it without importing insertion's state.
TIE = 1e-9


@njit(cache=True)
def first_per_cell(cell, key, cell_count, tie):
    """Rows (ascending cell) holding each present cell's candidate: the first row whose key is >= the cell's largest
    key - tie. Cells are in [0, cell_count): the callers locate every point (a cell of -1 would index the last cell)."""
    largest = np.full(cell_count, -np.inf)
    for m in range(cell.shape[0]):
        largest[cell[m]] = max(largest[cell[m]], key[m])
    best = np.full(cell_count, -1, dtype=np.int64)
    for m in range(cell.shape[0]):
        c = cell[m]
        if best[c] < 0 and key[m] >= largest[c] - tie:
            best[c] = m
    count = 0
    for c in range(cell_count):
        if best[c] >= 0:
            count += 1
    rows = np.empty(count, dtype=np.int64)
    count = 0
    for c in range(cell_count):
        if best[c] >= 0:
            rows[count] = best[c]
            count += 1
    return rows
