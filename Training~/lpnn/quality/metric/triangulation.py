"""Tetrahedralisation of a probe set, the way the quality metric interpolates (quality.md §1).

A Delaunay tetrahedralisation computed as the lower convex hull of the points lifted to 4-D
(Qhull `Qt`). Grids are cospherical, so their Delaunay tetrahedralisation is not unique
and Qhull's own `Delaunay` resolves the ties with zero-volume "flat" tetrahedra whose two sides
disagree about a square's diagonal (C0-discontinuous interpolation) and that slow point location
down. We add a tiny, deterministic height to each lifted point (a hash of its world position, at
most 1e-5 of the squared point spacing): the result is a *regular* triangulation that is a Delaunay
triangulation of the points with every tie broken consistently, so it
- keeps every point as a vertex and, almost everywhere, has no flat tetrahedra and is conforming (C0 interpolation);
  but Qhull merges lifted facets nearly on one hyperplane (e.g. five lattice points of a ramp whose float32 rounding
  puts them within its precision of one sphere) and `Qt` triangulates such a facet with a flat simplex, which is
  dropped: the faces it shared keep no tetrahedron across, inside the hull (a *crack*; INNER_BOUNDARY below);
- is unique for a given set, and the same point always gets the same height, so removing a probe
  changes only the tetrahedra around it (the fast reference relies on this);
- equals the plain Delaunay tetrahedralisation wherever that one is unique.

All geometry is done in a local frame (translated to the centre of the candidate set, divided by
its extent), so tolerances are relative and positions far from the origin work.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError, cKDTree

from ...errors import InvalidInputError
from .tet_geometry import edge_inverse, orient_and_invert
from .tet_numbering import GOLDEN_GAMMA, mix64, numbered

DUPLICATE_TOLERANCE = 1e-7  # two probes closer than this fraction of the extent are duplicates
FLAT_TOLERANCE = 1e-7  # a set thinner than this fraction of its length is coplanar/collinear
TIE_BREAK_FRACTION = 1e-5  # lifted-height perturbation, as a fraction of the squared spacing
LOWER_FACET_TOLERANCE = 1e-10  # 4-D facet normals with w-component above -this are not lower facets
QHULL_OPTIONS = "Qt"  # triangulated output; no Qbb/Qz: those are for Qhull's own Delaunay mode
VERTEX_KEY_BITS = 21  # three vertex ids fit one int64 face key when there are < 2^21 points
QUERY_WORKERS = -1  # the spacing's nearest-neighbour query on every core (same distances; ~1 s less at 10^6 points)
PARALLEL_QUERY = 20_000  # placement's k-d queries of at least this many points use QUERY_WORKERS, smaller ones one thread
HULL = -1  # `neighbours` across a face on the convex hull: nothing lies beyond its plane
INNER_BOUNDARY = -2  # `neighbours` across a face no tetrahedron shares that is not on the hull: the crack a dropped flat
# tetrahedron leaves (module text). Beyond its plane there are tetrahedra, so a walk must not conclude "outside" there.
HULL_SUPPORT_TOLERANCE = 1e-12  # a face is on the hull when no probe lies beyond its plane by more than this (local units:
# rounding puts hull vertices <= 3e-16 beyond their own faces' planes, a crack has probes a cell or more beyond; a face
# in between counts as a crack, which costs its points a brute-force location and nothing else)


class GeometryError(InvalidInputError):
    """The probe set cannot be tetrahedralised; the message names the problem and what to do."""


# --------------------------------------------------------------------------------------- the frame

def position_hash(world: np.ndarray) -> np.ndarray:
    """A deterministic value in [0, 1) per position (M, 3), a function of the float64 bits only."""
    bits = np.ascontiguousarray(world, dtype=np.float64).view(np.uint64).reshape(-1, 3)
    with np.errstate(over="ignore"):  # uint64 wrap-around is the point of the hash
        key = mix64(bits[:, 0] + GOLDEN_GAMMA)
        key = mix64(key ^ bits[:, 1])
        key = mix64(key ^ bits[:, 2])
    return (key >> np.uint64(11)).astype(np.float64) / float(2**53)


@dataclass(frozen=True)
class Frame:
    """Local coordinates shared by every triangulation of subsets of one candidate set."""

    origin: np.ndarray  # (3,) float64, world
    scale: float  # world length of one local unit (the candidate set's largest extent)
    tie_break: float  # lifted-height perturbation amplitude, local units squared

    @staticmethod
    def for_points(world: np.ndarray) -> "Frame":
        points = checked_positions(world, "positions")
        lo, hi = points.min(axis=0), points.max(axis=0)
        scale = float(np.max(hi - lo))
        if not scale > 0.0:
            raise GeometryError(
                f"all {points.shape[0]:,} positions coincide at {lo.tolist()}: a tetrahedralisation needs "
                "at least 4 probes that are not all in one plane")
        origin = (lo + hi) / 2.0
        local = (points - origin) / scale
        spacing = 1.0
        if points.shape[0] >= 2:
            distances = cKDTree(local).query(local, k=2, workers=QUERY_WORKERS)[0][:, 1]
            positive = distances[distances > 0.0]
            if positive.shape[0]:
                spacing = float(np.median(positive))
        return Frame(origin=origin, scale=scale, tie_break=TIE_BREAK_FRACTION * spacing * spacing)

    def to_local(self, world: np.ndarray) -> np.ndarray:
        return (np.asarray(world, dtype=np.float64) - self.origin) / self.scale

    def to_world(self, local: np.ndarray) -> np.ndarray:
        return np.asarray(local, dtype=np.float64) * self.scale + self.origin

    def tie_heights(self, world: np.ndarray) -> np.ndarray:
        """(M,): each position's deterministic perturbation of the lifted height."""
        return self.tie_break * position_hash(world)

    def lifted(self, world: np.ndarray) -> np.ndarray:
        """(M, 4): local coordinates and the perturbed paraboloid height."""
        local = self.to_local(world)
        height = np.einsum("ij,ij->i", local, local) + self.tie_heights(world)
        return np.concatenate([local, height[:, None]], axis=1)


def checked_positions(world: np.ndarray, what: str) -> np.ndarray:
    points = np.asarray(world, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise GeometryError(f"{what} need shape (N, 3), got {list(points.shape)}")
    bad = np.flatnonzero(~np.all(np.isfinite(points), axis=1))
    if bad.shape[0]:
        raise GeometryError(f"{what}[{int(bad[0])}] = {points[bad[0]].tolist()} is not finite "
                            f"({bad.shape[0]:,} bad rows): every coordinate must be a finite number")
    return points


# ------------------------------------------------------------------------------- the triangulation

@dataclass(frozen=True)
class Tetrahedralization:
    frame: Frame
    world: np.ndarray  # (K, 3) float64 probe positions
    points: np.ndarray  # (K, 3) float64 local coordinates
    tets: np.ndarray  # (T, 4) int64, positively oriented
    neighbours: np.ndarray  # (T, 4) int64: tetrahedron across the face opposite vertex i, else HULL or INNER_BOUNDARY
    inverse: np.ndarray  # (T, 3, 3): barycentric transform, lambda_1..3 = inverse @ (x - v0)
    hull_faces: np.ndarray  # (H, 3) int64 boundary triangles (a crack's included), counter-clockwise seen from outside
    hull_face_tets: np.ndarray  # (H,) int64 tetrahedron owning each boundary triangle

    @property
    def point_count(self) -> int:
        return int(self.points.shape[0])


def _check_not_duplicate(local: np.ndarray, world: np.ndarray) -> None:
    distances, neighbours = cKDTree(local).query(local, k=2)
    close = np.flatnonzero(distances[:, 1] <= DUPLICATE_TOLERANCE)
    if close.shape[0]:
        a = int(close[0])
        b = int(neighbours[a, 1])
        a, b = min(a, b), max(a, b)
        raise GeometryError(
            f"probe positions {a} and {b} coincide ({world[a].tolist()} and {world[b].tolist()} are closer than "
            f"{DUPLICATE_TOLERANCE:g} of the extent; {close.shape[0]:,} probes have such a twin): remove duplicates")


def flatness(local: np.ndarray) -> str | None:
    """'line' or 'plane' when the points are (within FLAT_TOLERANCE) collinear or coplanar, else None."""
    if local.shape[0] < 3:
        return "line"
    centred = local - local.mean(axis=0)
    axes = np.linalg.svd(centred, full_matrices=False)[2]
    extent = np.ptp(centred @ axes.T, axis=0)  # length along the principal axes, largest first
    if extent.shape[0] < 2 or extent[1] <= FLAT_TOLERANCE * extent[0]:
        return "line"
    if local.shape[0] < 4 or extent[2] <= FLAT_TOLERANCE * extent[0]:
        return "plane"
    return None


def _check_not_flat(local: np.ndarray) -> None:
    shape = flatness(local)
    if shape == "line":
        raise GeometryError(
            f"all {local.shape[0]:,} probes lie on one line: a tetrahedralisation needs at least 4 probes "
            "that are not all in one plane (add probes off that line)")
    if shape == "plane":
        raise GeometryError(
            f"all {local.shape[0]:,} probes lie in one plane: a tetrahedralisation needs at least 4 probes "
            "that are not all in one plane (add a probe off that plane, e.g. make the volume two cells deep)")


def face_keys(faces: np.ndarray, vertex_count: int) -> np.ndarray:
    """One int64 per triangle, independent of vertex order (sorted ids packed, or a row rank)."""
    ordered = np.sort(faces, axis=1).astype(np.int64)
    if vertex_count < (1 << VERTEX_KEY_BITS):
        return (ordered[:, 0] << (2 * VERTEX_KEY_BITS)) | (ordered[:, 1] << VERTEX_KEY_BITS) | ordered[:, 2]
    return np.unique(ordered, axis=0, return_inverse=True)[1].reshape(-1).astype(np.int64)


NOT_A_MANIFOLD = ("the tetrahedralisation is not a manifold (a face is shared by 3 tetrahedra); report this probe set "
                  "as a bug")


def _face_pairs(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The pairs of positions whose face keys are equal (each face in two tetrahedra); GeometryError when a face is in
    three. Either order of a pair does: both positions get the other's tetrahedron (so the faster unstable sort)."""
    order = np.argsort(keys)
    sorted_keys = keys[order]
    same_as_next = sorted_keys[1:] == sorted_keys[:-1]
    if np.any(same_as_next[1:] & same_as_next[:-1]):
        raise GeometryError(NOT_A_MANIFOLD)
    return order[:-1][same_as_next], order[1:][same_as_next]


def _adjacency(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """neighbours (T, 4) (HULL / INNER_BOUNDARY where no tetrahedron is across), boundary faces (H, 3) oriented outward,
    and their tetrahedra (H,)."""
    from .removal_kernel import boundary_faces, face_vertices  # compiled (removal_kernel.py)

    tets = np.ascontiguousarray(tets, dtype=np.int64)
    count = tets.shape[0]
    every_face = np.arange(4 * count, dtype=np.int64)
    first, second = _matched_faces(tets, every_face, points.shape[0])
    neighbours = np.full(4 * count, HULL, dtype=np.int64)
    neighbours[first] = second // 4
    neighbours[second] = first // 4
    boundary = boundary_faces(neighbours)
    corners = face_vertices(tets, boundary)
    neighbours[boundary[~_on_hull_of_boundary(points, corners, corners)]] = INNER_BOUNDARY
    return neighbours.reshape(count, 4), corners, boundary // 4


def _matched_faces(tets: np.ndarray, positions: np.ndarray, vertex_count: int) -> tuple[np.ndarray, np.ndarray]:
    """The pairs of faces `positions` (4 x tetrahedron + j, the face opposite vertex j) that are one triangle: through a
    hash table of their keys (removal_kernel.paired_faces) when the vertex ids fit face_keys' packing, else by sorting
    the keys; GeometryError when a face is in three tetrahedra."""
    from .removal_kernel import face_vertices, paired_faces

    if vertex_count < (1 << VERTEX_KEY_BITS):
        first, second, manifold = paired_faces(tets, positions, VERTEX_KEY_BITS)
        if not manifold:
            raise GeometryError(NOT_A_MANIFOLD)
    else:
        first, second = _face_pairs(face_keys(face_vertices(tets, positions), vertex_count))
    return positions[first], positions[second]


def _on_hull_of_boundary(points: np.ndarray, faces: np.ndarray, boundary_corners: np.ndarray) -> np.ndarray:
    """on_hull of `faces` (F, 3), some of a tetrahedralisation's boundary faces `boundary_corners` (H, 3): every vertex
    of the hull is a corner of a boundary face, so the 3-D hull is built of those alone (the same hull vertices from
    fewer points), or the faces are tested against every point when they are few."""
    if faces.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    few = faces.shape[0] <= FEW_HULL_FACES
    return on_hull(points, faces, every_point=few, outer=None if few else np.unique(boundary_corners))


def corners_of_faces(tets: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The vertex ids (with repeats) of the faces flagged in `faces` (T, 4) bool, face j of a tetrahedron being the one
    opposite its vertex j, as in `neighbours`: the hull's vertices are corners_of_faces(tets, neighbours == HULL)."""
    rows, opposite = np.nonzero(faces)
    return np.concatenate([tets[rows[opposite != j], j] for j in range(4)])


HULL_TEST_BLOCK = 1 << 20  # face-vertex pairs per block of on_hull's test (8 MiB of distances)
# Up to this many faces on_hull tests against every point rather than building the convex hull first: the test costs
# ~7 ns a face and point, Qhull's 3-D hull ~0.15-0.3 us a point (measured on this machine, 600-20,000 points).
FEW_HULL_FACES = 32


def on_hull(points: np.ndarray, faces: np.ndarray, every_point: bool = False,
            outer: np.ndarray | None = None) -> np.ndarray:
    """(F,) bool: which boundary faces (F, 3), counter-clockwise seen from outside, lie on the convex hull of `points`
    (K, 3): no hull vertex beyond the face's plane by more than HULL_SUPPORT_TOLERANCE. The others are cracks
    (INNER_BOUNDARY). Tested against Qhull's hull vertices, or against every point (`every_point`, or when Qhull
    fails): the same answer — a plane's farthest point is a hull vertex — slower for many faces, faster for a few
    (no hull to build: assembled_after_removal tests only the faces a removal opened). `outer`: indices of points among
    which every vertex of the hull is (e.g. the corners of a tetrahedralisation's boundary faces), so the hull is built
    of those alone: the same hull vertices, hence the same answer, from fewer points."""
    if faces.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    extreme = points
    if not every_point:
        candidates = points if outer is None else points[outer]
        try:
            extreme = candidates[ConvexHull(candidates).vertices]
        except QhullError:
            pass
    a = points[faces[:, 0]]
    normal = np.cross(points[faces[:, 1]] - a, points[faces[:, 2]] - a)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    offset = np.einsum("ij,ij->i", normal, a)
    beyond = np.empty(faces.shape[0])
    step = max(1, HULL_TEST_BLOCK // extreme.shape[0])
    for lo in range(0, faces.shape[0], step):
        beyond[lo:lo + step] = (extreme @ normal[lo:lo + step].T).max(axis=0) - offset[lo:lo + step]
    return beyond <= HULL_SUPPORT_TOLERANCE


def lower_hull(lifted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower-hull facets of lifted points (M, 4): tetrahedra (T, 4) and their hyperplanes (T, 5),
    unit normals pointing down-and-out (n.x + d > 0 below a facet). Raises GeometryError on failure."""
    if lifted.shape[0] == 4:  # Qhull needs 5 points in 4-D; 4 non-coplanar points are one tetrahedron
        normal = np.linalg.svd(lifted[1:] - lifted[0])[2][-1]
        normal = -normal if normal[3] > 0.0 else normal
        return np.arange(4, dtype=np.int64)[None, :], np.append(normal, -normal @ lifted[0])[None, :]
    try:
        hull = ConvexHull(lifted, qhull_options=QHULL_OPTIONS)
    except QhullError as exc:
        first_line = str(exc).strip().splitlines()[0] if str(exc).strip() else "Qhull failed"
        raise GeometryError(f"Qhull could not tetrahedralise these {lifted.shape[0]:,} probes ({first_line}); "
                            "check for duplicate or coplanar probes") from exc
    lower = hull.equations[:, 3] < -LOWER_FACET_TOLERANCE
    return np.asarray(hull.simplices[lower], dtype=np.int64), hull.equations[lower]


def lower_hull_tets(lifted: np.ndarray) -> np.ndarray:
    """Tetrahedra (T, 4) of the lower hull of lifted points (M, 4); raises GeometryError on failure."""
    return lower_hull(lifted)[0]


def tetrahedralize(world: np.ndarray, frame: Frame | None = None, ids: np.ndarray | None = None) -> Tetrahedralization:
    """Tetrahedralise probe positions (K, 3), the tetrahedra numbered by §1's rule (tet_numbering.numbered) over the
    probes' point indices `ids` (K,) (None: their positions 0..K-1), so that the numbering does not depend on Qhull's
    facet order nor on the order the probes come in. Raises GeometryError for < 4, duplicate or flat sets."""
    positions = checked_positions(world, "probe positions")
    count = positions.shape[0]
    if count < 4:
        raise GeometryError(f"{count} probe(s) cannot be tetrahedralised: Unity needs at least 4 probes "
                            "that are not all in one plane")
    used_frame = frame if frame is not None else Frame.for_points(positions)
    local = used_frame.to_local(positions)
    _check_not_duplicate(local, positions)
    _check_not_flat(local)
    if ids is not None and np.shape(ids) != (count,):
        raise GeometryError(f"ids need one point index per probe position ({count:,}), got shape {list(np.shape(ids))}")
    return tetrahedralized_from(used_frame, positions, local, lower_hull_tets(used_frame.lifted(positions)), ids)


def tetrahedralized_from(frame: Frame, positions: np.ndarray, local: np.ndarray, lower: np.ndarray,
                         ids: np.ndarray | None = None) -> Tetrahedralization:
    """tetrahedralize's answer from the lower hull's tetrahedra `lower` (T, 4) of the lifted positions (K, 3) (`local`:
    theirs in `frame`), in any order and orientation: Qhull's, or derived by insertion (regular_insertion.py)."""
    # Flat tetrahedra (vertical facets that slipped through, or Qt's in a merged facet) dropped (a crack where they were
    # inside: module text), the rest oriented positively and inverted.
    tets, inverse, _, _ = orient_and_invert(local, numbered(lower, ids))
    used = np.zeros(positions.shape[0], dtype=bool)
    used[tets.reshape(-1)] = True
    if not np.all(used):
        missing = int(np.flatnonzero(~used)[0])
        raise GeometryError(f"probe {missing} at {positions[missing].tolist()} was dropped by the tetrahedralisation "
                            f"({int(np.count_nonzero(~used))} probes dropped); it is (nearly) a duplicate of another probe")
    return _assembled(frame, positions, local, tets, inverse)


def assembled(world: np.ndarray, frame: Frame, tets: np.ndarray) -> Tetrahedralization:
    """The Tetrahedralization of probe positions (K, 3) whose positively oriented tetrahedra (T, 4) are already known,
    e.g. derived from two others by local changes (placement/batched_refinement.py): adjacency, hull and barycentric
    transforms as tetrahedralize computes them. Raises GeometryError when the tetrahedra do not form a manifold."""
    positions = checked_positions(world, "probe positions")
    return _assembled(frame, positions, frame.to_local(positions), np.asarray(tets, dtype=np.int64).reshape(-1, 4))


def assembled_after_removal(old: Tetrahedralization, keep: np.ndarray, vertex_map: np.ndarray, world: np.ndarray,
                            added: np.ndarray) -> Tetrahedralization:
    """assembled(world, old.frame, tets) for tets = [vertex_map[old.tets[keep]]; added], the tetrahedralisation of `old`'s
    probes after some were removed (world: the remaining probes' positions; vertex_map: each old probe's position among
    them, -1 if removed; added (F, 4): positively oriented tetrahedra that refill the removed probes' stars, new
    positions), the same arrays bit for bit without redoing the whole mesh: a kept tetrahedron keeps its barycentric
    transform (the same vertices in the same order) and its neighbours across faces whose neighbour was kept; only the
    added tetrahedra's faces and the kept faces left open are matched again. Raises GeometryError when they do not form
    a manifold."""
    # Compiled passes (removal_kernel.py; imported here: the module's other users need no numba).
    from .removal_kernel import boundary_faces, copy_kept, face_vertices

    positions = checked_positions(world, "probe positions")
    local = old.frame.to_local(positions)
    keep = np.ascontiguousarray(keep, dtype=bool)
    added = np.ascontiguousarray(added, dtype=np.int64).reshape(-1, 4)
    kept_count = int(np.count_nonzero(keep))
    total = kept_count + added.shape[0]
    tets = np.empty((total, 4), dtype=np.int64)
    neighbours = np.empty((total, 4), dtype=np.int64)
    inverse = np.empty((total, 3, 3))
    was_hull = np.zeros(4 * total, dtype=bool)
    opened = np.empty(4 * kept_count, dtype=np.int64)
    open_count, bad = copy_kept(old.tets, old.neighbours, old.inverse, keep,
                                np.ascontiguousarray(vertex_map, dtype=np.int64), HULL, tets, neighbours, inverse,
                                was_hull, opened)
    if bad or np.any(added < 0):
        raise GeometryError("a kept tetrahedron has a removed vertex: not a tetrahedralisation of the remaining probes")
    tets[kept_count:] = added
    inverse[kept_count:] = edge_inverse(local, added)
    neighbours[kept_count:] = HULL
    # Faces to match: the kept ones whose neighbour went, and every face of the added tetrahedra.
    open_faces = np.concatenate([opened[:open_count], 4 * kept_count + np.arange(4 * added.shape[0])])
    first, second = _matched_faces(tets, open_faces, positions.shape[0])
    flat = neighbours.reshape(-1)
    flat[first], flat[second] = second // 4, first // 4
    # A face on the old hull stays on it (the probes left are a subset: no plane that held them all off is crossed
    # now); only the faces opened or left as cracks are tested, against every probe when they are few.
    boundary = boundary_faces(neighbours)
    test = boundary[~was_hull[boundary]]
    boundary_corners = face_vertices(tets, boundary)
    flat[test] = np.where(_on_hull_of_boundary(local, face_vertices(tets, test), boundary_corners), HULL, INNER_BOUNDARY)
    return Tetrahedralization(frame=old.frame, world=positions, points=local, tets=tets, neighbours=neighbours,
                              inverse=inverse, hull_faces=boundary_corners, hull_face_tets=boundary // 4)


def _assembled(frame: Frame, positions: np.ndarray, local: np.ndarray, tets: np.ndarray,
               inverse: np.ndarray | None = None) -> Tetrahedralization:
    neighbours, hull_faces, hull_face_tets = _adjacency(local, tets)
    if inverse is None:
        inverse = edge_inverse(local, tets)
    return Tetrahedralization(frame=frame, world=positions, points=local, tets=tets, neighbours=neighbours,
                              inverse=inverse, hull_faces=hull_faces, hull_face_tets=hull_face_tets)
