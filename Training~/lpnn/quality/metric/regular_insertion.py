"""A tie-broken Delaunay tetrahedralisation grown by inserting points, without Qhull (quality.md §5.1 step 6).

    tets, refusal = inserted_tetrahedra(mesh, local, heights, order)   # (T, 4) positions, or None and why

Bowyer–Watson on the points lifted to |x|^2 + h (h: each point's tie height, triangulation.Frame.tie_heights): a new
point's cavity is the tetrahedra whose lifted hyperplane it lies below, and the hull faces it lies beyond or, in a hull
face's plane, inside that face's power circle; it is re-triangulated from the point. A vertex at infinity closes the
hull (one "infinite" tetrahedron per hull face), so points outside the hull grow it. The lifted points are in general
position, so the result is the unique regular triangulation of the points: the set of tetrahedra the tie-broken Qhull
call of triangulation.tetrahedralize returns, whatever the insertion order. The C# core's Quality.RegularInsertion, the
same steps and refusals.

Every sign is computed in double with a bound on its rounding and, within the bound, exactly (regular_predicates.py,
exact_predicates.py: Python's integers through numba's object mode; C#: BigInteger), so only truly coplanar points (a lattice's axis-aligned planes: every product of
the expansion 0) or a true lifted tie count as such. Refused, so that the caller tetrahedralises with Qhull instead: a
true lifted tie, a new tetrahedron that is not positively oriented, a vertex the cavity would swallow, a new face
that does not pair with exactly one other (C# pairs them by a dictionary, which would not notice a fourth), and a
starting tetrahedralisation that is not one closed convex surface around a manifold: a crack a dropped flat
tetrahedron left (triangulation.py; any INNER_BOUNDARY neighbour), a hull face's far corner exactly beyond another's
plane (Qhull's merged facets can leave one, by rounding), or a hull in pieces. The starting Tetrahedralization's
orientation and flatness are tetrahedralize's own (orient_and_invert), so they are not checked again. A point walks to
its cavity from the last tetrahedron made (plain double; a scan of every tetrahedron where the walk stops beside it).
The caller's order cannot change the answer, only the walks' length (InsertionTetrahedra inserts in grid order).
"""

from __future__ import annotations

import numpy as np

from ...core.cache import use_project_cache_for_numba
from .regular_predicates import INFINITE, conflict, orient, orient_sign
from .triangulation import HULL, Tetrahedralization

use_project_cache_for_numba()
from numba import njit  # noqa: E402  (after the cache folder is chosen)


# Why a derivation was refused (kernel status codes; FAILURES names them).
DONE, TIE, NO_CONFLICT, NOT_POSITIVE, NO_WAY_BACK, UNPAIRED, VANISHED, NOT_CLOSED, NOT_CONVEX, DISCONNECTED = range(10)
FAILURES = {
    TIE: "a true tie (lifted points on one hyperplane)",
    NO_CONFLICT: "no tetrahedron in conflict with the point",
    NOT_POSITIVE: "a new tetrahedron flat or negative (the cavity not star-shaped)",
    NO_WAY_BACK: "no way back from outside the cavity",
    UNPAIRED: "a new face unpaired",
    VANISHED: "a vertex would vanish",
    NOT_CLOSED: "the starting tetrahedra not a closed manifold (a crack, or a face of three tetrahedra)",
    NOT_CONVEX: "the starting hull not convex",
    DISCONNECTED: "the starting hull in pieces (a crack inside)",
}


@njit(cache=True)
def _slot_of(N, t, neighbour):
    for s in range(4):
        if N[t, s] == neighbour:
            return s
    return -1


@njit(cache=True)
def _other_two(V, t, i, j):
    """The two vertices of t other than slots i and j (one may be INFINITE), ascending, as one int64 key."""
    x, y = -2, -2
    for s in range(4):
        if s != i and s != j:
            if x == -2:
                x = V[t, s]
            else:
                y = V[t, s]
    lo, hi = min(x, y) + 1, max(x, y) + 1
    return (lo << 32) | hi


@njit(cache=True)
def _grown(V, N, alive, mark, free, need):
    """The structure's arrays with room for `need` tetrahedra."""
    size = max(need, 2 * V.shape[0])
    V2 = np.full((size, 4), -3, dtype=np.int64)
    N2 = np.full((size, 4), -3, dtype=np.int64)
    alive2 = np.zeros(size, dtype=np.bool_)
    mark2 = np.full(size, -1, dtype=np.int64)
    free2 = np.empty(size, dtype=np.int64)
    V2[:V.shape[0]] = V
    N2[:N.shape[0]] = N
    alive2[:alive.shape[0]] = alive
    mark2[:mark.shape[0]] = mark
    free2[:free.shape[0]] = free
    return V2, N2, alive2, mark2, free2


@njit(cache=True)
def _pair_by_keys(keys, owners, slots, N):
    """Links the (tetrahedron, slot) pairs whose keys are equal, two by two; False unless every key occurs twice."""
    order = np.argsort(keys, kind="mergesort")
    if order.shape[0] % 2:
        return False
    for k in range(0, order.shape[0], 2):
        i, j = order[k], order[k + 1]
        if keys[i] != keys[j] or (k + 2 < order.shape[0] and keys[order[k + 2]] == keys[i]):
            return False
        N[owners[i], slots[i]] = owners[j]
        N[owners[j], slots[j]] = owners[i]
    return True


@njit(cache=True)
def _outward_face(V, t, s):
    """The face of finite t opposite slot s, ordered so that t's fourth vertex is on its negative side."""
    v0, v1, v2, v3 = V[t, 0], V[t, 1], V[t, 2], V[t, 3]
    if s == 0:
        return v1, v2, v3
    if s == 1:
        return v0, v3, v2
    if s == 2:
        return v0, v1, v3
    return v0, v2, v1


@njit(cache=True)
def _assemble(tets, neighbours, local, vertex_count, capacity):
    """The structure of a tetrahedralisation (positively oriented tets, their neighbours with HULL across hull faces) with
    one infinite tetrahedron per hull face: (status, V, N, count)."""
    T = tets.shape[0]
    V = np.full((capacity, 4), -3, dtype=np.int64)
    N = np.full((capacity, 4), -3, dtype=np.int64)
    used = np.zeros(vertex_count, dtype=np.bool_)
    hull_faces = 0
    for t in range(T):
        for s in range(4):
            V[t, s] = tets[t, s]
            used[tets[t, s]] = True
            nb = neighbours[t, s]
            if nb >= 0:
                N[t, s] = nb
            elif nb == HULL:
                hull_faces += 1
            else:
                return NOT_CLOSED, V, N, 0
    for v in range(vertex_count):
        if not used[v]:
            return NOT_CLOSED, V, N, 0
    count = T
    keys = np.empty(3 * hull_faces, dtype=np.int64)
    owners = np.empty(3 * hull_faces, dtype=np.int64)
    slots = np.empty(3 * hull_faces, dtype=np.int64)
    k = 0
    for t in range(T):
        for s in range(4):
            if neighbours[t, s] != HULL:
                continue
            a, b, c = _outward_face(V, t, s)
            h = count
            count += 1
            V[h, 0], V[h, 1], V[h, 2], V[h, 3] = a, b, c, INFINITE
            N[h, 3] = t
            N[t, s] = h
            for e in range(3):
                keys[k], owners[k], slots[k] = _other_two(V, h, 3, e), h, e
                k += 1
    if not _pair_by_keys(keys, owners, slots, N):
        return NOT_CLOSED, V, N, 0
    # Convex: across every hull edge the other face's far corner is not beyond this face's plane; one surface.
    if hull_faces == 0:
        return NOT_CONVEX, V, N, 0
    seen = np.zeros(count, dtype=np.bool_)
    queue = np.empty(hull_faces, dtype=np.int64)
    queue[0], seen[T] = T, True
    head, tail = 0, 1
    while head < tail:
        h = queue[head]
        head += 1
        for e in range(3):
            other = N[h, e]
            slot = _slot_of(N, other, h)
            if slot < 0:
                return NOT_CLOSED, V, N, 0
            far = V[other, slot]
            if far == INFINITE:
                return NOT_CLOSED, V, N, 0
            if orient_sign(local, V[h, 0], V[h, 1], V[h, 2], far) > 0:  # beyond the face's plane
                return NOT_CONVEX, V, N, 0
            if not seen[other]:
                seen[other] = True
                queue[tail] = other
                tail += 1
    if tail != hull_faces:
        return DISCONNECTED, V, N, 0
    return DONE, V, N, count


@njit(cache=True)
def _locate(V, N, alive, count, local, last, p):
    """A tetrahedron holding p or, outside the hull, an infinite one whose face p lies beyond: a walk across the faces p
    lies beyond (plain double), from `last`; -1 when it does not end."""
    t = last
    if not alive[t]:
        t = 0
        while t < count and not alive[t]:
            t += 1
    if V[t, 3] == INFINITE:
        t = N[t, 3]
    limit = 4 * count + 64
    for step in range(limit):
        if V[t, 3] == INFINITE:
            return t
        nxt = -1
        for k in range(4):
            s = (k + step) & 3  # rotating the first face tried keeps a walk from cycling
            a = p if s == 0 else V[t, 0]
            b = p if s == 1 else V[t, 1]
            c = p if s == 2 else V[t, 2]
            d = p if s == 3 else V[t, 3]
            det, _ = orient(local, a, b, c, d)
            if det < 0.0:
                nxt = N[t, s]
                break
        if nxt < 0:
            return t
        t = nxt
    return -1


@njit(cache=True)
def _insert_all(V, N, count, local, height, order):
    """Inserts the vertices `order` one by one (module text): (status, failing vertex, V, N, count)."""
    capacity = V.shape[0]
    alive = np.zeros(capacity, dtype=np.bool_)
    alive[:count] = True
    mark = np.full(capacity, -1, dtype=np.int64)
    free = np.empty(capacity, dtype=np.int64)
    free_top = 0
    kept = np.full(local.shape[0], -1, dtype=np.int64)
    m = np.empty((4, 4))
    cavity = np.empty(64, dtype=np.int64)
    boundary_t = np.empty(64, dtype=np.int64)
    boundary_s = np.empty(64, dtype=np.int64)
    last = 0
    for stamp in range(order.shape[0]):
        p = order[stamp]
        start = _locate(V, N, alive, count, local, last, p)
        if start >= 0:
            if conflict(V, local, height, m, start, p) != 1:
                start = -1
        if start < 0:  # the walk stopped beside the point (within rounding of a face): scan for any conflict
            for t in range(count):
                if alive[t] and conflict(V, local, height, m, t, p) == 1:
                    start = t
                    break
        if start < 0:
            return NO_CONFLICT, p, V, N, count
        size = 1
        cavity[0] = start
        mark[start] = stamp
        boundary = 0
        k = 0
        while k < size:
            t = cavity[k]
            k += 1
            for j in range(4):
                u = N[t, j]
                if mark[u] == stamp:
                    continue
                state = conflict(V, local, height, m, u, p)
                if state == 0:
                    return TIE, p, V, N, count
                if state > 0:
                    mark[u] = stamp
                    if size == cavity.shape[0]:
                        cavity = np.concatenate((cavity, np.empty(size, dtype=np.int64)))
                    cavity[size] = u
                    size += 1
        for i in range(size):
            t = cavity[i]
            for j in range(4):
                if mark[N[t, j]] != stamp:
                    if boundary == boundary_t.shape[0]:
                        boundary_t = np.concatenate((boundary_t, np.empty(boundary, dtype=np.int64)))
                        boundary_s = np.concatenate((boundary_s, np.empty(boundary, dtype=np.int64)))
                    boundary_t[boundary], boundary_s[boundary] = t, j
                    boundary += 1
        # Room for the new tetrahedra beyond the free ones.
        if count + boundary > capacity:
            V, N, alive, mark, free = _grown(V, N, alive, mark, free, count + boundary + 64)
            capacity = V.shape[0]
        made = np.empty(boundary, dtype=np.int64)
        keys = np.empty(3 * boundary, dtype=np.int64)
        owners = np.empty(3 * boundary, dtype=np.int64)
        slots = np.empty(3 * boundary, dtype=np.int64)
        for b in range(boundary):
            t, j = boundary_t[b], boundary_s[b]
            if free_top > 0:
                free_top -= 1
                fresh = free[free_top]
            else:
                fresh = count
                count += 1
            alive[fresh] = True
            mark[fresh] = -1
            for s in range(4):
                V[fresh, s] = V[t, s]
            V[fresh, j] = p
            if V[fresh, 3] != INFINITE and orient_sign(local, V[fresh, 0], V[fresh, 1], V[fresh, 2], V[fresh, 3]) != 1:
                return NOT_POSITIVE, p, V, N, count
            outside = N[t, j]
            N[fresh, j] = outside
            back = _slot_of(N, outside, t)
            if back < 0:
                return NO_WAY_BACK, p, V, N, count
            N[outside, back] = fresh
            made[b] = fresh
            e = 0
            for s in range(4):
                if s != j:
                    keys[3 * b + e], owners[3 * b + e], slots[3 * b + e] = _other_two(V, fresh, j, s), fresh, s
                    e += 1
        if not _pair_by_keys(keys, owners, slots, N):
            return UNPAIRED, p, V, N, count
        # Every vertex of the cavity must stay one (a regular triangulation may otherwise hide it).
        for b in range(boundary):
            for s in range(4):
                if V[made[b], s] >= 0:
                    kept[V[made[b], s]] = stamp
        for i in range(size):
            t = cavity[i]
            for s in range(4):
                if V[t, s] >= 0 and kept[V[t, s]] != stamp:
                    return VANISHED, p, V, N, count
            alive[t] = False
            free[free_top] = t
            free_top += 1
        last = made[0]
    finite = 0
    for t in range(count):
        if alive[t] and V[t, 3] != INFINITE:
            finite += 1
    out = np.empty((finite, 4), dtype=np.int64)
    k = 0
    for t in range(count):
        if alive[t] and V[t, 3] != INFINITE:
            out[k] = V[t]
            k += 1
    return DONE, -1, out, N, count


def inserted_tetrahedra(mesh: Tetrahedralization, local: np.ndarray, heights: np.ndarray, order: np.ndarray,
                        capacity: int | None = None) -> tuple[np.ndarray | None, str | None]:
    """The tetrahedra (T, 4, positions 0..P-1, positively oriented, in no particular order) of `mesh`'s probes (the first
    mesh.point_count positions) and the new vertices `order` (positions, inserted in that order), or (None, why) when
    the derivation is refused (module text). `local` (P, 3) and `heights` (P,): every position's local coordinates and
    tie height, as triangulation.tetrahedralize lifts them. `capacity`: tests only, the structure's first room in
    tetrahedra (at least the mesh's, infinite ones included; it grows as needed)."""
    local = np.ascontiguousarray(local, dtype=np.float64)
    heights = np.ascontiguousarray(heights, dtype=np.float64)
    order = np.ascontiguousarray(order, dtype=np.int64)
    known, total = mesh.point_count, local.shape[0]
    if local.shape != (total, 3) or heights.shape != (total,):
        raise ValueError(f"local {list(local.shape)} and heights {list(heights.shape)} must give all {total:,} positions")
    if order.shape != (total - known,) or not np.array_equal(np.sort(order), np.arange(known, total)):
        raise ValueError(f"order must hold each new position {known:,}..{total - 1:,} once, got {order.shape[0]:,} values")
    tets = np.ascontiguousarray(mesh.tets, dtype=np.int64)
    if capacity is None:
        capacity = 2 * tets.shape[0] + 8 * (total - known) + 4 * mesh.hull_faces.shape[0] + 64
    capacity = max(int(capacity), tets.shape[0] + mesh.hull_faces.shape[0])
    status, V, N, count = _assemble(tets, np.ascontiguousarray(mesh.neighbours, dtype=np.int64), local,
                                    mesh.point_count, capacity)
    if status != DONE:
        return None, FAILURES[status]
    status, vertex, out, _, _ = _insert_all(V, N, count, local, heights, order)
    if status != DONE:
        return None, f"{FAILURES[status]} (vertex {vertex})"
    return out, None
