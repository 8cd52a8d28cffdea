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
A point on a face, edge or vertex shared by several tetrahedra (its smallest coordinate within the inside tolerance of
0) belongs to the lowest-index one of them (quality.md §1 "Ties"), wherever the walk reached it: only such points take
the extra search (boundary_owner), so the walk costs the same elsewhere.
A face with no tetrahedron across is on the hull (HULL) or, rarely, a crack inside it (INNER_BOUNDARY, triangulation.py):
a walk leaving through a crack, or a tie's search reaching one, leaves the point to the brute force (tetrahedra lie
beyond a crack, unconnected to the walk's).
Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ...core.cache import use_project_cache_for_numba
from ...core.features_kernel import pairwise_sum
from .triangulation import HULL

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


@njit(cache=True, inline="always")
def row_error(interpolated, values, point, floor, metric, difference, magnitude):
    """The error of the row `interpolated` (width values) against values[point] (metric IRRADIANCE: sum|I - R| /
    (sum(|I| + |R|) + floor); SMAPE: the mean of |I - R| / (|I| + |R| + floor)) in the module text's arithmetic;
    difference and magnitude: the caller's scratch rows. Shared by the per-point loops here and insertion's
    (insertion_kernel.median_deviation); stencil_irradiance_errors writes it out beside its blend instead (its speed)."""
    width = values.shape[1]
    if metric == IRRADIANCE:
        for c in range(width):
            i, r = interpolated[c], values[point, c]
            difference[c] = abs(i - r)
            magnitude[c] = abs(i) + abs(r)
        return pairwise_sum(difference, width) / (pairwise_sum(magnitude, width) + floor)
    for c in range(width):
        i, r = interpolated[c], values[point, c]
        difference[c] = abs(i - r) / (abs(i) + abs(r) + floor)
    return pairwise_sum(difference, width) / width


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
            out[point] = row_error(interpolated, values, point, floor, metric, difference, magnitude)


@njit(cache=True, parallel=True)
def stencil_irradiance_errors(values, probes, vertices, weights, rows, floor, out):
    """stencil_errors(..., IRRADIANCE, out) for stencils of 4 probes, the same numbers: the blend is the same sum in
    the same order, written out per probe so that one pass over a point's values blends and compares them (1.5x
    faster than the general loop on 460,000 points of a 10^6-point level: the placement's most frequent call; blending
    into a row first and comparing it with row_error kept only a third of that gain)."""
    width = values.shape[1]
    chunks = chunk_count(rows.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(rows.shape[0], chunks, chunk)
        difference = np.empty(width)
        magnitude = np.empty(width)
        for m in range(lo, hi):
            point = rows[m]
            s0, s1, s2, s3 = probes[vertices[m, 0]], probes[vertices[m, 1]], probes[vertices[m, 2]], probes[vertices[m, 3]]
            w0, w1, w2, w3 = weights[m, 0], weights[m, 1], weights[m, 2], weights[m, 3]
            for c in range(width):
                i = (((0.0 + w0 * values[s0, c]) + w1 * values[s1, c]) + w2 * values[s2, c]) + w3 * values[s3, c]
                r = values[point, c]
                difference[c] = abs(i - r)
                magnitude[c] = abs(i) + abs(r)
            out[point] = pairwise_sum(difference, width) / (pairwise_sum(magnitude, width) + floor)


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


BOUNDARY_SEARCH_LIMIT = 512  # tetrahedra a tie's search may visit (an edge's ring is ~5-20): beyond, the brute force
# A tie's search crosses the faces the point lies within this of, and goes on through the tetrahedra it is inside within
# this: a candidate (inside within the tolerance) may be reached only through such a near one, where float32 lattices
# put points a few 1e-9 off an edge (ctf_compromise).
BOUNDARY_REACH = 1e-6


@njit(cache=True)
def _smallest(lam):
    return min(min(lam[0], lam[1]), min(lam[2], lam[3]))


@njit(cache=True)
def boundary_owner(points, tets, inverse, neighbours, qx, qy, qz, start, tolerance, visited, lam, trial):
    """quality.md §1 "Ties" for a point whose smallest coordinate in tetrahedron `start` lies in [-tolerance, tolerance]
    (on a face, edge or vertex it may share): its candidates are the tetrahedra it is inside within the tolerance. They
    are searched from `start` across the faces the point lies within BOUNDARY_REACH of, through every tetrahedron it is
    inside within BOUNDARY_REACH. The point belongs to the candidate it is clearly inside (smallest coordinate >
    tolerance: at most one) if there is one, else to the lowest-index candidate. Returns that tetrahedron with lam[0..3]
    the point's coordinates there (trial: scratch), or -1 when more than visited.shape[0] tetrahedra are near or the
    point lies within BOUNDARY_REACH of a crack (candidates beyond it are not reachable): the caller settles the point by
    brute force."""
    visited[0] = start
    count = 1
    lowest = start
    done = 0
    while done < count:
        t = visited[done]
        done += 1
        barycentric_into(points, tets, inverse, t, qx, qy, qz, lam)
        for face in range(4):
            u = neighbours[t, face]
            if lam[face] > BOUNDARY_REACH or u == HULL:
                continue
            if u < 0:  # a crack
                return -1
            seen = False
            for k in range(count):
                if visited[k] == u:
                    seen = True
                    break
            if seen:
                continue
            barycentric_into(points, tets, inverse, u, qx, qy, qz, trial)
            smallest = _smallest(trial)
            if smallest > tolerance:  # clearly inside u, hence inside no other tetrahedron
                for i in range(4):
                    lam[i] = trial[i]
                return u
            if smallest >= -BOUNDARY_REACH:
                if count == visited.shape[0]:
                    return -1
                visited[count] = u
                count += 1
                if smallest >= -tolerance:
                    lowest = min(lowest, u)
    barycentric_into(points, tets, inverse, lowest, qx, qy, qz, lam)
    return lowest


@njit(cache=True)
def nearest_centroids(points, tets, query, out):
    """out[q] = the tetrahedron whose centroid is nearest query[q] (the first of equals), one pass over the
    tetrahedra for all queries: a few walk starts without building a k-d tree over every centroid (location.py)."""
    best = np.full(query.shape[0], np.inf)
    for t in range(tets.shape[0]):
        cx = 0.25 * (points[tets[t, 0], 0] + points[tets[t, 1], 0] + points[tets[t, 2], 0] + points[tets[t, 3], 0])
        cy = 0.25 * (points[tets[t, 0], 1] + points[tets[t, 1], 1] + points[tets[t, 2], 1] + points[tets[t, 3], 1])
        cz = 0.25 * (points[tets[t, 0], 2] + points[tets[t, 1], 2] + points[tets[t, 2], 2] + points[tets[t, 3], 2])
        for q in range(query.shape[0]):
            dx, dy, dz = cx - query[q, 0], cy - query[q, 1], cz - query[q, 2]
            d = dx * dx + dy * dy + dz * dz
            if d < best[q]:
                best[q] = d
                out[q] = t


# Where metric_kernel.walk starts each point's walk (its `mode`).
WALK_FROM_EACH_START = 0  # start[m]
WALK_COHERENT = 1  # start[c] for the first point of slice c, then where the previous point's walk ended
WALK_WITHIN_RUNS = 2  # start[m] where it differs from start[m - 1] (or m begins a slice), else where the previous ended


@njit(cache=True, parallel=True)
def walk(points, tets, inverse, neighbours, query, start, step_limit, inside_tolerance, cell, resolved, coordinates,
         mode):
    """The visibility walk of location.py for each query point from its start tetrahedron (as `mode` says, one of the
    WALK_ constants: a coherent walk starts the first point of each slice of chunk_count's slices at start[slice]): cell[m]
    is the first tetrahedron reached whose barycentric coordinates are all >= -inside_tolerance, or, when its smallest
    is within inside_tolerance of 0, the tetrahedron the tie rule gives (boundary_owner), and coordinates[m] the
    coordinates there (-1 when the walk leaves through a hull face: resolved, outside), resolved[m] False after
    step_limit steps, through a crack, or at a tie with too many candidates or beside a crack (the brute force settles
    those). Slices in parallel: with the tie rule a point's cell does not depend on where its walk started, so neither
    on the slicing."""
    chunks = chunk_count(query.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        lam = np.empty(4)
        trial = np.empty(4)
        visited = np.empty(BOUNDARY_SEARCH_LIMIT, dtype=np.int64)
        current = start[chunk] if mode == WALK_COHERENT else 0
        for m in range(lo, hi):
            if mode == WALK_FROM_EACH_START or (mode == WALK_WITHIN_RUNS and (m == lo or start[m] != start[m - 1])):
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
                    if lam[worst] <= inside_tolerance:  # on the boundary: the tie rule's tetrahedron
                        owner = boundary_owner(points, tets, inverse, neighbours, qx, qy, qz, current,
                                               inside_tolerance, visited, lam, trial)
                        if owner < 0:
                            break
                        current = owner
                    cell[m] = current
                    resolved[m] = True
                    for i in range(4):
                        coordinates[m, i] = lam[i]
                    break
                step = neighbours[current, worst]
                if step == HULL:  # beyond that hull face's plane: outside the hull
                    resolved[m] = True
                    break
                if step < 0:  # beyond a crack: tetrahedra this walk cannot reach may hold the point
                    break
                current = step


@njit(cache=True, parallel=True)
def most_inside(points, tets, inverse, query, tolerance, best_cell, best_min):
    """For each query point, the tetrahedron of largest smallest barycentric coordinate (the first of equals, as
    numpy's argmax) and that coordinate, except that a point whose largest is within `tolerance` of 0 (on a face, edge
    or vertex) takes the lowest-index tetrahedron whose smallest is >= -tolerance (quality.md §1 "Ties"): location.py's
    brute force, in the walk's arithmetic; points in parallel."""
    chunks = chunk_count(query.shape[0] * max(1, tets.shape[0] // 64))
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        lam = np.empty(4)
        for m in range(lo, hi):
            qx, qy, qz = query[m, 0], query[m, 1], query[m, 2]
            best_cell[m] = 0
            best_min[m] = -np.inf
            lowest = -1
            for t in range(tets.shape[0]):
                barycentric_into(points, tets, inverse, t, qx, qy, qz, lam)
                smallest = _smallest(lam)
                if smallest > best_min[m] or t == 0:
                    best_cell[m] = t
                    best_min[m] = smallest
                if lowest < 0 and smallest >= -tolerance:
                    lowest = t
            if lowest >= 0 and best_min[m] <= tolerance:
                best_cell[m] = lowest


@njit(cache=True, parallel=True)
def kept_cells(points, tets, inverse, neighbours, query, tolerance, cell, walked, coordinates):
    """For each point known to lie in tetrahedron cell[m] (>= 0; insertion's incremental rounds,
    placement/insertion_state.py): its coordinates there when it is clearly inside it (smallest > tolerance: no other
    tetrahedron holds it, as a location would find), else, on its boundary, the tie rule's tetrahedron searched from
    there (boundary_owner) and the coordinates in it (walked[m] set either way); cell[m] = -1 when that search overflows
    (to be located). Points in parallel."""
    chunks = chunk_count(query.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        lam = np.empty(4)
        trial = np.empty(4)
        visited = np.empty(BOUNDARY_SEARCH_LIMIT, dtype=np.int64)
        for m in range(lo, hi):
            t = cell[m]
            if t < 0:
                continue
            qx, qy, qz = query[m, 0], query[m, 1], query[m, 2]
            barycentric_into(points, tets, inverse, t, qx, qy, qz, lam)
            if _smallest(lam) <= tolerance:
                t = boundary_owner(points, tets, inverse, neighbours, qx, qy, qz, t, tolerance, visited, lam, trial)
                cell[m] = t
                if t < 0:
                    continue
            walked[m] = True
            for i in range(4):
                coordinates[m, i] = lam[i]


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


@njit(cache=True, parallel=True)
def outside_stencils(tets, hull_faces, hull_face_tets, far, face, projected_weights, projected_anchor, vertices, weights,
                     cell, anchor):
    """Stencils of the points outside the hull (rows far[r]) from their hull projection (face[r], its weights and
    anchor): the hull triangle's corners with its weights, then the owning tetrahedron's fourth vertex with weight 0;
    the cell becomes that tetrahedron. One pass instead of numpy's (M, 4, 3) comparison and fancy-indexed copies
    (~0.1 s a round at 10^6 points). Rows in parallel."""
    chunks = chunk_count(far.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(far.shape[0], chunks, chunk)
        for r in range(lo, hi):
            m, f = far[r], face[r]
            owner = hull_face_tets[f]
            a, b, c = hull_faces[f, 0], hull_faces[f, 1], hull_faces[f, 2]
            fourth = tets[owner, 0]
            for i in range(4):
                v = tets[owner, i]
                if v != a and v != b and v != c:
                    fourth = v
            vertices[m, 0], vertices[m, 1], vertices[m, 2], vertices[m, 3] = a, b, c, fourth
            weights[m, 0], weights[m, 1], weights[m, 2] = (projected_weights[r, 0], projected_weights[r, 1],
                                                           projected_weights[r, 2])
            weights[m, 3] = 0.0
            cell[m] = owner
            anchor[m, 0], anchor[m, 1], anchor[m, 2] = (projected_anchor[r, 0], projected_anchor[r, 1],
                                                        projected_anchor[r, 2])
