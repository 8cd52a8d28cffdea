"""Compiled per-cell candidate of insertion's rounds, the typical tetrahedron's deviations (insertion.py), and the points
a round carries over (insertion_state.py).

At 10^6 points a round's lexsort by (cell, -key, index) cost more than its point location; two passes find the rows
quality.md §5.1 asks for: per cell, its largest key, then the first row whose key is within `tie` of it (rows are in
ascending point index, so the first is the lowest index). tests/quality/test_quality_insertion.py compares a numpy
formulation.
The typical tetrahedron ranks every point by its metric error against the per-value median (POINT_ERRORS on (N, 42)
broadcast arrays: 2.5 s at 10^6 points, in its temporaries); median_deviation computes the same numbers row by row in
numpy's order of operations (metric_kernel's module text: a row sum is numpy's pairwise sum), bit-identical
(tests/quality/test_quality_insertion.py compares both metrics).
A round keeps every other point that it did not insert, with its tetrahedron if that survived and its coordinates: five
numpy passes over 10^6 points and their temporaries, carried_points' one (18 -> 6 ms a round on a validation capture of
1,151,667 points, ~75 rounds in a tolerance search); likewise the points walked again (broken tetrahedra, outside the
hull: ~40 %), gathered and their locations written back by rows_of and located_again instead of four fancy indexings.
Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ...core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit, prange  # noqa: E402  (after the cache folder is chosen)

from ..metric.metric_kernel import chunk_bounds, chunk_count, row_error  # noqa: E402

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


@njit(cache=True, parallel=True)
def median_deviation(values, median, floor, metric, out):
    """out[p] = POINT_ERRORS[metric](median, values[p]) for every row p (metric_kernel.row_error, the median in the
    interpolation's place); rows in parallel slices (metric_kernel.run_rows)."""
    width = values.shape[1]
    chunks = chunk_count(values.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(values.shape[0], chunks, chunk)
        difference = np.empty(width)
        magnitude = np.empty(width)
        for p in range(lo, hi):
            out[p] = row_error(median, values, p, floor, metric, difference, magnitude)


@njit(cache=True)
def carried_points(others, inside, is_added, survivor, local):
    """The points of `others` (ascending) not `is_added`, in order; for each, survivor[inside] where inside >= 0 (its
    tetrahedron's number in the new tetrahedralisation, -1 if it broke), else -1 (outside the hull); and its row of
    `local` (as numpy's others, np.where(...), np.ascontiguousarray(local[others]) give them)."""
    count = 0
    for m in range(others.shape[0]):
        if not is_added[others[m]]:
            count += 1
    kept = np.empty(count, dtype=np.int64)
    cell = np.empty(count, dtype=np.int64)
    coordinates = np.empty((count, local.shape[1]), dtype=local.dtype)
    j = 0
    for m in range(others.shape[0]):
        point = others[m]
        if is_added[point]:
            continue
        kept[j] = point
        cell[j] = survivor[inside[m]] if inside[m] >= 0 else -1
        for axis in range(local.shape[1]):
            coordinates[j, axis] = local[point, axis]
        j += 1
    return kept, cell, coordinates


@njit(cache=True)
def rows_of(source, rows):
    """source[rows] for a 2-D `source`, C-contiguous (numpy's np.ascontiguousarray(source[rows]))."""
    out = np.empty((rows.shape[0], source.shape[1]), dtype=source.dtype)
    for j in range(rows.shape[0]):
        for axis in range(source.shape[1]):
            out[j, axis] = source[rows[j], axis]
    return out


@njit(cache=True)
def located_again(rows, cell, walked, coordinates, found_cell, found_walked, found_coordinates):
    """cell[rows], walked[rows], coordinates[rows] = found_cell, found_walked, found_coordinates, in place."""
    for j in range(rows.shape[0]):
        row = rows[j]
        cell[row] = found_cell[j]
        walked[row] = found_walked[j]
        for k in range(coordinates.shape[1]):
            coordinates[row, k] = found_coordinates[j, k]
