"""Compiled nearest-triangle loop of hull projection (hull_projection.py).

Points outside the probes' hull are most of a volume during insertion's first rounds: at 10^6 points the numpy
version spent most of a placement in (M, k, 3) temporaries. This loop computes, point by point and candidate by
candidate, the numbers of Ericson's closest-point-on-triangle (Real-Time Collision Detection §5.1.5) in numpy's
order of operations, so that results are bit-identical to the numpy formulation it replaced
(tests/quality/test_quality_hull_kernel.py keeps that formulation and compares both):
- a 3-component dot product is numpy's sum over the last axis, ((x0 y0 + x1 y1) + x2 y2);
- the region tests are taken in np.select's order (vertex a, vertex b, edge ab, vertex c, edge ac, edge bc, face);
- the anchor is einsum's sum over the three corners, and the distance sqrt((dx^2 + dy^2) + dz^2);
- the best candidate is the first of the smallest distances (numpy's argmin).
settle_ties applies the tie rule of quality.md §1 to those answers (hull_projection.lowest_owner_at_ties); the test
file compares it with a numpy formulation over every hull triangle.
Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import math

import numpy as np

from ...core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit, prange  # noqa: E402  (after the cache folder is chosen)

from .metric_kernel import chunk_bounds, chunk_count  # noqa: E402
from .removal_kernel import sorted3  # noqa: E402


@njit(cache=True)
def _ratio(numerator, denominator):
    return numerator / (denominator if denominator != 0.0 else 1.0)


@njit(cache=True)
def _dot(x0, x1, x2, y0, y1, y2):
    return (x0 * y0 + x1 * y1) + x2 * y2


@njit(cache=True)
def closest_weights(px, py, pz, a, b, c, out):
    """out[0..2] = barycentric weights of the point of triangle (a, b, c) (each (3,)) closest to p."""
    abx, aby, abz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    acx, acy, acz = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    apx, apy, apz = px - a[0], py - a[1], pz - a[2]
    d1 = _dot(abx, aby, abz, apx, apy, apz)
    d2 = _dot(acx, acy, acz, apx, apy, apz)
    bpx, bpy, bpz = px - b[0], py - b[1], pz - b[2]
    d3 = _dot(abx, aby, abz, bpx, bpy, bpz)
    d4 = _dot(acx, acy, acz, bpx, bpy, bpz)
    cpx, cpy, cpz = px - c[0], py - c[1], pz - c[2]
    d5 = _dot(abx, aby, abz, cpx, cpy, cpz)
    d6 = _dot(acx, acy, acz, cpx, cpy, cpz)
    vc = d1 * d4 - d3 * d2
    vb = d5 * d2 - d1 * d6
    va = d3 * d6 - d5 * d4
    if d1 <= 0.0 and d2 <= 0.0:
        u, v, w = 1.0, 0.0, 0.0
    elif d3 >= 0.0 and d4 <= d3:
        u, v, w = 0.0, 1.0, 0.0
    elif vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = _ratio(d1, d1 - d3)
        u, v, w = 1.0 - t, t, 0.0
    elif d6 >= 0.0 and d5 <= d6:
        u, v, w = 0.0, 0.0, 1.0
    elif vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = _ratio(d2, d2 - d6)
        u, v, w = 1.0 - t, 0.0, t
    elif va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        t = _ratio(d4 - d3, (d4 - d3) + (d5 - d6))
        u, v, w = 0.0, 1.0 - t, t
    else:
        total = va + vb + vc
        v = _ratio(vb, total)
        w = _ratio(vc, total)
        u = 1.0 - v - w
    u, v, w = max(u, 0.0), max(v, 0.0), max(w, 0.0)
    total = (u + v) + w
    out[0], out[1], out[2] = u / total, v / total, w / total


@njit(cache=True)
def _point_and_distance(px, py, pz, a, b, c, w):
    """The point w[0] a + w[1] b + w[2] c (einsum's order) and its distance to p."""
    x = (w[0] * a[0] + w[1] * b[0]) + w[2] * c[0]
    y = (w[0] * a[1] + w[1] * b[1]) + w[2] * c[1]
    z = (w[0] * a[2] + w[1] * b[2]) + w[2] * c[2]
    dx, dy, dz = x - px, y - py, z - pz
    return x, y, z, math.sqrt((dx * dx + dy * dy) + dz * dz)


@njit(cache=True, parallel=True)
def nearest_among(query, corners, candidates, allowed, use_allowed, face, weights, anchor, distance):
    """For each point m: the candidate triangle candidates[m, j] (among those allowed) whose closest point is nearest,
    its weights, that point and the distance (distance inf when none is allowed; face -1 when there are none);
    points in parallel slices (metric_kernel.chunk_count)."""
    chunks = chunk_count(query.shape[0] * max(1, candidates.shape[1] // 8))
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        trial = np.empty(3)
        for m in range(lo, hi):
            px, py, pz = query[m, 0], query[m, 1], query[m, 2]
            face[m] = -1
            distance[m] = np.inf
            weights[m, 0] = weights[m, 1] = weights[m, 2] = 0.0
            anchor[m, 0] = anchor[m, 1] = anchor[m, 2] = 0.0
            for j in range(candidates.shape[1]):
                f = candidates[m, j]
                a, b, c = corners[f, 0], corners[f, 1], corners[f, 2]
                closest_weights(px, py, pz, a, b, c, trial)
                x, y, z, d = _point_and_distance(px, py, pz, a, b, c, trial)
                if use_allowed and not allowed[f]:
                    d = np.inf
                if d < distance[m] or face[m] < 0:
                    face[m] = f
                    distance[m] = d
                    weights[m, 0], weights[m, 1], weights[m, 2] = trial[0], trial[1], trial[2]
                    anchor[m, 0], anchor[m, 1], anchor[m, 2] = x, y, z


@njit(cache=True, parallel=True)
def certified(query, anchor, distance, vertices, tolerance, out):
    """out[m]: (q - p).(x - p) <= tolerance x |q - p| + 1e-15 for every hull vertex x (p = anchor[m], a finite
    distance): p is the nearest point of the hull to q. Stops at the first vertex beyond; points in parallel. (The
    slack is thousands of times the rounding of these sums, so their order of operations decides nothing.)"""
    chunks = chunk_count(query.shape[0] * max(1, vertices.shape[0] // 8))
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        for m in range(lo, hi):
            if not np.isfinite(distance[m]):
                out[m] = False
                continue
            ax, ay, az = anchor[m, 0], anchor[m, 1], anchor[m, 2]
            rx, ry, rz = query[m, 0] - ax, query[m, 1] - ay, query[m, 2] - az
            base = (rx * ax + ry * ay) + rz * az
            limit = tolerance * distance[m] + 1e-15
            ok = True
            for v in range(vertices.shape[0]):
                if ((rx * vertices[v, 0] + ry * vertices[v, 1]) + rz * vertices[v, 2]) - base > limit:
                    ok = False
                    break
            out[m] = ok


@njit(cache=True)
def _before(faces, owners, f, g):
    """The tie rule's order of hull triangles: lower owning tetrahedron, then smaller sorted corners."""
    if owners[f] != owners[g]:
        return owners[f] < owners[g]
    x0, x1, x2 = sorted3(faces[f, 0], faces[f, 1], faces[f, 2])
    y0, y1, y2 = sorted3(faces[g, 0], faces[g, 1], faces[g, 2])
    if x0 != y0:
        return x0 < y0
    if x1 != y1:
        return x1 < y1
    return x2 < y2


@njit(cache=True, parallel=True)
def settle_ties(points, faces, owners, faces_at_start, faces_at, edge_over_area, query, reach, tie, face, weights,
                anchor, distance):
    """quality.md §1 "Ties" outside the hull, in place, for points whose nearest hull point (face, weights, anchor,
    distance: hull_projection's answer) lies within reach x distance of one of its triangle's edge lines (weight x
    altitude, the altitude being 1 / edge_over_area[face, corner]: an upper bound of its distance to the boundary; no
    other point can tie). The tie set: the hull triangles at the nearest triangle's corners (faces_at[faces_at_start[v] ..
    faces_at_start[v + 1]]) whose distance is within a relative `tie` of the nearest. The point takes the one owned by
    the lowest tetrahedron (then smallest sorted corners), with its nearest point snapped onto the hull edge or vertex
    every tied triangle holds (the exact nearest point lies there; the edge's ends ordered by probe index), so the
    weights do not depend on which of them is chosen; with one triangle, or none held by all, its own weights. Points
    in parallel."""
    chunks = chunk_count(query.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(query.shape[0], chunks, chunk)
        trial = np.empty(3)
        held = np.empty(3, dtype=np.bool_)  # per slice, not per point (~10^6 points a round in the first rounds)
        for m in range(lo, hi):
            f0 = face[m]
            near = reach * distance[m]
            if not (weights[m, 0] <= near * edge_over_area[f0, 0] or weights[m, 1] <= near * edge_over_area[f0, 1]
                    or weights[m, 2] <= near * edge_over_area[f0, 2]):
                continue
            px, py, pz = query[m, 0], query[m, 1], query[m, 2]
            limit = distance[m] * (1.0 + tie)
            chosen = f0
            held[0] = held[1] = held[2] = True  # which of f0's corners every tied triangle holds
            for k in range(3):
                v = faces[f0, k]
                for j in range(faces_at_start[v], faces_at_start[v + 1]):
                    f = faces_at[j]
                    a, b, c = points[faces[f, 0]], points[faces[f, 1]], points[faces[f, 2]]
                    closest_weights(px, py, pz, a, b, c, trial)
                    if _point_and_distance(px, py, pz, a, b, c, trial)[3] > limit:
                        continue
                    for corner in range(3):
                        if faces[f0, corner] != faces[f, 0] and faces[f0, corner] != faces[f, 1] and \
                                faces[f0, corner] != faces[f, 2]:
                            held[corner] = False
                    if _before(faces, owners, f, chosen):
                        chosen = f
            common = 0
            for corner in range(3):
                if held[corner]:
                    common += 1
            if common == 3:
                continue  # no tie: no other triangle holds all of f0's corners
            a, b, c = points[faces[chosen, 0]], points[faces[chosen, 1]], points[faces[chosen, 2]]
            closest_weights(px, py, pz, a, b, c, trial)
            if common == 1 or common == 2:
                # The corners of `chosen` on the common vertex or edge, that edge's ends by probe index.
                first, second = -1, -1
                for k in range(3):
                    for corner in range(3):
                        if held[corner] and faces[chosen, k] == faces[f0, corner]:
                            if first < 0:
                                first = k
                            else:
                                second = k
                trial[0] = trial[1] = trial[2] = 0.0
                if second < 0:
                    trial[first] = 1.0
                else:
                    if faces[chosen, second] < faces[chosen, first]:
                        first, second = second, first
                    s, e = points[faces[chosen, first]], points[faces[chosen, second]]
                    ex, ey, ez = e[0] - s[0], e[1] - s[1], e[2] - s[2]
                    t = _ratio(((px - s[0]) * ex + (py - s[1]) * ey) + (pz - s[2]) * ez, (ex * ex + ey * ey) + ez * ez)
                    t = min(max(t, 0.0), 1.0)
                    trial[first], trial[second] = 1.0 - t, t
            x, y, z, d = _point_and_distance(px, py, pz, a, b, c, trial)
            face[m] = chosen
            weights[m, 0], weights[m, 1], weights[m, 2] = trial[0], trial[1], trial[2]
            anchor[m, 0], anchor[m, 1], anchor[m, 2] = x, y, z
            distance[m] = d
