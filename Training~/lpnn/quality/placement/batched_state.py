"""The probe-set state of batched refinement (quality.md §5.3): a set evaluated at every point, the trial without an
independent set of candidates (their exact removal costs), and the state without some of them — each evaluated only
where it can change.

    state = evaluate(field, probes)                  # every point located (the seed)
    trial = trial_of(field, state, candidates)       # costs; located only where a candidate's weight reached
    state = without(field, state, removed, trial)    # located only where a removed probe was touched; no Qhull
    boundary = boundary_vertices(state)              # probes whose measured costs a later round must re-measure
    mesh = derived_mesh(field, state, removed, fills.positions)   # both meshes from the state's, not assembled afresh

With a LeakWeighting (evaluate(field, probes, weighting)) every error the state holds, sums and compares is the weighted
one (leak_aware.py): a leaking point's error counts several times, in the costs and in the tolerance alike.

Why only there. Removing a probe retriangulates its own star and nothing else (metric/triangulation.py: the tie-broken
Delaunay is unique), and the convex hull only shrinks, so a point outside it keeps its nearest hull point unless that
point's triangle had a removed vertex. A point whose stencil touched no removed probe (at any weight, zero included)
therefore keeps its stencil and its error; the committed set's tetrahedra are the state's outside the removed stars and
the trial's inside them (refilled). The updated errors equal a fresh evaluation up to rounding (~1e-12): a point on a
face shared by two tetrahedra keeps the one it had where a fresh location may take the other.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...core.integer_sets import sorted_contains, sorted_unique
from ...scenes.ranges import concatenated_ranges
from .delaunay_graph import edges_after_removal, graph_edges
from .leak_aware import LeakWeighting
from ..metric.location import locate_local
from ..metric.metric import ReferenceField, probe_mesh, stencil_point_errors
from ..metric.metric_kernel import run_rows
from ..metric.removal_kernel import count_marker, kept_tetrahedra, uses_every_vertex
from .refinement_kernel import attributed_costs, refill_start_rows, rows_holding_which, stencil_ids
from .trial_fills import Fills, star_fills
from ..metric.triangulation import (INNER_BOUNDARY, GeometryError, Tetrahedralization, assembled_after_removal,
                                    corners_of_faces)


@dataclass(frozen=True)
class MeshState:
    """One probe set evaluated, per point (N rows): the global ids its stencil weighs > 0 (`owners`, -1 elsewhere and
    at the probes), every global id of its stencil, zero weights included (`touched`), its error; the error sum; the
    probes (sorted), their tetrahedralisation and its Delaunay graph's edges (both directions, global ids)."""

    probes: np.ndarray
    owners: np.ndarray  # (N, 4)
    touched: np.ndarray  # (N, 4)
    errors: np.ndarray  # (N,)
    error_sum: float  # errors.sum(), read several times a round
    edges: np.ndarray  # (E, 2)
    mesh: Tetrahedralization  # vertices are positions in `probes`
    weighting: LeakWeighting | None = None  # errors weighted by leaks (leak_aware.py), kept by trials and removals
    replaced: "ReplacedRows | None" = None  # made by without(reuse=True): the rows it overwrote, for restore()

    @property
    def tets(self) -> np.ndarray:
        """(T, 4) global ids."""
        return self.probes[self.mesh.tets]


@dataclass(frozen=True)
class ReplacedRows:
    """The rows of a state's per-point arrays that without(..., reuse=True) overwrote, as they were."""

    rows: np.ndarray
    errors: np.ndarray
    owners: np.ndarray
    touched: np.ndarray


@dataclass(frozen=True)
class Located:
    """A probe set's tetrahedralisation and what it gives at some points."""

    points: np.ndarray  # (M,) ascending
    errors: np.ndarray  # (N,), 0 but at `points`
    owners: np.ndarray  # (M, 4)
    touched: np.ndarray  # (M, 4)
    probes: np.ndarray  # sorted
    mesh: Tetrahedralization


def evaluated_at(field: ReferenceField, probes: np.ndarray, points: np.ndarray | None,
                 tets: np.ndarray | None = None, weighting: LeakWeighting | None = None,
                 mesh: Tetrahedralization | None = None, start: np.ndarray | None = None) -> Located:
    """The sorted probes' tetrahedralisation (given by `tets`, global ids, or assembled as `mesh`, when known) and, at
    `points` (every other point when None), their errors (weighted by leaks with a `weighting`), owners and touched
    ids. `start`: a tetrahedron of `mesh` near each of `points` (refill_starts), where its location's walk starts."""
    ordered = np.sort(probes)
    local_tets = None if tets is None else np.searchsorted(ordered, tets)
    indices, others, tri, stencil = probe_mesh(field, ordered, coherent=True, points=points, tets=local_tets, mesh=mesh,
                                               start=start)
    errors = stencil_point_errors(field, indices, others, stencil)
    if weighting is not None:
        errors = weighting.weighted(field, indices, others, stencil, errors)
    touched = np.empty(stencil.vertices.shape, dtype=np.int64)
    owners = np.empty(stencil.vertices.shape, dtype=np.int64)
    run_rows(stencil_ids, others.shape[0], indices, stencil.vertices, stencil.weights, touched, owners)
    return Located(points=others, errors=errors, owners=owners, touched=touched, probes=indices, mesh=tri)


def evaluate(field: ReferenceField, probes: np.ndarray, weighting: LeakWeighting | None = None,
             mesh: Tetrahedralization | None = None) -> MeshState:
    """Every point evaluated (the seed); with a `weighting`, leaking points' errors weighted from now on. `mesh`: the
    sorted probes' tetrahedralisation when it is known (insertion_tetrahedra.InsertionTetrahedra.of_superset)."""
    n = field.point_count
    located = evaluated_at(field, probes, None, weighting=weighting, mesh=mesh)
    owners = np.full((n, 4), -1, dtype=np.int64)
    touched = np.full((n, 4), -1, dtype=np.int64)
    owners[located.points], touched[located.points] = located.owners, located.touched
    return MeshState(probes=located.probes, owners=owners, touched=touched, errors=located.errors,
                     error_sum=float(located.errors.sum()), edges=graph_edges(located.probes, located.mesh.tets),
                     mesh=located.mesh, weighting=weighting)


def refill_starts(mesh: Tetrahedralization, refill_owner: np.ndarray, star: np.ndarray, probes: np.ndarray
                  ) -> np.ndarray:
    """Where to start locating points in `mesh`, whose last len(refill_owner) tetrahedra refill removed probes' stars
    (refill_owner: each one's removed probe, as derived_mesh assembles them), given the removed probe whose star each
    point was in (`star`, stencils_with_stars; removed probes of the sorted `probes`, state.probes): the first
    tetrahedron of that star's refill, near the one that holds the point, where the previous point's walk ended in
    another star (location.locate_local's `start`: a run of points of one star continues from the previous point's
    tetrahedron). A coherent walk crossed the stars between such runs (ctf_compromise's refinement, leak-aware: its 158
    locations took 0.26 s instead of 0.80 s). A point whose removed probe left no refill (a hull vertex whose star the
    hull lost) starts at the first refill tetrahedron, or at the last tetrahedron when there is none. The start changes
    no cell but where location.locate_local says a walk's start can."""
    start = np.empty(star.shape[0], dtype=np.int64)
    base = min(mesh.tets.shape[0] - refill_owner.shape[0], mesh.tets.shape[0] - 1)  # no refill at all: the last one
    refill_start_rows(np.ascontiguousarray(star, dtype=np.int64), np.ascontiguousarray(probes, dtype=np.int64),
                      np.ascontiguousarray(refill_owner, dtype=np.int64), base, start)
    return start


def stencils_with_stars(state: MeshState, removed: np.ndarray, ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The points (ascending) whose `ids` rows (state.owners or state.touched) hold a removed probe, and the removed;
    for each, the removed probe whose star it was in: itself when removed, else the first removed probe its row holds
    (an independent set: a stencil's weighing probes hold at most one of them)."""
    gone = np.zeros(state.errors.shape[0], dtype=bool)
    gone[removed] = True
    return rows_holding_which(ids, gone)


@dataclass(frozen=True)
class Trial:
    """The state's probes without an independent set of candidates: each candidate's removal cost, and the trial's
    tetrahedra (global ids), from which the tetrahedralisation without any subset of the candidates follows."""

    candidates: np.ndarray
    costs: np.ndarray
    tets: np.ndarray  # (T, 4)
    fills: Fills | None = None  # each candidate's refill (trial_fills.py); None when Qhull tetrahedralised the trial


def trial_of(field: ReferenceField, state: MeshState, candidates: np.ndarray) -> Trial:
    """batched_refinement.py's step 2: each candidate's exact removal cost, the summed error change at the points its stencil
    weight reached plus its own new error; the trial is evaluated at those points only (no other point enters a
    cost). `candidates` must be independent in the state's Delaunay graph."""
    n = state.errors.shape[0]
    attributed, star = stencils_with_stars(state, candidates, state.owners)
    is_candidate = np.zeros(n, dtype=bool)
    is_candidate[candidates] = True
    remaining = np.setdiff1d(state.probes, candidates, assume_unique=True)  # both sorted, distinct
    fills = star_fills(field, state, candidates)
    trial = None
    if fills is not None:  # the state's tetrahedra outside the stars and the stars' refills: no Qhull (trial_fills.py)
        mesh = derived_mesh(field, state, is_candidate, fills.positions)
        if mesh is not None:
            trial = evaluated_at(field, remaining, attributed, weighting=state.weighting, mesh=mesh,
                                 start=refill_starts(mesh, fills.owner, star, state.probes))
        else:
            fills = None
    if trial is None:
        trial = evaluated_at(field, remaining, attributed, weighting=state.weighting)
    total = np.zeros(n)  # one candidate per stencil: a candidate point itself, else the candidate its stencil weighs
    attributed_costs(state.owners, attributed, is_candidate, trial.errors, state.errors, total)
    return Trial(candidates=candidates, costs=total[candidates], tets=trial.probes[trial.mesh.tets], fills=fills)


def derived_mesh(field: ReferenceField, state: MeshState, removed: np.ndarray, added: np.ndarray
                 ) -> Tetrahedralization | None:
    """The tetrahedralisation of state.probes without the `removed` ((N,) bool) probes: the state's tetrahedra without a
    removed vertex, then `added` (positions in state.probes, positively oriented: the removed probes' refills,
    Fills.positions — no search of each vertex among the remaining probes), assembled from the state's mesh (triangulation.assembled_after_removal: the same arrays as assembling them afresh).
    None when they are not a tetrahedralisation of the remaining probes: a probe unused, not a manifold, or a new crack
    (a face without a tetrahedron across inside the hull: a refill that left part of a star empty; the state's cracks
    are kept)."""
    gone_probe = removed[state.probes]
    remaining = state.probes[~gone_probe]
    vertex_map = np.full(state.probes.shape[0], -1, dtype=np.int64)
    vertex_map[~gone_probe] = np.arange(remaining.shape[0])
    keep = np.empty(state.mesh.tets.shape[0], dtype=bool)
    kept_tetrahedra(state.mesh.tets, gone_probe, keep)
    try:  # a removed probe's position maps to -1, which assembled_after_removal refuses
        mesh = assembled_after_removal(state.mesh, keep, vertex_map, field.world[remaining], vertex_map[added])
    except GeometryError:
        return None
    cracks_before = count_marker(state.mesh.neighbours, INNER_BOUNDARY)
    return (mesh if uses_every_vertex(mesh.tets, remaining.shape[0])
            and count_marker(mesh.neighbours, INNER_BOUNDARY) <= cracks_before else None)


def tet_keys(tets: np.ndarray, probes: np.ndarray) -> np.ndarray:
    """One exact int64 key per tetrahedron (global ids, all in the sorted `probes`): its sorted positions in `probes`,
    packed 4 x 15 bits when there are fewer than 2^15 probes, else a 4-field record (slower to compare)."""
    local = np.sort(np.searchsorted(probes, tets), axis=1)
    if probes.shape[0] < 1 << 15:
        return ((local[:, 0] << 45) | (local[:, 1] << 30) | (local[:, 2] << 15) | local[:, 3]).astype(np.int64)
    record = np.dtype([("a", np.int64), ("b", np.int64), ("c", np.int64), ("d", np.int64)])
    return np.ascontiguousarray(local, dtype=np.int64).view(record).reshape(-1)


def stars(field: ReferenceField, state: MeshState, trial: Trial, fills: np.ndarray) -> np.ndarray:
    """The candidate in whose star each new tetrahedron of the trial lies. Its 4 vertices are all Delaunay neighbours
    of that candidate; where they are neighbours of none or of several, the candidate of the state's tetrahedron that
    holds its centroid decides."""
    n = field.point_count
    is_candidate = np.zeros(n, dtype=bool)
    is_candidate[trial.candidates] = True
    links = state.edges[is_candidate[state.edges[:, 1]]]  # (vertex, candidate) pairs
    links = links[np.argsort(links[:, 0], kind="stable")]
    known = np.sort(links[:, 0] * n + links[:, 1])
    first = fills[:, 0]
    start, stop = np.searchsorted(links[:, 0], first), np.searchsorted(links[:, 0], first, side="right")
    rows = np.repeat(np.arange(fills.shape[0]), stop - start)
    guess = links[concatenated_ranges(start, stop - start), 1]  # each candidate next to the first vertex
    fits = np.ones(rows.shape[0], dtype=bool)
    for k in range(1, 4):
        key = fills[rows, k] * n + guess
        fits &= sorted_contains(key, known)
    matches = np.bincount(rows[fits], minlength=fills.shape[0])
    star = np.full(fills.shape[0], -1, dtype=np.int64)
    star[rows[fits]] = guess[fits]
    unsure = np.flatnonzero(matches != 1)
    if unsure.shape[0]:
        host = state.tets[locate_local(state.mesh, field.local[fills[unsure]].mean(axis=1)).cell]
        star[unsure] = host[np.arange(unsure.shape[0]), np.argmax(is_candidate[host], axis=1)]
    return star


def refilled(field: ReferenceField, state: MeshState, trial: Trial, removed: np.ndarray) -> np.ndarray:
    """The tetrahedra (global ids) of state.probes without `removed` (a subset of the trial's candidates), without
    tetrahedralising: the state's tetrahedra outside the removed probes' stars, and the trial's tetrahedra that fill
    those stars. Removing a probe retriangulates its own star and nothing else (the tie-broken Delaunay is unique) and
    the candidates' stars are disjoint, so each new tetrahedron of the trial lies in exactly one candidate's star."""
    before = state.tets
    gone = np.zeros(field.point_count, dtype=bool)
    gone[removed] = True
    fills = trial.tets[~np.isin(tet_keys(trial.tets, state.probes), tet_keys(before, state.probes))]
    kept = before[~gone[before].any(axis=1)]
    return np.concatenate([kept, fills[gone[stars(field, state, trial, fills)]]])


def boundary_vertices(state: MeshState) -> np.ndarray:
    """(N,) bool: the probes on a face with no tetrahedron across — the hull's, or a crack's. A fresh cost of any other
    probe (measured, no Delaunay neighbour removed since) is the cost a new trial would measure, up to rounding: its
    star, the points inside it, their old errors and its refill (a function of its link) are unchanged, and removing
    other candidates leaves the hull it lies inside alone. A hull vertex's cost is not: its star's points that fall
    outside the shrunken hull project onto a hull other removals elsewhere may have changed, and a point outside the hull
    may have moved its nearest hull point onto its triangles (batched_refinement.py step 2)."""
    on = np.zeros(state.errors.shape[0], dtype=bool)
    on[corners_of_faces(state.tets, state.mesh.neighbours < 0)] = True  # HULL or INNER_BOUNDARY
    return on


def removal_fills(field: ReferenceField, state: MeshState, removed: np.ndarray, trial: Trial | None) -> Fills | None:
    """The `removed` probes' star refills: the round's trial's where it made them, the rest made now (a committed
    candidate whose fresh cost was reused was not in the trial: batched_refinement.py step 2); None when the trial was
    tetrahedralised by Qhull or a refill fails its checks (trial_fills.py)."""
    if trial is not None and trial.fills is None:
        return None
    known = np.zeros(0, dtype=np.int64) if trial is None else trial.candidates
    lacking = removed[~sorted_contains(removed, np.sort(known))]
    if lacking.shape[0] == 0:
        return trial.fills
    made = star_fills(field, state, lacking)
    if made is None or trial is None:
        return made
    return Fills(tets=np.concatenate([trial.fills.tets, made.tets]), owner=np.concatenate([trial.fills.owner, made.owner]),
                 positions=np.concatenate([trial.fills.positions, made.positions]))


def without(field: ReferenceField, state: MeshState, removed: np.ndarray, trial: Trial | None = None,
            reuse: bool = False) -> MeshState:
    """The state of state.probes minus `removed`, re-evaluating only the points whose stencil touched a removed probe
    (and the removed themselves). `reuse`: update the state's per-point arrays in place instead of copying them (~70 MB
    a round at 10^6 points); the old state is then only valid again after restore(new state). Exact: the tie-broken
    Delaunay is unique, so every tetrahedron outside the removed probes' stars survives, and a point outside the hull
    keeps its nearest hull point unless that point's triangle had a removed vertex (the new hull lies inside the old one
    and keeps every triangle without a removed vertex). The tetrahedralisation is derived from the state's mesh and the
    removed probes' refills (removal_fills: the round's `trial`'s, or made for the removed it lacks) when they pass
    derived_mesh's checks; else from the trial's Qhull tetrahedra when it has every removed probe (refilled); else Qhull."""
    affected, star = stencils_with_stars(state, removed, state.touched)
    probes = np.setdiff1d(state.probes, removed, assume_unique=True)
    fills = removal_fills(field, state, removed, trial)
    if fills is not None:  # the removed probes' refills are known: no new mesh to assemble
        gone = np.zeros(field.point_count, dtype=bool)
        gone[removed] = True
        refilling = gone[fills.owner]
        refills = fills.tets[refilling]
        mesh = derived_mesh(field, state, gone, fills.positions[refilling])
        if mesh is not None:
            edges = edges_after_removal(state.edges, state.tets, state.mesh.neighbours, gone, refills)
            start = refill_starts(mesh, fills.owner[refilling], star, state.probes)
            return _replaced(state, affected, evaluated_at(field, probes, affected, weighting=state.weighting,
                                                           mesh=mesh, start=start), reuse, edges)
    # Refills refused (assembled another way they would pass what derived_mesh refused) or failed: Qhull decides, unless
    # the trial was Qhull's itself and holds every removed probe (refilled).
    qhull_trial = (trial is not None and trial.fills is None
                   and bool(sorted_contains(removed, np.sort(trial.candidates)).all()))
    tets = refilled(field, state, trial, removed) if qhull_trial else None
    if tets is not None and sorted_unique(tets.reshape(-1)).shape[0] != probes.shape[0]:
        tets = None  # cannot happen with a unique triangulation; Qhull decides if it does
    try:
        located = evaluated_at(field, probes, affected, tets, state.weighting)
    except GeometryError:
        if tets is None:
            raise
        located = evaluated_at(field, probes, affected, weighting=state.weighting)  # not a manifold: Qhull decides
    return _replaced(state, affected, located, reuse)


def _replaced(state: MeshState, affected: np.ndarray, located: Located, reuse: bool,
              edges: np.ndarray | None = None) -> MeshState:
    """The new state: `state`'s per-point rows with the `affected` ones from `located` (in place with `reuse`);
    `edges`: its Delaunay graph when known (delaunay_graph.edges_after_removal), else made from located.mesh."""
    replaced = None
    if reuse:  # the state's (N, ...) arrays become the new state's; `replaced` can bring the old rows back
        errors, owners, touched = state.errors, state.owners, state.touched
        replaced = ReplacedRows(rows=affected, errors=errors[affected], owners=owners[affected],
                                touched=touched[affected])
    else:
        errors, owners, touched = state.errors.copy(), state.owners.copy(), state.touched.copy()
    errors[affected], owners[affected], touched[affected] = located.errors[affected], located.owners, located.touched
    return MeshState(probes=located.probes, owners=owners, touched=touched, errors=errors,
                     error_sum=float(errors.sum()),
                     edges=graph_edges(located.probes, located.mesh.tets) if edges is None else edges,
                     mesh=located.mesh,
                     weighting=state.weighting, replaced=replaced)


def restore(following: MeshState) -> None:
    """Undo a `without(..., reuse=True)`: the rows it replaced get their old values back, so the state it was made from
    (whose arrays it shares) is whole again and `following` must not be used any more."""
    old = following.replaced
    if old is None:
        raise ValueError("restore() needs a state made by without(..., reuse=True)")
    following.errors[old.rows], following.owners[old.rows], following.touched[old.rows] = (old.errors, old.owners,
                                                                                           old.touched)
