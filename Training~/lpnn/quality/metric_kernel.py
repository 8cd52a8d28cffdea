"""Compiled loops of the placement error (metric.py) and of point location's walk (location.py).

At 10^6 evaluation points the numpy versions spend most of a tolerance search in temporaries: the
blend gathers (M, 4, 42) values, each error a few (M, 42) arrays, the walk (M, 3, 3) inverses per
step. These loops compute the same numbers point by point, in numpy's order of operations, so the
results are bit-identical (tests/quality/test_quality_metric_kernel.py compares both on every
metric and on walks through real tetrahedralisations):
- a blend is einsum's sum over the 4 stencil probes in stencil order, starting from 0;
- a row sum is numpy's pairwise sum (core/features_kernel.pairwise_sum);
- a barycentric step is einsum's rest_i = (a_0 + a_2) + a_1 with a_j = inverse[i, j] (q - v0)_j
  (its two-way unrolled sum of three products, measured: tests/quality/test_quality_metric_kernel.py),
  and lambda_0 = 1 - ((rest_0 + rest_1) + rest_2); the walk leaves through the first most negative
  coordinate, as numpy's argmin.
Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ..core.cache import use_project_cache_for_numba
from ..core.features_kernel import pairwise_sum

use_project_cache_for_numba()
import numba  # noqa: E402  (after the cache folder is chosen)
from numba import njit, prange  # noqa: E402

IRRADIANCE = 0
SMAPE = 1
PARALLEL_ROWS = 4096  # rows per parallel slice at least (fewer: one slice, no threads woken for nothing)
PARALLEL_CHUNKS = 64  # slices at most: enough to balance any core count here


def run_rows(kernel, work: int, *arguments) -> None:
    """Calls a parallel kernel (chunk_count's slices) on every core when `work` (rows, weighted as its chunk_count
    call weighs them) fills two slices, else on this thread alone: waking the other threads costs ~1 ms a call (measured
    with another process on the second core: 980 us against 38 us for 500 rows), more than small calls take, and a
    placement on a room makes thousands of them. Same numbers either way."""
    threads = numba.config.NUMBA_NUM_THREADS if work >= 2 * PARALLEL_ROWS else 1
    previous = numba.get_num_threads()
    numba.set_num_threads(threads)
    try:
        kernel(*arguments)
    finally:
        numba.set_num_threads(previous)


@njit(cache=True, inline="always")
def chunk_bounds(total, chunks, chunk):
    """Rows [lo, hi) of chunk `chunk` of `chunks` near-equal slices of `total` rows."""
    return total * chunk // chunks, total * (chunk + 1) // chunks


@njit(cache=True, inline="always")
def chunk_count(total):
    """Slices a parallel loop over `total` independent rows is cut into (a fixed function of the rows, so results
    never depend on the thread count; each point's numbers are computed alone anyway)."""
    return max(1, min(total // PARALLEL_ROWS, PARALLEL_CHUNKS))


@njit(cache=True, parallel=True)
def stencil_errors(values, probes, vertices, weights, rows, floor, metric, out):
    """out[rows[m]] = the error of point rows[m] against the blend of values[probes[vertices[m]]]
    with weights[m] (metric IRRADIANCE: sum|I - R| / (sum(|I| + |R|) + floor); SMAPE: the mean of
    |I - R| / (|I| + |R| + floor)), for every m; rows in parallel slices."""
    width = values.shape[1]
    chunks = chunk_count(rows.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(rows.shape[0], chunks, chunk)
        interpolated = np.empty(width)
        difference = np.empty(width)
        magnitude = np.empty(width)
        for m in range(lo, hi):
            point = rows[m]
            for c in range(width):
                interpolated[c] = 0.0
            for k in range(vertices.shape[1]):
                w = weights[m, k]
                source = probes[vertices[m, k]]
                for c in range(width):
                    interpolated[c] += w * values[source, c]
            for c in range(width):
                i, r = interpolated[c], values[point, c]
                if metric == IRRADIANCE:
                    difference[c] = abs(i - r)
                    magnitude[c] = abs(i) + abs(r)
                else:
                    difference[c] = abs(i - r) / (abs(i) + abs(r) + floor)
            if metric == IRRADIANCE:
                out[point] = pairwise_sum(difference, width) / (pairwise_sum(magnitude, width) + floor)
            else:
                out[point] = pairwise_sum(difference, width) / width


@njit(cache=True, inline="always")
def barycentric_into(points, tets, inverse, t, qx, qy, qz, lam):
    """lam[0..3] = the barycentric coordinates of (qx, qy, qz) in tetrahedron t, in `barycentric`'s arithmetic
    (module text): rest_i = (a_0 + a_2) + a_1, lambda_0 = 1 - ((rest_0 + rest_1) + rest_2)."""
    base = tets[t, 0]
    dx, dy, dz = qx - points[base, 0], qy - points[base, 1], qz - points[base, 2]
    total = 0.0
    for i in range(3):
        rest = (inverse[t, i, 0] * dx + inverse[t, i, 2] * dz) + inverse[t, i, 1] * dy
        lam[i + 1] = rest
        total += rest
    lam[0] = 1.0 - total


@njit(cache=True)
def walk(points, tets, inverse, neighbours, query, start, step_limit, inside_tolerance, cell, resolved, coordinates,
         coherent):
    """The visibility walk of location.py for each query point from its start tetrahedron (coherent:
    start[0] for the first point, then the tetrahedron where the previous point's walk ended): cell[m] is
    the first tetrahedron reached whose barycentric coordinates are all >= -inside_tolerance, and
    coordinates[m] those coordinates (-1 when the walk leaves through a hull face: resolved, outside),
    resolved[m] False after step_limit steps."""
    lam = np.empty(4)
    current = start[0] if query.shape[0] else 0
    for m in range(query.shape[0]):
        if not coherent:
            current = start[m]
        cell[m] = -1
        resolved[m] = False
        qx, qy, qz = query[m, 0], query[m, 1], query[m, 2]
        for _ in range(step_limit):
            barycentric_into(points, tets, inverse, current, qx, qy, qz, lam)
            worst = 0
            for i in range(1, 4):
                if lam[i] < lam[worst]:
                    worst = i
            if lam[worst] >= -inside_tolerance:
                cell[m] = current
                resolved[m] = True
                for i in range(4):
                    coordinates[m, i] = lam[i]
                break
            step = neighbours[current, worst]
            if step < 0:  # beyond that hull face's plane: outside the hull
                resolved[m] = True
                break
            current = step


@njit(cache=True, parallel=True)
def most_inside(points, tets, inverse, query, best_cell, best_min):
    """For each query point, the tetrahedron of largest smallest barycentric coordinate (the first of equals, as
    numpy's argmax) and that coordinate: location.py's brute force, in the walk's arithmetic; points in parallel."""
    chunks = chunk_count(query.shape[0] * max(1, tets.shape[0] // 64))
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        lam = np.empty(4)
        for m in range(lo, hi):
            qx, qy, qz = query[m, 0], query[m, 1], query[m, 2]
            best_cell[m] = 0
            best_min[m] = -np.inf
            for t in range(tets.shape[0]):
                barycentric_into(points, tets, inverse, t, qx, qy, qz, lam)
                smallest = min(min(lam[0], lam[1]), min(lam[2], lam[3]))
                if smallest > best_min[m] or t == 0:
                    best_cell[m] = t
                    best_min[m] = smallest


@njit(cache=True, parallel=True)
def inside_stencils(points, tets, inverse, query, cell, walked, coordinates, vertices, weights):
    """Stencils of the points inside a tetrahedron (cell[m] >= 0): its vertices and the barycentric coordinates
    clamped to >= 0 and divided by their sum ((l0 + l1) + l2) + l3, numpy's order; the coordinates are the walk's
    where walked[m], else computed here in `barycentric`'s arithmetic. Rows of other points are left untouched;
    points in parallel."""
    chunks = chunk_count(query.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        lam = np.empty(4)
        for m in range(lo, hi):
            t = cell[m]
            if t < 0:
                continue
            if walked[m]:
                for i in range(4):
                    lam[i] = coordinates[m, i]
            else:
                barycentric_into(points, tets, inverse, t, query[m, 0], query[m, 1], query[m, 2], lam)
            total = 0.0
            for i in range(4):
                if not lam[i] >= 0.0:  # np.clip(x, 0, None); NaN cannot reach here (the cell accepted the point)
                    lam[i] = 0.0
                total += lam[i]
            for i in range(4):
                vertices[m, i] = tets[t, i]
                weights[m, i] = lam[i] / total
