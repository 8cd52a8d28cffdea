"""Interpolation stencils: which 4 probes, with which weights, give the lighting at a point.

Inside the hull: the tetrahedron containing the point (vectorised visibility walk from the
tetrahedron whose centroid is nearest, with a brute-force fallback for walks that cycle or meet a crack, faces without a
tetrahedron across inside the hull: triangulation.py INNER_BOUNDARY), barycentric weights clamped
to >= 0 and renormalised (they are >= -1e-9 before clamping). Outside: the nearest point on the
hull surface and its triangle's weights (hull_projection.py); the fourth weight is 0.

Ties (quality.md §1): a point on a face, edge or vertex shared by several tetrahedra (smallest coordinate within
INSIDE_TOLERANCE of 0) belongs to the lowest-index one, and a point outside whose nearest hull point lies on a hull edge
or vertex to the hull triangle there of the lowest-index owner (snapped onto that edge or vertex); so a point's stencil
does not depend on where a walk started, nor on the language (the C# core's TetrahedronLocator and HullProjector apply
the same rule).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from .hull_projection import project_to_hull
from .metric_kernel import (WALK_COHERENT, WALK_FROM_EACH_START, WALK_WITHIN_RUNS, chunk_bounds, chunk_count,
                            inside_stencils, kept_cells, most_inside, nearest_centroids, outside_stencils, run_rows, walk)
from .triangulation import PARALLEL_QUERY, QUERY_WORKERS, Tetrahedralization

INSIDE_TOLERANCE = 1e-9  # coordinates >= -this count as inside; a smallest within this of 0 is a tie (module text)
# Below this many point-tetrahedron pairs, test them all; above, walk (the same cells: the tie rule settles a point on a
# shared boundary either way). 200,000 before 2026-11-29: the refinement's trials on crops then tested ~0.4 ms a call
# where the walk takes a fraction of it (benchmarks.md "Hull vertices wrapped, small locations walked").
BRUTE_FORCE_PAIRS = 16_384
WALK_STEP_LIMIT = 10_000
FEW_STARTS = 64  # walks with at most this many starts find them in one pass over the tetrahedra, without a k-d tree
# (a coherent walk starts once per parallel slice, <= 64: the tree over ~10^5 centroids cost ~25 ms a call, the pass ~2 ms)


@dataclass(frozen=True)
class Stencil:
    vertices: np.ndarray  # (M, 4) int64 probe indices (into the triangulation's points)
    weights: np.ndarray  # (M, 4) float64, >= 0, sum 1
    cell: np.ndarray  # (M,) int64 tetrahedron containing the point, or owning its hull triangle
    outside: np.ndarray  # (M,) bool: point outside the hull (weights from its projection)
    anchor: np.ndarray  # (M, 3) local coordinates where the weights apply (the point, or its projection)

    @property
    def count(self) -> int:
        return int(self.cell.shape[0])


def barycentric(tri: Tetrahedralization, cells: np.ndarray, query: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (..., 4) of points (..., 3) in tetrahedra `cells` (...)."""
    base = tri.points[tri.tets[cells, 0]]
    rest = np.einsum("...ij,...j->...i", tri.inverse[cells], query - base)
    return np.concatenate([1.0 - rest.sum(axis=-1, keepdims=True), rest], axis=-1)


def _brute_force(tri: Tetrahedralization, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Most-inside tetrahedron (max of min barycentric, the first of equals; on a shared boundary the tie rule's) for
    each point, and that largest minimum (metric_kernel.most_inside: `barycentric`'s numbers)."""
    best_cell = np.empty(query.shape[0], dtype=np.int64)
    best_min = np.empty(query.shape[0])
    run_rows(most_inside, query.shape[0] * max(1, tri.tets.shape[0] // 64), tri.points, tri.tets, tri.inverse,
             np.ascontiguousarray(query, dtype=np.float64), INSIDE_TOLERANCE, best_cell, best_min)
    return best_cell, best_min


def _walk(tri: Tetrahedralization, query: np.ndarray, coherent: bool = False, start: np.ndarray | None = None
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Visibility walk for all points at once. Returns cell (-1 = outside; on a shared boundary the tie rule's
    tetrahedron), a 'resolved' mask and the barycentric coordinates (M, 4) in the cell (those of `barycentric`, bit for
    bit; rows of points not inside a cell are undefined). Each walk starts in the tetrahedron whose centroid is nearest,
    or with `coherent` (points in grid order) where the previous point's walk ended (each parallel slice's first point
    from its nearest centroid), or, given `start` (M,; checked by locate_cells: checked_starts), in tetrahedron start[m]
    where it differs from the previous point's or m begins a parallel slice, else where the previous point's walk ended
    (a caller that knows where runs of points lie)."""
    m = query.shape[0]
    if start is not None:
        mode = WALK_WITHIN_RUNS
    else:
        start, mode = _nearest_starts(tri, query, coherent), WALK_COHERENT if coherent else WALK_FROM_EACH_START
    result = np.empty(m, dtype=np.int64)
    resolved = np.empty(m, dtype=bool)
    coordinates = np.empty((m, 4))
    # Point by point in parallel slices (metric_kernel.walk: the arithmetic of `barycentric`, numpy's argmin; ties
    # settled there). Leaving through a hull face: the point is beyond that face's plane, hence outside the hull; through
    # a crack (INNER_BOUNDARY) it may be in tetrahedra the walk cannot reach: unresolved, for the brute force.
    run_rows(walk, m, tri.points, tri.tets, tri.inverse, tri.neighbours, np.ascontiguousarray(query), start,
             WALK_STEP_LIMIT, INSIDE_TOLERANCE, result, resolved, coordinates, mode)
    return result, resolved, coordinates


def checked_starts(tri: Tetrahedralization, start: np.ndarray, count: int) -> np.ndarray:
    """`start` as the walk's int64 starts: one tetrahedron of `tri` for each of `count` points (the compiled walk does
    not check its indices)."""
    start = np.ascontiguousarray(start, dtype=np.int64)
    if start.shape != (count,):
        raise ValueError(f"{start.shape} walk starts for {count} points: give one tetrahedron per point")
    if count and not (0 <= int(start.min()) and int(start.max()) < tri.tets.shape[0]):
        raise ValueError(f"walk starts {int(start.min())}..{int(start.max())} outside the {tri.tets.shape[0]} tetrahedra")
    return start


def _nearest_starts(tri: Tetrahedralization, query: np.ndarray, coherent: bool) -> np.ndarray:
    """_walk's default starts: the tetrahedron whose centroid is nearest each point, or with `coherent` each parallel
    slice's first point's."""
    m = query.shape[0]
    if coherent:
        chunks = chunk_count(m) if m else 0
        first = query[[chunk_bounds(m, chunks, c)[0] for c in range(chunks)]]
    else:
        first = query
    if first.shape[0] <= FEW_STARTS:
        start = np.zeros(first.shape[0], dtype=np.int64)
        nearest_centroids(tri.points, tri.tets, np.ascontiguousarray(first, dtype=np.float64), start)
        return start
    centroids = tri.points[tri.tets].mean(axis=1)
    workers = QUERY_WORKERS if first.shape[0] >= PARALLEL_QUERY else 1  # threads cost more than small queries take
    return np.asarray(cKDTree(centroids).query(first, k=1, workers=workers)[1], dtype=np.int64).reshape(-1)


def locate_local(tri: Tetrahedralization, query: np.ndarray, coherent: bool = False,
                 start: np.ndarray | None = None) -> Stencil:
    """Stencils for points given in the triangulation's local coordinates (M, 3). coherent=True
    (points in grid order, each near the previous one) starts each walk where the previous one ended
    instead of at the nearest tetrahedron centroid (a k-d tree query per point, most of the time at
    10^6 points); `start` (M,), a tetrahedron near each point (a batched refinement's refill of the star the point was
    in), starts each walk there where it differs from the previous point's and continues the previous walk where it
    does not (points of one star in a row). The same stencils whatever the start, since a point on a boundary shared
    by several tetrahedra gets the tie rule's (module text) wherever its walk arrived — with one exception: a point
    outside the hull by less than INSIDE_TOLERANCE in one tetrahedron's coordinates but more in a thinner hull
    tetrahedron's is inside for the rule and the brute force, yet a walk leaving through the thin one's hull face calls
    it outside (its weights then come from its projection onto the hull, which lies within that distance). That holds
    for every start mode alike; on the validation levels and crops no answer depends on it (the same probes files with
    coherent and refill starts)."""
    q = np.asarray(query, dtype=np.float64).reshape(-1, 3)
    return stencils_of_cells(tri, q, *locate_cells(tri, q, coherent, start))


def locate_cells(tri: Tetrahedralization, q: np.ndarray, coherent: bool = False, start: np.ndarray | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The first half of locate_local for points (M, 3) in local coordinates: each one's tetrahedron (-1: outside the
    hull), whether the walk found it, and the walk's barycentric coordinates there (rows of other points undefined)."""
    m = q.shape[0]
    if start is not None:
        start = checked_starts(tri, start, m)
    if m * tri.tets.shape[0] <= BRUTE_FORCE_PAIRS:
        cell, smallest = _brute_force(tri, q)
        return np.where(smallest >= -INSIDE_TOLERANCE, cell, -1), np.zeros(m, dtype=bool), np.empty((m, 4))
    cell, walked, coordinates = _walk(tri, q, coherent, start)
    stuck = np.flatnonzero(~walked)  # numerically cycling walks, walks into a crack: rare, settle them exactly
    if stuck.shape[0]:
        fallback, smallest = _brute_force(tri, q[stuck])
        cell[stuck] = np.where(smallest >= -INSIDE_TOLERANCE, fallback, -1)
    return cell, walked, coordinates


def keep_located(tri: Tetrahedralization, q: np.ndarray, cell: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For points (M, 3) known to lie in tetrahedra `cell` of `tri` (-1: unknown), modified in place: the tetrahedron
    location would give them, without a walk (metric_kernel.kept_cells): the same one when the point is clearly inside it
    (smallest coordinate > INSIDE_TOLERANCE), else the tie rule's (module text), searched from it (-1 in the rare case the
    search overflows: to be located). Returns `walked` (the points settled) and their coordinates, in locate_cells'
    form."""
    walked = np.zeros(q.shape[0], dtype=bool)
    coordinates = np.empty((q.shape[0], 4))
    run_rows(kept_cells, q.shape[0], tri.points, tri.tets, tri.inverse, tri.neighbours, q, INSIDE_TOLERANCE, cell, walked,
             coordinates)
    return walked, coordinates


def stencils_of_cells(tri: Tetrahedralization, q: np.ndarray, cell: np.ndarray, walked: np.ndarray,
                      coordinates: np.ndarray) -> Stencil:
    """The second half of locate_local: stencils from each point's tetrahedron (cell >= 0; its barycentric coordinates
    are the walk's where `walked`, else computed here) or, outside the hull (cell -1), from its nearest hull point.
    `cell` becomes the Stencil's own."""
    m = q.shape[0]
    vertices = np.zeros((m, 4), dtype=np.int64)
    weights = np.zeros((m, 4))
    anchor = q.copy()
    run_rows(inside_stencils, m, tri.points, tri.tets, tri.inverse, q, cell, walked, coordinates, vertices, weights)
    outside = cell < 0
    far = np.flatnonzero(outside)
    if far.shape[0]:
        projection = project_to_hull(tri.points, tri.hull_faces, q[far], owners=tri.hull_face_tets)
        # The hull triangle's corners and weights, then the owner's fourth vertex with weight 0 (every stencil 4 wide).
        run_rows(outside_stencils, far.shape[0], tri.tets, tri.hull_faces, tri.hull_face_tets, far, projection.face,
                 projection.weights, projection.anchor, vertices, weights, cell, anchor)
    return Stencil(vertices=vertices, weights=weights, cell=cell, outside=outside, anchor=anchor)


def locate(tri: Tetrahedralization, world: np.ndarray) -> Stencil:
    """Stencils for world positions (M, 3)."""
    return locate_local(tri, tri.frame.to_local(world))
