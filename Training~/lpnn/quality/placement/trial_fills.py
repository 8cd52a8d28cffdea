"""The tetrahedra that refill each candidate's star in a batched refinement trial, without a global tetrahedralisation
(quality.md §5.3).

    fills = star_fills(field, state, candidates)   # None: let Qhull tetrahedralise the trial instead
    trial_tets = np.concatenate([state.tets[no candidate], fills.tets])

Why. A trial removes an independent set of candidates; their stars are disjoint and each is refilled by its own link
(metric/triangulation.py: the tie-broken Delaunay is unique, so nothing outside the stars changes). The fills are the
regular tetrahedra of the lifted link that lie in the star — the gift wrapping of the fast reference
(decimation/hole_wrap.py, ~10x faster than one Qhull call per probe); for a hull vertex the wrapping lets a face of the
star's boundary, too, end on the new hull (hole_wrap.HULL_VERTEX: the star minus the part the hull loses). For a hole
the wrapping could not close, or a hull vertex with a point in a face's on-plane band that would make a sliver
(hole_wrap.SLIVER_IN_BAND) or whose wrapped refill holds one (SLIVER_RELATIVE_VOLUME), the lower hull of its lifted
link, keeping the tetrahedra whose centroid lies in its star (the tetrahedra of Del(link) inside the star are exactly
the refill: the star minus the part the hull loses is covered by the refill, which belongs to Del(link) too, and two
tetrahedra of one triangulation do not overlap). Wrapping the hull vertices as well took the validation crops'
lifted-link Qhull calls from 1,716 to 161 (benchmarks.md "Hull vertices wrapped, small locations walked").
One global Qhull call per round was ~30 % of the refinement's time on whole levels (benchmarks.md "Scale: whole
levels"); the fills cost a fraction of it and give the same tetrahedra.

Checked before use: an interior star's fills have its volume (to VOLUME_TOLERANCE), a hull vertex's at most its volume;
the caller then assembles the whole trial mesh, which must use every remaining probe, be a manifold and have no crack
the state had not (batched_state.derived_mesh: a hull vertex's refill that left part of its star empty). Any failure,
or a star next to a crack (INNER_BOUNDARY: a flat tetrahedron Qhull dropped, so the star is not closed), returns None
and the round tetrahedralises with Qhull as before.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ...core.integer_sets import sorted_unique
from ...scenes.ranges import concatenated_ranges
from .decimation.hole_wrap import HULL_VERTEX, INTERIOR, ON_HULL, wrap_hole_runs
from ..metric.metric import ReferenceField
from ..metric.tet_geometry import edge_frames, edge_product, is_flat
from ..metric.triangulation import HULL, INNER_BOUNDARY, GeometryError, corners_of_faces, lower_hull_tets

VOLUME_TOLERANCE = 1e-9  # an interior star's fills must have its volume to this relative tolerance
INSIDE_TOLERANCE = 1e-9  # a fill's centroid is in the star when its barycentric weights are >= -this in a star tetrahedron
# A hull vertex's wrapped refill holding a tetrahedron this thin (6 x volume over its edges' product; a tetrahedron of
# grid points is >= ~1e-2, float32 rounding's slivers ~1e-7) is left to Qhull: the two may pick different slivers.
SLIVER_RELATIVE_VOLUME = 1e-5


@dataclass(frozen=True)
class Fills:
    """Each candidate star's refill: tetrahedra (F, 4), global point ids, positively oriented, the same as positions in
    the state's probes (batched_state.derived_mesh maps those without a search), and the candidate whose star each
    fills."""

    tets: np.ndarray
    owner: np.ndarray
    positions: np.ndarray


def star_fills(field: ReferenceField, state, candidates: np.ndarray) -> Fills | None:
    """The refill of every candidate's star (module text), or None when the round should tetrahedralise with Qhull.
    `state`: a batched_state.MeshState (not imported: that module imports this one); `candidates`: independent in its
    Delaunay graph."""
    mesh = state.mesh
    probes = state.probes
    local = mesh.points
    position = np.searchsorted(probes, candidates)  # candidates as positions in the probes
    is_candidate = np.zeros(probes.shape[0], dtype=bool)
    is_candidate[position] = True
    tets = mesh.tets
    holds = is_candidate[tets]  # independent candidates: at most one per tetrahedron
    in_star = holds.any(axis=1)
    if np.any(mesh.neighbours[in_star] == INNER_BOUNDARY):
        return None
    star_rows = np.flatnonzero(in_star)
    star_owner = tets[star_rows][holds[star_rows]]  # the candidate (position) of each star tetrahedron
    by_owner = np.argsort(star_owner, kind="stable")
    star_rows, star_owner = star_rows[by_owner], star_owner[by_owner]
    bounds = np.searchsorted(star_owner, position)
    ends = np.searchsorted(star_owner, position, side="right")
    on_surface = np.zeros(probes.shape[0], dtype=bool)
    on_surface[corners_of_faces(tets, mesh.neighbours == HULL)] = True
    try:  # the hull's vertices are on its faces: its 3-D hull built of those probes alone (the same vertices, faster)
        surface = np.flatnonzero(on_surface)
        extreme = np.zeros(probes.shape[0], dtype=bool)
        extreme[surface[ConvexHull(local[surface]).vertices]] = True
    except QhullError:
        return None
    tie = field.frame.tie_heights(mesh.world)
    count = position.shape[0]
    candidate_at = np.zeros(probes.shape[0], dtype=np.int64)  # position -> the candidate's place in `candidates`
    candidate_at[position] = np.arange(count)
    star_volume = np.bincount(candidate_at[star_owner], np.abs(edge_frames(local, tets[star_rows])[3]), minlength=count)
    # Every candidate's star as one array (each star's rows in star_rows' order) and their wraps as runs of one array:
    # no list of small arrays per candidate (~2,500 a round on whole levels).
    sizes = ends - bounds
    star_start = np.zeros(count + 1, dtype=np.int64)
    np.cumsum(sizes, out=star_start[1:])
    hull = np.where(extreme[position], HULL_VERTEX, np.where(on_surface[position], ON_HULL, INTERIOR))
    out, out_start, counts = wrap_hole_runs(local, tie, position, tets[star_rows[concatenated_ranges(bounds, sizes)]],
                                            star_start, hull)
    wrapped = counts > 0
    closed = np.flatnonzero(wrapped)
    owner = np.repeat(closed, counts[wrapped])
    fill, volume6, kept = _oriented(local, out[concatenated_ranges(out_start[:-1][wrapped], counts[wrapped])])
    owner = owner[kept]
    filled = np.bincount(owner, volume6, minlength=count)
    # A closed star's fill has its volume; a hull vertex's at most its volume (the hull loses the rest), and no sliver:
    # where rounding left one (collinear probes on a hull face), the wrapping and Qhull's `Qt` may pick different ones.
    good = wrapped & _volume_fits(filled, star_volume, extreme[position])
    at_vertex = np.flatnonzero(extreme[position][owner])  # the hull vertices' fills alone: a few per round
    good &= np.bincount(owner[at_vertex[_slivers(local, fill[at_vertex])]], minlength=count) == 0
    keep = good[owner]
    fill, owner = [fill[keep]], [owner[keep]]
    for k in np.flatnonzero(~good).tolist():  # holes not wrapped, hull vertices refused: the lifted link
        star = tets[star_rows[bounds[k]:ends[k]]]
        linked = _link_fill(local, tie, int(position[k]), star)
        if linked is None:
            return None
        if not _volume_fits(float(linked[1].sum()), star_volume[k], extreme[position[k]]):
            return None
        fill.append(linked[0])
        owner.append(np.full(linked[0].shape[0], k, dtype=np.int64))
    positions = np.concatenate(fill)
    return Fills(tets=probes[positions], owner=probes[position[np.concatenate(owner)]], positions=positions)


def _volume_fits(filled, star, at_vertex):
    """Whether a refill's volume `filled` checks out against its star's `star` (arrays or numbers alike): an interior
    star's (or one on a flat part of the hull) to VOLUME_TOLERANCE, a hull vertex's (`at_vertex`) at most the star's."""
    return np.where(at_vertex, filled <= star * (1.0 + VOLUME_TOLERANCE), np.abs(filled - star) <= VOLUME_TOLERANCE * star)


def _slivers(local: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """(T,) bool: the tetrahedra whose 6 x volume is at most SLIVER_RELATIVE_VOLUME x the product of their edges from
    vertex 0 (kept by tet_geometry.is_flat, yet thin enough to be rounding's)."""
    e1, e2, e3, det = edge_frames(local, tets)
    return np.abs(det) <= SLIVER_RELATIVE_VOLUME * edge_product(e1, e2, e3)


def _oriented(local: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The tetrahedra positively oriented, the flat ones dropped, as the tetrahedralisation does (a flat fill is one
    Qhull's `Qt` leaves out too: metric/triangulation.py): tetrahedra, 6 x volumes, the mask of the rows kept."""
    e1, e2, e3, det = edge_frames(local, tets)
    kept = ~is_flat(e1, e2, e3, det)
    out = tets[kept].copy()
    negative = det[kept] < 0.0
    out[negative, 2], out[negative, 3] = tets[kept][negative, 3], tets[kept][negative, 2]
    return out, np.abs(det[kept]), kept


def _link_fill(local: np.ndarray, tie: np.ndarray, v: int, star: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray] | None:
    """The regular tetrahedra of v's link whose centroid lies in v's star (module text), oriented, and their 6 x
    volumes; None when Qhull cannot tetrahedralise the link. A link of three probes (a hull vertex whose star is one
    tetrahedron, e.g. a corner of a lattice) has no tetrahedra, and its refill is none: the hull loses the whole star
    (the C# core's StarRefills.LinkFill, the same rule). Before 2026-11-29 Qhull refused the three points and the whole
    round was tetrahedralised (ctf_compromise's 30 % budget, leak-aware: 571 s, now 60 s; benchmarks.md "A hull corner
    refilled by nothing")."""
    link = sorted_unique(star[star != v])
    if link.shape[0] < 4:
        return np.zeros((0, 4), dtype=np.int64), np.zeros(0)
    relative = local[link] - local[v]
    lifted = np.concatenate([relative, (np.einsum("ij,ij->i", relative, relative) + tie[link])[:, None]], axis=1)
    try:
        candidates = link[lower_hull_tets(lifted)]
    except GeometryError:
        return None
    if candidates.shape[0] == 0:
        return None
    e1, e2, e3, _ = edge_frames(local, star)
    # Barycentric weights of a point x in star tetrahedron (s0, s1, s2, s3): solve [e1 e2 e3] w = x - s0.
    frames = np.stack([e1, e2, e3], axis=2)  # (S, 3, 3), columns the edges
    try:
        to_weights = np.linalg.inv(frames)
    except np.linalg.LinAlgError:
        return None
    centroids = local[candidates].mean(axis=1)
    offsets = centroids[:, None, :] - local[star[:, 0]][None, :, :]  # (C, S, 3)
    weights = np.einsum("syx,csx->csy", to_weights, offsets)
    inside = ((weights.min(axis=2) >= -INSIDE_TOLERANCE) & (weights.sum(axis=2) <= 1.0 + INSIDE_TOLERANCE)).any(axis=1)
    return _oriented(local, candidates[inside])[:2]
