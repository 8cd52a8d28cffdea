"""Points outside the probes' hull: the nearest point on the hull surface (quality.md §1).

For a point outside the convex hull, the nearest point of the hull is unique (projection onto a
convex set) and lies on a boundary triangle; the point takes that triangle's barycentric weights,
which are >= 0 and sum to 1. The map is continuous (projection is 1-Lipschitz, the surface
interpolant is continuous) and equals the inside interpolation on the hull itself.

Exact and vectorised: each point takes the best of its k nearest triangles (by centroid,
cKDTree); the answer p for point q is then certified by the supporting-plane test of convex
projection (p is the nearest point of the hull iff (q - p).(x - p) <= 0 for every hull vertex x);
the few points that fail it are settled against every triangle.

Ties (quality.md §1 "Ties"): a nearest point on a hull edge or vertex lies on every hull triangle there, at the same
distance, and near one (within ~1e-10 of the extent, as float32 positions put many lattice points) the distances differ
by less than their rounding. For point location (project_to_hull with the triangles' owners) a point takes, among the
triangles within a relative HULL_TIE of the smallest distance, the one owned by the lowest-index tetrahedron, its
nearest point snapped onto the edge or vertex they share, as the C# core's HullProjector does, so its cell and weights
do not hang on rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from .hull_kernel import certified, nearest_among, settle_ties
from .metric_kernel import run_rows
from .triangulation import PARALLEL_QUERY, QUERY_WORKERS

INITIAL_CANDIDATES = 8
# Hulls of at most this many triangles are searched whole (every_triangle): during insertion's first rounds at 10^6
# points ~0.5-1 M points lie outside a 20-30 triangle hull, where testing every triangle (0.12 s a round) is quicker
# than the centroid tree's query and the certificate (0.19 s; measured on ctf_compromise at 0.81 m).
SMALL_HULL_FACES = 32
# Also searched whole when the points times the triangles are at most this many pairs: a refinement round's few points
# outside a hull of hundreds of triangles are tested in less time than the centroid tree takes to build, query and
# certify (the validation crops' 1,035 calls of the default at tau: 0.24 s against 0.33 s, the same answers).
WHOLE_SEARCH_PAIRS = 1 << 14
PROJECTION_TOLERANCE = 4e-12  # supporting-plane slack per unit distance (local units, extent ~1)
# Hull triangles within this relative distance of the nearest one are a tie (quality.md §1 "Ties"); their closest points
# then lie within TIE_REACH / 2 x the distance of the nearest point (convexity), so a nearest point farther than
# TIE_REACH x the distance from its triangle's edges has no tie.
HULL_TIE = 1e-9
TIE_REACH = 2.0 * math.sqrt(2.0 * HULL_TIE + HULL_TIE ** 2)
CHUNK_PAIRS = 1 << 20  # point-triangle or point-vertex pairs per pass (bounds temporaries)


@dataclass(frozen=True)
class HullProjection:
    face: np.ndarray  # (M,) int64 triangle index (extra triangles follow the indexed ones)
    weights: np.ndarray  # (M, 3) float64, >= 0, sum 1
    anchor: np.ndarray  # (M, 3) float64 nearest point on the hull
    distance: np.ndarray  # (M,) float64


def _nearest_among(query: np.ndarray, corners: np.ndarray, candidates: np.ndarray, allowed: np.ndarray | None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For points (M, 3) and candidate triangles (M, k): best triangle (the first of the nearest), weights, anchor,
    distance (distance inf when no candidate is allowed); hull_kernel.nearest_among."""
    m = query.shape[0]
    face = np.empty(m, dtype=np.int64)
    weights = np.empty((m, 3))
    anchor = np.empty((m, 3))
    distance = np.empty(m)
    use_allowed = allowed is not None
    q = np.ascontiguousarray(query, dtype=np.float64)
    c = np.ascontiguousarray(corners, dtype=np.float64)
    usable = np.ascontiguousarray(allowed if use_allowed else np.zeros(1, dtype=bool))
    # Candidates may be a broadcast view: copied in slices, always writable (a one-row slice of a view is contiguous but
    # read-only, and numba compiles read-only arrays as another type: ~1 s the warm-up would not have done).
    rows = max(1, CHUNK_PAIRS // max(candidates.shape[1], 1))
    for start in range(0, m, rows):
        part = slice(start, min(start + rows, m))
        block = q[part]
        run_rows(nearest_among, block.shape[0] * max(1, candidates.shape[1] // 8), block, c,
                 np.require(candidates[part], np.int64, ["C", "W"]), usable, use_allowed, face[part], weights[part],
                 anchor[part], distance[part])
    return face, weights, anchor, distance


class HullIndex:
    """Hull triangles (H, 3) over points (K, 3) with a centroid tree, for repeated nearest queries."""

    def __init__(self, points: np.ndarray, faces: np.ndarray):
        self.points = points
        self.faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
        self.corners = points[self.faces]  # (H, 3, 3)
        self.tree = cKDTree(self.corners.mean(axis=1)) if self.faces.shape[0] else None

    def nearest(self, query: np.ndarray, allowed: np.ndarray | None = None,
                extra_faces: np.ndarray | None = None) -> HullProjection:
        """Nearest point among the allowed indexed triangles and `extra_faces` (E, 3), for points (M, 3).

        The allowed and extra triangles must together be the whole boundary of a convex hull.
        Faces are numbered indexed first, then extra (H + e).
        """
        q = np.asarray(query, dtype=np.float64).reshape(-1, 3)
        m, h = q.shape[0], self.faces.shape[0]
        extra = np.zeros((0, 3), dtype=np.int64) if extra_faces is None else np.asarray(extra_faces, np.int64)
        usable = np.ones(h, dtype=bool) if allowed is None else np.asarray(allowed, dtype=bool)
        if not np.any(usable) and extra.shape[0] == 0:
            raise ValueError("the hull has no triangles")
        all_corners = np.concatenate([self.corners, self.points[extra]])
        all_usable = np.concatenate([usable, np.ones(extra.shape[0], dtype=bool)])
        hull_vertices = self.points[np.unique(np.concatenate([self.faces[usable].reshape(-1), extra.reshape(-1)]))]
        candidates = [np.broadcast_to(np.arange(h, h + extra.shape[0]), (m, extra.shape[0]))]
        if h:
            k = min(INITIAL_CANDIDATES, h)
            workers = QUERY_WORKERS if m >= PARALLEL_QUERY else 1  # threads cost more than small queries take
            candidates.append(np.asarray(self.tree.query(q, k=k, workers=workers)[1], dtype=np.int64).reshape(m, k))
        face, weights, anchor, distance = _nearest_among(q, all_corners, np.concatenate(candidates, axis=1),
                                                         all_usable)
        # Supporting-plane certificate; points failing it are settled against every triangle.
        pending = np.flatnonzero(~_is_projection(q, anchor, distance, hull_vertices))
        if pending.shape[0]:
            everything = np.flatnonzero(all_usable)
            f, w, a, d = _nearest_among(q[pending], all_corners,
                                        np.broadcast_to(everything, (pending.shape[0], everything.shape[0])), None)
            face[pending], weights[pending], anchor[pending], distance[pending] = f, w, a, d
        return HullProjection(face=face, weights=weights, anchor=anchor, distance=distance)


def nearest_on_candidates(points: np.ndarray, faces: np.ndarray, query: np.ndarray, hull_points: np.ndarray
                          ) -> tuple[HullProjection, np.ndarray]:
    """Nearest point among the candidate triangles (F, 3) for each query (M, 3), and whether it is
    certified as the nearest point of conv(hull_points) (supporting-plane test).

    Each point first tries its INITIAL_CANDIDATES nearest triangles (by centroid); the points whose
    answer is not certified then try all the candidates.
    """
    q = np.asarray(query, dtype=np.float64).reshape(-1, 3)
    if faces.shape[0] <= 2 * INITIAL_CANDIDATES:
        whole = every_triangle(points, faces, q)
        return whole, _is_projection(q, whole.anchor, whole.distance, hull_points)
    corners = points[faces]
    nearest = np.asarray(cKDTree(corners.mean(axis=1)).query(q, k=INITIAL_CANDIDATES)[1], dtype=np.int64)
    face, weights, anchor, distance = _nearest_among(q, corners, nearest.reshape(q.shape[0], -1), None)
    certified = _is_projection(q, anchor, distance, hull_points)
    retry = np.flatnonzero(~certified)
    if retry.shape[0]:
        again = every_triangle(points, faces, q[retry])
        face[retry], weights[retry] = again.face, again.weights
        anchor[retry], distance[retry] = again.anchor, again.distance
        certified[retry] = _is_projection(q[retry], again.anchor, again.distance, hull_points)
    return HullProjection(face=face, weights=weights, anchor=anchor, distance=distance), certified


def _is_projection(query: np.ndarray, anchor: np.ndarray, distance: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """(q - p).(x - p) <= tolerance for all hull vertices x: p is the nearest point of the hull to q. The slack is
    proportional to |q - p|: an accepted p is the nearest point to ~1e-11 of the extent (hull_kernel.certified)."""
    ok = np.empty(query.shape[0], dtype=bool)
    run_rows(certified, query.shape[0] * max(1, vertices.shape[0] // 8), np.ascontiguousarray(query, dtype=np.float64),
             np.ascontiguousarray(anchor, dtype=np.float64), np.ascontiguousarray(distance, dtype=np.float64),
             np.ascontiguousarray(vertices, dtype=np.float64), PROJECTION_TOLERANCE, ok)
    return ok


def project_to_hull(points: np.ndarray, faces: np.ndarray, query: np.ndarray, owners: np.ndarray | None = None
                    ) -> HullProjection:
    """Nearest point on the triangles `faces` (H, 3) over `points` (K, 3) for each query (M, 3). With the triangles'
    owning tetrahedra `owners` (H,), a nearest point on a hull edge or vertex takes the tie rule's triangle
    (lowest_owner_at_ties)."""
    triangles = np.asarray(faces).reshape(-1, 3).shape[0]
    if owners is not None and (triangles <= SMALL_HULL_FACES
                               or triangles * np.asarray(query).reshape(-1, 3).shape[0] <= WHOLE_SEARCH_PAIRS):
        projection = every_triangle(points, faces, query)
        return lowest_owner_at_ties(points, faces, owners, query, projection)
    projection = HullIndex(points, faces).nearest(query)
    return projection if owners is None else lowest_owner_at_ties(points, faces, owners, query, projection)


def every_triangle(points: np.ndarray, faces: np.ndarray, query: np.ndarray) -> HullProjection:
    """The nearest point among every triangle `faces` (H, 3) over `points` for each query (M, 3): exact without the
    centroid tree or the certificate, the first of the nearest in triangle order (HullIndex.nearest may take another of
    exactly equal distance; lowest_owner_at_ties then settles both alike)."""
    q = np.asarray(query, dtype=np.float64).reshape(-1, 3)
    triangles = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    every = np.broadcast_to(np.arange(triangles.shape[0]), (q.shape[0], triangles.shape[0]))
    face, weights, anchor, distance = _nearest_among(q, points[triangles], every, None)
    return HullProjection(face=face, weights=weights, anchor=anchor, distance=distance)


def lowest_owner_at_ties(points: np.ndarray, faces: np.ndarray, owners: np.ndarray, query: np.ndarray,
                         projection: HullProjection) -> HullProjection:
    """quality.md §1 "Ties" outside the hull (hull_kernel.settle_ties): among the hull triangles whose distance is within
    a relative HULL_TIE of the smallest, the one of the lowest owning tetrahedron (then of the smallest sorted corners),
    its nearest point snapped onto the hull edge or vertex they all hold. Such triangles pass within TIE_REACH / 2 x the
    distance of the nearest point (convexity), so only points nearer than TIE_REACH x the distance to their triangle's
    edges are looked at again, against the hull triangles at that triangle's corners (any triangle that near the nearest
    point has one of them as a corner, unless the hull has triangles narrower than that)."""
    flat = faces.reshape(-1)
    by_corner = np.argsort(flat, kind="stable")
    faces_at = (by_corner // 3).astype(np.int64)  # the hull triangles at each probe, ascending
    faces_at_start = np.searchsorted(flat[by_corner], np.arange(points.shape[0] + 1)).astype(np.int64)
    # Per triangle and corner: the opposite edge's length over twice the area (1 / the corner's altitude).
    corners = points[faces]
    opposite = corners[:, [2, 0, 1]] - corners[:, [1, 2, 0]]
    twice_area = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    edge_over_area = np.linalg.norm(opposite, axis=2) / twice_area[:, None]
    face, weights, anchor, distance = (projection.face.copy(), projection.weights.copy(), projection.anchor.copy(),
                                       projection.distance.copy())
    run_rows(settle_ties, face.shape[0], points, np.ascontiguousarray(faces, dtype=np.int64),
             np.ascontiguousarray(owners, dtype=np.int64), faces_at_start, faces_at, edge_over_area,
             np.ascontiguousarray(np.asarray(query, dtype=np.float64).reshape(-1, 3)), TIE_REACH, HULL_TIE, face,
             weights, anchor, distance)
    return HullProjection(face=face, weights=weights, anchor=anchor, distance=distance)
