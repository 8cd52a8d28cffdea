"""Compiled passes of a tetrahedralisation after probes are removed (triangulation.assembled_after_removal,
placement/batched_state.derived_mesh); its face pairing and boundary listing serve every tetrahedralisation's adjacency
(triangulation._adjacency) too.

Batched refinement derives two meshes a round from the last one (~160 a placement on a 10^5-point level). As numpy
array expressions each took ~15 passes over every tetrahedron (the kept rows gathered, their vertices and neighbours
renumbered, every face's three vertices listed, the boundary searched, the vertices used and the cracks counted), ~12 ms
a mesh at 70,000 tetrahedra. These loops make the same integer arrays in one or two passes; only the faces a removal
opened are matched again (by the caller, with numpy's sort) and only the boundary's faces are listed. Pure data movement:
the arrays are those of the numpy expressions bit for bit (tests/quality/test_quality_removal_kernel.py).
Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ...core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit  # noqa: E402  (after the cache folder is chosen)

from .tet_geometry import OPPOSITE  # noqa: E402


@njit(cache=True)
def sorted3(a, b, c):
    """(a, b, c) in ascending order, without an array (hull_kernel.settle_ties runs this per point and candidate)."""
    if a > b:
        a, b = b, a
    if b > c:
        b, c = c, b
    if a > b:
        a, b = b, a
    return a, b, c


@njit(cache=True)
def kept_tetrahedra(tets, removed_vertex, keep):
    """keep[r]: no vertex of tets[r] is flagged in removed_vertex. Returns how many are kept."""
    count = 0
    for r in range(tets.shape[0]):
        kept = True
        for j in range(4):
            if removed_vertex[tets[r, j]]:
                kept = False
        keep[r] = kept
        count += kept
    return count


@njit(cache=True)
def copy_kept(old_tets, old_neighbours, old_inverse, keep, vertex_map, hull, tets, neighbours, inverse, was_hull,
              opened):
    """The kept tetrahedra (rows of old_tets where keep), in order, into the first rows of tets (vertices through
    vertex_map), inverse (the old transforms) and neighbours (renumbered; `hull` where the tetrahedron across went, the
    old HULL or crack marker where there was none); was_hull[4 i + j]: face j of new row i was on the hull before.
    opened: the faces whose neighbour went (positions 4 i + j, ascending). Returns (faces opened, whether a kept
    tetrahedron has a removed vertex)."""
    renumbered = np.empty(old_tets.shape[0], dtype=np.int64)
    count = 0
    for r in range(old_tets.shape[0]):
        if keep[r]:
            renumbered[r] = count
            count += 1
        else:
            renumbered[r] = -1
    open_count = 0
    bad = False
    for r in range(old_tets.shape[0]):
        if not keep[r]:
            continue
        i = renumbered[r]
        for j in range(4):
            v = vertex_map[old_tets[r, j]]
            if v < 0:
                bad = True
            tets[i, j] = v
            across = old_neighbours[r, j]
            was_hull[4 * i + j] = across == hull
            if across >= 0:
                if renumbered[across] >= 0:
                    neighbours[i, j] = renumbered[across]
                else:
                    neighbours[i, j] = hull
                    opened[open_count] = 4 * i + j
                    open_count += 1
            else:
                neighbours[i, j] = across
        for a in range(3):
            for b in range(3):
                inverse[i, a, b] = old_inverse[r, a, b]
    return open_count, bad


@njit(cache=True)
def face_vertices(tets, positions):
    """(M, 3): the vertices of faces `positions` (4 x tetrahedron + j: the face opposite vertex j), as
    tets[:, OPPOSITE].reshape(-1, 3)[positions]."""
    out = np.empty((positions.shape[0], 3), dtype=np.int64)
    for k in range(positions.shape[0]):
        r = positions[k] // 4
        j = positions[k] % 4
        for c in range(3):
            out[k, c] = tets[r, OPPOSITE[j, c]]
    return out


@njit(cache=True)
def boundary_faces(neighbours):
    """np.flatnonzero(neighbours < 0): the faces (ascending positions) with no tetrahedron across."""
    flat = neighbours.reshape(-1)
    count = 0
    for k in range(flat.shape[0]):
        count += flat[k] < 0
    out = np.empty(count, dtype=np.int64)
    count = 0
    for k in range(flat.shape[0]):
        if flat[k] < 0:
            out[count] = k
            count += 1
    return out


@njit(cache=True)
def uses_every_vertex(tets, vertex_count):
    """Whether every vertex 0..vertex_count-1 is a corner of some tetrahedron."""
    used = np.zeros(vertex_count, dtype=np.bool_)
    for r in range(tets.shape[0]):
        for j in range(4):
            used[tets[r, j]] = True
    for v in range(vertex_count):
        if not used[v]:
            return False
    return True


@njit(cache=True)
def count_marker(neighbours, marker):
    """np.count_nonzero(neighbours == marker)."""
    flat = neighbours.reshape(-1)
    count = 0
    for k in range(flat.shape[0]):
        count += flat[k] == marker
    return count


@njit(cache=True)
def paired_faces(tets, positions, vertex_bits):
    """The pairs of faces `positions` (4 x tetrahedron + j) with the same three vertices, found through a hash table
    of their keys (the sorted vertices packed, vertex ids < 2^vertex_bits; triangulation.face_keys) instead of a sort:
    (first, second, ok), ok False when a face is in three tetrahedra (not a manifold). Pairs come in no particular
    order; a face pairs with at most one other, so the neighbours they give do not depend on it."""
    count = positions.shape[0]
    size = 1
    while size < 2 * count + 2:
        size *= 2
    shift = 64 - int(np.log2(size))
    slot_key = np.empty(size, dtype=np.int64)
    slot_face = np.full(size, -1, dtype=np.int64)
    slot_pairs = np.zeros(size, dtype=np.int64)
    first = np.empty(count // 2 + 1, dtype=np.int64)
    second = np.empty(count // 2 + 1, dtype=np.int64)
    pairs = 0
    for k in range(count):
        r = positions[k] // 4
        j = positions[k] % 4
        a, b, c = sorted3(tets[r, OPPOSITE[j, 0]], tets[r, OPPOSITE[j, 1]], tets[r, OPPOSITE[j, 2]])
        key = (a << (2 * vertex_bits)) | (b << vertex_bits) | c
        h = np.int64((np.uint64(key) * np.uint64(0x9E3779B97F4A7C15)) >> np.uint64(shift))
        while True:
            if slot_face[h] < 0:
                slot_key[h] = key
                slot_face[h] = k
                break
            if slot_key[h] == key:
                if slot_pairs[h] > 0:
                    return first[:0], second[:0], False
                slot_pairs[h] = 1
                first[pairs] = slot_face[h]
                second[pairs] = k
                pairs += 1
                break
            h = (h + 1) & (size - 1)
    return first[:pairs], second[:pairs], True
