"""The tetrahedra that refill the hole an interior probe leaves, by gift wrapping (quality.md §3.2).

When interior probe v goes, its star is refilled by the regular (tie-broken Delaunay, see
metric/triangulation.py) tetrahedra of link(v) that lie in the star. Each rests on a face of the hole's
boundary (the star's faces opposite v) or of another hole tetrahedron; on a face (a, b, c) it is
completed by the link point p on the inner side that the lifted hyperplane through a, b, c meets
first as it tilts into that side, i.e. the smallest

    key(p) = (h(p) - L(p)) / dist(p)

with h the lifted height, L the affine function equal to h at a, b, c whose gradient lies in their
plane, and dist(p) the (scaled) distance of p from that plane. Starting from the boundary faces,
every face that is matched on one side only is completed, until the hole is closed. In exact
arithmetic this gives exactly the tetrahedra of the lower hull of the lifted link (the triangulation
is unique): the same result as one Qhull call per probe, ~10x faster. A hole fails (the caller then
uses Qhull) when a face has no link point on its inner side, a face is shared by three tetrahedra,
or it does not close within the size limits; the caller also checks the hole's volume.

On the hull (the `hull` code of each hole): a probe on the hull's surface (ON_HULL) may leave faces the
wrapping makes with nothing beyond them, which lie on the hull. A vertex of the hull (HULL_VERTEX, batched
refinement's trials only: placement/trial_fills.py) may leave boundary faces so too, where the hull loses
its corner: the wrapping then gives the part of the star the new hull keeps. Such a face is refused
(Qhull decides) when a link point in its on-plane band would make a tetrahedron tet_geometry.is_flat keeps.

Heights are taken relative to v (|x - v|^2 + tie-break: the same lifting up to an affine function),
so the keys keep their precision: on grids competing keys differ only by the tie-break, about 1e-5
of the squared spacing. The loops are compiled with numba (cached on disk after the first run, in the project's cache folder):
they are short, branchy and per-probe, which numpy cannot vectorise well.
"""

from __future__ import annotations

import numpy as np

from ....core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit, prange  # noqa: E402  (after the cache folder is chosen)

from ...metric.metric_kernel import chunk_bounds, chunk_count, run_rows  # noqa: E402
from ...metric.tet_geometry import FLAT_RELATIVE_VOLUME  # noqa: E402

ON_PLANE = 1e-9  # |dist| <= this x |n|^1.5 (a spacing^3 scale): the point lies on the face's plane
# A hull vertex's face with no apex is a hull face unless a point of its on-plane band makes a tetrahedron is_flat keeps
# (_kept_sliver): this fraction of is_flat's threshold, so rounding in the two arithmetics cannot tell them apart.
SLIVER_MARGIN = 0.1
MAX_LINK = 96  # larger links go to Qhull
MAX_FACES = 8 * MAX_LINK  # faces a hole may register (a closed hole of d points has < 4d)


@njit(cache=True)
def _orient_at(x: np.ndarray, a: int, b: int, c: int, q: np.ndarray) -> float:
    """Signed 6 x volume of (x[a], x[b], x[c], q)."""
    e1 = x[b] - x[a]
    e2 = x[c] - x[a]
    e3 = q - x[a]
    return (e1[1] * e2[2] - e1[2] * e2[1]) * e3[0] + (e1[2] * e2[0] - e1[0] * e2[2]) * e3[1] \
        + (e1[0] * e2[1] - e1[1] * e2[0]) * e3[2]


@njit(cache=True)
def _sorted3(a: int, b: int, c: int) -> tuple[int, int, int]:
    lo, hi = min(a, b, c), max(a, b, c)
    return lo, a + b + c - lo - hi, hi


@njit(cache=True)
def _find_face(faces: np.ndarray, count: int, a: int, b: int, c: int) -> int:
    """Index of the registered face with vertices {a, b, c}, or -1."""
    lo, mid, hi = _sorted3(a, b, c)
    for i in range(count):
        if faces[i, 0] == lo and faces[i, 1] == mid and faces[i, 2] == hi:
            return i
    return -1


@njit(cache=True)
def _register(faces: np.ndarray, seen: np.ndarray, count: int, a: int, b: int, c: int) -> tuple[int, int]:
    """Count one more tetrahedron on face {a, b, c}; returns (face index, new count of faces)."""
    found = _find_face(faces, count, a, b, c)
    if found >= 0:
        seen[found] += 1
        return found, count
    if count == faces.shape[0]:
        return -1, count
    faces[count, 0], faces[count, 1], faces[count, 2] = _sorted3(a, b, c)
    seen[count] = 1
    return count, count + 1


@njit(cache=True)
def _collect_link(star: np.ndarray, v: int, link: np.ndarray) -> int:
    """Write the distinct vertices of the star (S, 4) other than v into `link`; their count, or -1 when
    there are more than it holds."""
    d = 0
    for t in range(star.shape[0]):
        for j in range(4):
            u = star[t, j]
            if u == v:
                continue
            known = False
            for i in range(d):
                if link[i] == u:
                    known = True
                    break
            if not known:
                if d == link.shape[0]:
                    return -1
                link[d] = u
                d += 1
    return d


DEGENERATE_FACE = -2  # _lowest_apex: the face {a, b, c} has no area
SLIVER_IN_BAND = -3  # _lowest_apex: no apex, but a point its band skipped would make a sliver is_flat keeps

# Where the probe whose hole is wrapped lies (_wrap_one's `hull`, wrap_hole_runs' `hull` codes).
INTERIOR = 0  # inside the hull: the hole is closed
ON_HULL = 1  # on the hull's surface, not a vertex of it: a face the wrapping makes may be a hull face
HULL_VERTEX = 2  # a vertex of the hull: a face of the star's boundary may be one too


@njit(cache=True)
def _length(x: np.ndarray, i: int, j: int) -> float:
    return np.sqrt((x[j, 0] - x[i, 0]) ** 2 + (x[j, 1] - x[i, 1]) ** 2 + (x[j, 2] - x[i, 2]) ** 2)


@njit(cache=True)
def _kept_sliver(x: np.ndarray, a: int, b: int, c: int, p: int, volume6: float) -> bool:
    """Whether (a, b, c, p), of 6 x volume `volume6`, is a tetrahedron tet_geometry.is_flat keeps: above SLIVER_MARGIN x
    FLAT_RELATIVE_VOLUME x the smallest product of three edges meeting at one of its corners (the product is_flat uses
    depends on the corner listed first). A point on the face's plane up to rounding makes a flat one, which both drop."""
    ab, ac, bc = _length(x, a, b), _length(x, a, c), _length(x, b, c)
    ap, bp, cp = _length(x, a, p), _length(x, b, p), _length(x, c, p)
    smallest = min(ab * ac * ap, ab * bc * bp, ac * bc * cp, ap * bp * cp)
    return volume6 > SLIVER_MARGIN * FLAT_RELATIVE_VOLUME * smallest


@njit(cache=True)
def _lowest_apex(x: np.ndarray, h: np.ndarray, d: int, a: int, b: int, c: int, band_slivers: bool) -> int:
    """The link point on the positive side of face (a, b, c) whose lifted point lies lowest above the
    face's lifted plane (the regular-triangulation apex); -1 when none, DEGENERATE_FACE for a flat face.
    band_slivers: when there is none, SLIVER_IN_BAND if a point the ON_PLANE band skipped would make with the face a
    tetrahedron is_flat keeps (_kept_sliver)."""
    e1 = x[b] - x[a]
    e2 = x[c] - x[a]
    n0 = e1[1] * e2[2] - e1[2] * e2[1]
    n1 = e1[2] * e2[0] - e1[0] * e2[2]
    n2 = e1[0] * e2[1] - e1[1] * e2[0]
    g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]
    g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]
    g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]
    gram = g11 * g22 - g12 * g12
    if not gram > 0.0:
        return DEGENERATE_FACE
    db, dc = h[b] - h[a], h[c] - h[a]
    alpha, beta = (db * g22 - dc * g12) / gram, (dc * g11 - db * g12) / gram
    floor = ON_PLANE * gram ** 0.75
    best, best_key = -1, np.inf
    sliver = False
    for p in range(d):
        if p == a or p == b or p == c:
            continue
        e30, e31, e32 = x[p, 0] - x[a, 0], x[p, 1] - x[a, 1], x[p, 2] - x[a, 2]
        distance = n0 * e30 + n1 * e31 + n2 * e32
        if distance <= floor:
            if band_slivers and not sliver and distance >= -floor:
                sliver = _kept_sliver(x, a, b, c, p, abs(distance))
            continue
        rise = h[p] - h[a] - alpha * (e1[0] * e30 + e1[1] * e31 + e1[2] * e32) \
            - beta * (e2[0] * e30 + e2[1] * e31 + e2[2] * e32)
        key = rise / distance
        if key < best_key:
            best, best_key = p, key
    return SLIVER_IN_BAND if best < 0 and sliver else best


@njit(cache=True)
def _wrap_one(local: np.ndarray, tie: np.ndarray, v: int, star: np.ndarray, hull: int, out: np.ndarray) -> int:
    """Fill `out` with the hole tetrahedra of probe v (star (S, 4), global ids); returns their count,
    or -1 when wrapping failed. hull: INTERIOR, ON_HULL (v lies on the hull, not a vertex of it: a face the
    wrapping creates may have nothing on its far side, it lies on the hull) or HULL_VERTEX (a boundary face may
    have nothing on v's side too: the hull loses v's corner there, module text)."""
    # Link points (local numbering), coordinates relative to v and heights.
    link = np.empty(MAX_LINK, dtype=np.int64)
    d = _collect_link(star, v, link)
    if d < 0:
        return -1
    x = np.empty((d, 3))
    h = np.empty(d)
    for i in range(d):
        for k in range(3):
            x[i, k] = local[link[i], k] - local[v, k]
        h[i] = x[i, 0] * x[i, 0] + x[i, 1] * x[i, 1] + x[i, 2] * x[i, 2] + tie[link[i]]

    # Boundary faces (local numbering), v on the positive side; registered once (the star's side).
    faces = np.empty((MAX_FACES, 3), dtype=np.int64)
    seen = np.zeros(MAX_FACES, dtype=np.int64)
    queue = np.empty((MAX_FACES, 3), dtype=np.int64)
    count = 0
    pending = 0
    boundary_faces = star.shape[0]
    tri = np.empty(3, dtype=np.int64)
    at_v = np.zeros(3)  # v, the origin of x
    for t in range(star.shape[0]):
        m = 0
        for j in range(4):
            if star[t, j] != v:
                for i in range(d):
                    if link[i] == star[t, j]:
                        tri[m] = i
                m += 1
        a, b, c = tri[0], tri[1], tri[2]
        if _orient_at(x, a, b, c, at_v) < 0.0:  # v must be on the positive side
            b, c = c, b
        index, count = _register(faces, seen, count, a, b, c)
        if index < 0 or seen[index] > 1:
            return -1  # a repeated boundary face: not a proper star
        queue[pending, 0], queue[pending, 1], queue[pending, 2] = a, b, c
        pending += 1
    made = 0
    head = 0
    while head < pending:
        a, b, c = queue[head, 0], queue[head, 1], queue[head, 2]
        head += 1
        here = _find_face(faces, count, a, b, c)
        if seen[here] >= 2:
            continue  # closed meanwhile
        best = _lowest_apex(x, h, d, a, b, c, hull == HULL_VERTEX)
        if best == DEGENERATE_FACE or best == SLIVER_IN_BAND:
            # SLIVER_IN_BAND: a point in the band _lowest_apex skips may be the apex of a sliver the lower hull keeps (its
            # flatness is tet_geometry.is_flat's, not the band's): the caller's Qhull decides.
            return -1
        if best < 0 and (hull == HULL_VERTEX or (hull == ON_HULL and head > boundary_faces)):
            seen[here] = 2  # a face of the hull: nothing on its far side
            continue
        if best < 0 or made == out.shape[0]:
            return -1
        out[made, 0], out[made, 1], out[made, 2], out[made, 3] = link[a], link[b], link[c], link[best]
        made += 1
        seen[here] += 1
        # The other three faces; the inner side of each is away from the vertex it leaves out.
        for f in range(3):
            if f == 0:
                p0, p1, p2, away = a, b, best, c
            elif f == 1:
                p0, p1, p2, away = b, c, best, a
            else:
                p0, p1, p2, away = c, a, best, b
            index, count = _register(faces, seen, count, p0, p1, p2)
            if index < 0 or seen[index] > 2:
                return -1
            if seen[index] == 1:
                if pending == queue.shape[0]:
                    return -1
                if _orient_at(x, p0, p1, p2, x[away]) > 0.0:
                    p1, p2 = p2, p1
                queue[pending, 0], queue[pending, 1], queue[pending, 2] = p0, p1, p2
                pending += 1
    for i in range(count):
        if seen[i] != 2:
            return -1
    return made


# A hole's wrapping is a few dozen times the work of one row of a per-point pass (metric_kernel): its weight in the
# parallel slicing (chunk_count), so a refinement round's ~2,500 holes fill a few slices while the few holes a
# decimation wraps at a time stay on one thread.
HOLE_WEIGHT = 32


@njit(cache=True, parallel=True)
def _wrap_all(local: np.ndarray, tie: np.ndarray, vertices: np.ndarray, star_tets: np.ndarray,
              star_start: np.ndarray, hull: np.ndarray, out: np.ndarray, out_start: np.ndarray,
              counts: np.ndarray) -> None:
    """counts[k] = _wrap_one's count for hole k, its tetrahedra in out[out_start[k]:]; holes in parallel slices (each
    hole alone: the same tetrahedra however the holes are sliced)."""
    holes = vertices.shape[0]
    chunks = chunk_count(holes * HOLE_WEIGHT)
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(holes, chunks, chunk)
        for k in range(lo, hi):
            counts[k] = _wrap_one(local, tie, vertices[k], star_tets[star_start[k]:star_start[k + 1]], hull[k],
                                  out[out_start[k]:out_start[k + 1]])


def wrap_hole_runs(local: np.ndarray, tie: np.ndarray, vertices: np.ndarray, star_tets: np.ndarray,
                   star_start: np.ndarray, hull: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """wrap_holes with the stars given as one array: hole k's star is star_tets[star_start[k]:star_start[k + 1]]
    (star_start (H + 1,)); hull (H,): each probe's INTERIOR, ON_HULL or HULL_VERTEX (a bool array: ON_HULL where True).
    Returns out, out_start (H + 1,) and counts (H,): hole k's tetrahedra are out[out_start[k]:out_start[k] + counts[k]]
    (counts[k] 0: wrapping failed), without a list of arrays per hole. A hull vertex's wrapping gives the tetrahedra of
    its star that remain inside the new hull; the caller checks their volume is at most the star's."""
    vertices = np.ascontiguousarray(vertices, dtype=np.int64)
    star_start = np.ascontiguousarray(star_start, dtype=np.int64)
    out_start = 2 * star_start  # room for 2S tetrahedra per hole of S boundary faces; more fails to Qhull
    out = np.empty((int(out_start[-1]), 4), dtype=np.int64)
    counts = np.zeros(vertices.shape[0], dtype=np.int64)
    run_rows(_wrap_all, vertices.shape[0] * HOLE_WEIGHT, local, tie, vertices,
             np.ascontiguousarray(star_tets, dtype=np.int64), star_start, np.ascontiguousarray(hull, dtype=np.int64),
             out, out_start, counts)
    return out, out_start, counts


def wrap_holes(local: np.ndarray, tie: np.ndarray, vertices: list[int], stars: list[np.ndarray],
               on_hull: list[bool] | None = None) -> list[np.ndarray | None]:
    """For each probe vertices[k] that is not a vertex of the hull, with star tetrahedra stars[k]
    (S_k, 4) (global ids): the tetrahedra (T_k, 4) that refill its hole (unoriented), or None when
    wrapping failed. on_hull[k]: the probe lies on the hull's surface (default: none does).

    local (N, 3): positions in the frame; tie (N,): each point's tie-break height.
    """
    sizes = np.array([s.shape[0] for s in stars], dtype=np.int64)
    star_start = np.concatenate([[0], np.cumsum(sizes)])
    star_tets = np.concatenate(stars) if stars else np.zeros((0, 4), dtype=np.int64)
    surface = np.zeros(len(stars), dtype=np.bool_) if on_hull is None else np.asarray(on_hull, dtype=np.bool_)
    out, out_start, counts = wrap_hole_runs(local, tie, np.asarray(vertices, dtype=np.int64), star_tets, star_start,
                                            surface)
    return [out[out_start[k]:out_start[k] + counts[k]] if counts[k] > 0 else None for k in range(len(stars))]
