"""Batched refinement: greedy decimation of a seed set by whole independent sets of probes (quality.md §5.3).

    batched_refinement(field, seed, count=K)          # down to K probes
    batched_refinement(field, seed, tolerance=tau)    # the fewest probes it finds within tau

Why it exists. The exact refinement (reference_fast, seeded) is within 1.02-1.06x of the reference, but it needs
local Delaunay removal with hole filling and hull handling (~1,900 lines) and takes ~0.2 s per removal on a
137k-point level (636 s on ctf_compromise). This one needs only what every placement already has: a global
tetrahedralisation of a probe set, point location and the per-point error. That is what the C# core has
(Unity's Lightmapping.Tetrahedralize), so Unity volumes get a refinement too (BatchedRefinement.cs, the same rules).

Why it is nearly exact. Two probes that share no Delaunay edge share no tetrahedron, so their stars are disjoint,
and removing one changes only the tetrahedra of its own star (triangulation.py: the tie-broken triangulation is
unique). Removing a whole independent set I at once and tetrahedralising once therefore gives, for every v in I, its
exact removal cost: the sum of the error changes at the points whose stencil used v, plus v's own new error. Costs
are additive over I, so any subset of I can be committed with a known error. (Points whose stencil held a candidate only
with weight 0 — on the face or hull edge opposite it — are not attributed; the committed state re-evaluates them: step
4.)

A round, from the probe set P (its tetrahedralisation, stencils and errors e):
1. Candidates: the greedy independent set of P's Delaunay graph in order of each probe's measured cost, probes
   whose cost is not fresh (never measured, or a neighbour removed since) first, ties to the lower index, locked
   probes (`keep`, and those brought back in step 4) left out; at most |P| - 4 of them. If the rest is flat, only the
   first unlocked probe in that order whose removal alone leaves a solid set (those before it are locked: removing them
   flattens every later set too); if none does, stop. (Stale costs first, as the exact greedy recomputes them at once: on the
   validation crops 0.7 % fewer probes at tau, on oa_bases7 3 % and on ctf_compromise 8 %, for 1.5-1.8x the rounds.)
2. Trial: tetrahedralise P minus the candidates; each candidate's cost = sum of (new - old error) over the points
   whose stencil held it with a weight > 0, plus its own new error. These costs replace the candidates' old ones.
3. Commit: the candidates whose cost is at most the COMMIT_FRACTION quantile (the lower one, no interpolation) of
   all measured costs of P, cheapest first (ties: lower index) — or, when none is and every unlocked probe's cost is
   fresh, the cheapest candidate (then the cheapest removal there is); with a count, no more than |P| - K; with a
   tolerance, the longest prefix keeping sum(e) + its costs (summed in that order) <= tau x N. Nothing committed: with
   a tolerance and every cost fresh, stop; else go on (the stale costs are the next candidates). (Forcing the
   cheapest candidate of a round of stale costs instead took the validation crops from 1.00x to 1.08x the
   reference's error at 1 % and from 1.01x to 1.05x its probes at tau.)
4. Remove them; their Delaunay neighbours' costs become stale. The new set is evaluated at the points whose stencil
   touched a removed probe (any weight, zero included) and at the removed ones; every other point keeps its stencil
   and error (the tie-broken Delaunay is unique, so every tetrahedron outside the removed stars survives; a point
   outside the hull keeps its nearest hull point unless that point's triangle had a removed vertex, as the new hull lies
   inside the old one and keeps every other triangle). With a tolerance,
   if its error exceeds tau (the unattributed hull effect), the dearest removed probes come back one by one until it
   does not, and are locked.
Stops at K probes, at the tolerance, at 4 probes, or when the rest would lie in one plane.

COMMIT_FRACTION = 0.05 was chosen on the 10 validation crops and whole validation levels (none held out), seeded
with insertion's first 2 K0 points: at tau = 0.05 fractions 0.2/0.1/0.05 kept 1.10/1.08/1.05x the reference's
probes on the crops (geometric mean; exact refinement 1.005x, insertion 1.66x), and 1,745/-/1,697 on oa_bases7
(20,222 points; reference 1,605); on ctf_compromise (136,512 points; reference 652) 0.1/0.03 kept 802/788.
Each round costs one Qhull tetrahedralisation (the trial's), the trial's location of the points whose stencil weighs
a candidate (~40 % of them; no other point enters a cost) and the commit's of the points its removed probes touched (a
few %). The committed set's tetrahedra are not computed again: they are the state's outside the removed stars and the
trial's inside them (_refilled; the C# core, with Unity's native tetrahedraliser, calls it twice). Against two Qhull
calls and two locations of every point per round: 2.0-2.3x less CPU on whole validation levels (oa_bases7 53 -> 23 s,
ctf_compromise 52 -> 26 s; the same tau counts on the validation crops; benchmarks.md §11.2).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .decimation import MINIMUM_PROBES, initial_mask
from .location import locate_local
from .metric import MetricError, ReferenceField, probe_mesh, stencil_point_errors
from .policies import checked_tolerance
from .triangulation import GeometryError, Tetrahedralization, flatness

COMMIT_FRACTION = 0.05  # commit candidates within this quantile of the measured costs (module text)
UNMEASURED = -math.inf  # the cost of a probe never measured, and the key of any cost not fresh: candidates first


@dataclass(frozen=True)
class BatchedRefinement:
    indices: np.ndarray  # (K,) int64 point indices, sorted
    mean_error: float  # the irradiance mean error of `indices`
    rounds: int
    stop_reason: str  # "count", "tolerance", "minimum count", "the rest would lie in one plane" or
    # "the seed exceeds the tolerance" (then `indices` is the seed, unrefined)
    seconds: float


@dataclass(frozen=True)
class _MeshState:
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

    @property
    def tets(self) -> np.ndarray:
        """(T, 4) global ids."""
        return self.probes[self.mesh.tets]


@dataclass(frozen=True)
class _Located:
    """A probe set's tetrahedralisation and what it gives at some points."""

    points: np.ndarray  # (M,) ascending
    errors: np.ndarray  # (N,), 0 but at `points`
    owners: np.ndarray  # (M, 4)
    touched: np.ndarray  # (M, 4)
    probes: np.ndarray  # sorted
    mesh: Tetrahedralization


def _located(field: ReferenceField, probes: np.ndarray, points: np.ndarray | None,
             tets: np.ndarray | None = None) -> _Located:
    """The sorted probes' tetrahedralisation (given by `tets`, global ids, when known) and, at `points` (every other
    point when None), their errors, owners and touched ids."""
    ordered = np.sort(probes)
    local_tets = None if tets is None else np.searchsorted(ordered, tets)
    indices, others, tri, stencil = probe_mesh(field, ordered, coherent=True, points=points, tets=local_tets)
    errors = stencil_point_errors(field, indices, others, stencil)
    touched = indices[stencil.vertices]
    owners = np.where(stencil.weights > 0.0, touched, -1)
    return _Located(points=others, errors=errors, owners=owners, touched=touched, probes=indices, mesh=tri)


def _edges(located: _Located) -> np.ndarray:
    count = located.probes.shape[0]
    tets = located.mesh.tets
    pairs = np.sort(np.concatenate([tets[:, [a, b]] for a in range(4) for b in range(a + 1, 4)]), axis=1)
    keys = np.unique(pairs[:, 0] * count + pairs[:, 1])  # one key per edge (a row-wise unique is ~20x slower)
    pairs = np.stack([keys // count, keys % count], axis=1)
    return located.probes[np.concatenate([pairs, pairs[:, ::-1]])]


def _evaluate(field: ReferenceField, probes: np.ndarray) -> _MeshState:
    """Every point evaluated (the seed)."""
    n = field.point_count
    located = _located(field, probes, None)
    owners = np.full((n, 4), -1, dtype=np.int64)
    touched = np.full((n, 4), -1, dtype=np.int64)
    owners[located.points], touched[located.points] = located.owners, located.touched
    return _MeshState(probes=located.probes, owners=owners, touched=touched, errors=located.errors,
                      error_sum=float(located.errors.sum()), edges=_edges(located), mesh=located.mesh)


def _stencils_using(state: _MeshState, removed: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Points (ascending) whose `ids` rows (state.owners or state.touched) hold a removed probe, and the removed."""
    gone = np.zeros(state.errors.shape[0], dtype=bool)
    gone[removed] = True
    return np.flatnonzero(((ids >= 0) & gone[np.maximum(ids, 0)]).any(axis=1) | gone)


@dataclass(frozen=True)
class _Trial:
    """The state's probes without an independent set of candidates: each candidate's removal cost, and the trial's
    tetrahedra (global ids), from which the tetrahedralisation without any subset of the candidates follows."""

    candidates: np.ndarray
    costs: np.ndarray
    tets: np.ndarray  # (T, 4)


def _trial(field: ReferenceField, state: _MeshState, candidates: np.ndarray) -> _Trial:
    """Module text, step 2: each candidate's exact removal cost, the summed error change at the points its stencil
    weight reached plus its own new error; the trial is evaluated at those points only (no other point enters a
    cost). `candidates` must be independent in the state's Delaunay graph."""
    n = state.errors.shape[0]
    attributed = _stencils_using(state, candidates, state.owners)
    is_candidate = np.zeros(n, dtype=bool)
    is_candidate[candidates] = True
    rows = state.owners[attributed]
    hits = (rows >= 0) & is_candidate[np.maximum(rows, 0)]
    owner = np.where(is_candidate[attributed], attributed, rows[np.arange(attributed.shape[0]), np.argmax(hits, axis=1)])
    trial = _located(field, np.setdiff1d(state.probes, candidates), attributed)
    total = np.bincount(owner, trial.errors[attributed] - state.errors[attributed], minlength=n)  # one per stencil
    return _Trial(candidates=candidates, costs=total[candidates], tets=trial.probes[trial.mesh.tets])


def removal_costs(field: ReferenceField, state: _MeshState, candidates: np.ndarray) -> np.ndarray:
    """Each candidate's exact removal cost (module text, step 2)."""
    return _trial(field, state, candidates).costs


def _tet_keys(tets: np.ndarray, probes: np.ndarray) -> np.ndarray:
    """One exact int64 key per tetrahedron (global ids, all in the sorted `probes`): its sorted positions in `probes`,
    packed 4 x 15 bits when there are fewer than 2^15 probes, else a 4-field record (slower to compare)."""
    local = np.sort(np.searchsorted(probes, tets), axis=1)
    if probes.shape[0] < 1 << 15:
        return ((local[:, 0] << 45) | (local[:, 1] << 30) | (local[:, 2] << 15) | local[:, 3]).astype(np.int64)
    record = np.dtype([("a", np.int64), ("b", np.int64), ("c", np.int64), ("d", np.int64)])
    return np.ascontiguousarray(local, dtype=np.int64).view(record).reshape(-1)


def _stars(field: ReferenceField, state: _MeshState, trial: _Trial, fills: np.ndarray) -> np.ndarray:
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
    offsets = np.arange(rows.shape[0]) - np.repeat(np.cumsum(stop - start) - (stop - start), stop - start)
    guess = links[start[rows] + offsets, 1]  # each candidate next to the first vertex
    fits = np.ones(rows.shape[0], dtype=bool)
    for k in range(1, 4):
        key = fills[rows, k] * n + guess
        fits &= known[np.minimum(np.searchsorted(known, key), known.shape[0] - 1)] == key
    matches = np.bincount(rows[fits], minlength=fills.shape[0])
    star = np.full(fills.shape[0], -1, dtype=np.int64)
    star[rows[fits]] = guess[fits]
    unsure = np.flatnonzero(matches != 1)
    if unsure.shape[0]:
        host = state.tets[locate_local(state.mesh, field.local[fills[unsure]].mean(axis=1)).cell]
        star[unsure] = host[np.arange(unsure.shape[0]), np.argmax(is_candidate[host], axis=1)]
    return star


def _refilled(field: ReferenceField, state: _MeshState, trial: _Trial, removed: np.ndarray) -> np.ndarray:
    """The tetrahedra (global ids) of state.probes without `removed` (a subset of the trial's candidates), without
    tetrahedralising: the state's tetrahedra outside the removed probes' stars, and the trial's tetrahedra that fill
    those stars. Removing a probe retriangulates its own star and nothing else (the tie-broken Delaunay is unique) and
    the candidates' stars are disjoint, so each new tetrahedron of the trial lies in exactly one candidate's star."""
    fills = trial.tets[~np.isin(_tet_keys(trial.tets, state.probes), _tet_keys(state.tets, state.probes))]
    gone = np.zeros(field.point_count, dtype=bool)
    gone[removed] = True
    kept = state.tets[~gone[state.tets].any(axis=1)]
    return np.concatenate([kept, fills[gone[_stars(field, state, trial, fills)]]])


def _without(field: ReferenceField, state: _MeshState, removed: np.ndarray, trial: _Trial | None = None) -> _MeshState:
    """The state of state.probes minus `removed`, re-evaluating only the points whose stencil touched a removed probe
    (and the removed themselves). Exact: the tie-broken Delaunay is unique, so every tetrahedron outside the removed
    probes' stars survives, and a point outside the hull keeps its nearest hull point unless that point's triangle had
    a removed vertex (the new hull lies inside the old one and keeps every triangle without a removed vertex). With the
    round's `trial` (removed among its candidates), the tetrahedralisation comes from _refilled instead of Qhull."""
    affected = _stencils_using(state, removed, state.touched)
    probes = np.setdiff1d(state.probes, removed)
    tets = None if trial is None else _refilled(field, state, trial, removed)
    if tets is not None and np.unique(tets).shape[0] != probes.shape[0]:
        tets = None  # cannot happen with a unique triangulation; Qhull decides if it does
    try:
        located = _located(field, probes, affected, tets)
    except GeometryError:
        if tets is None:
            raise
        located = _located(field, probes, affected)  # a derived mesh that is not a manifold: Qhull decides

    errors, owners, touched = state.errors.copy(), state.owners.copy(), state.touched.copy()
    errors[affected], owners[affected], touched[affected] = located.errors[affected], located.owners, located.touched
    return _MeshState(probes=located.probes, owners=owners, touched=touched, errors=errors,
                      error_sum=float(errors.sum()), edges=_edges(located), mesh=located.mesh)


def greedy_independent_set(vertices: np.ndarray, edges: np.ndarray, rank: np.ndarray) -> np.ndarray:
    """The independent set the sequential greedy takes when it visits `vertices` by ascending `rank` (distinct,
    indexed by vertex id) and keeps every vertex none of whose neighbours it kept; returned in rank order.
    Vectorised: take every live vertex ranked below all its live neighbours, drop their neighbours, repeat (each pass
    takes what the sequential greedy takes, so the result is the same)."""
    size = rank.shape[0]
    live = np.zeros(size, dtype=bool)
    live[vertices] = True
    chosen = np.zeros(size, dtype=bool)
    unranked = np.iinfo(np.int64).max
    while live.any():
        alive = edges[live[edges[:, 0]] & live[edges[:, 1]]]
        lowest_neighbour = np.full(size, unranked, dtype=np.int64)
        np.minimum.at(lowest_neighbour, alive[:, 0], rank[alive[:, 1]])
        take = live & (rank < lowest_neighbour)
        chosen |= take
        live &= ~take
        live[alive[take[alive[:, 0]], 1]] = False
    picked = np.flatnonzero(chosen)
    return picked[np.argsort(rank[picked], kind="stable")]


def _ranks(probes: np.ndarray, cost: np.ndarray, size: int) -> np.ndarray:
    """Each probe's position in the order (cost, index); other ids rank last."""
    rank = np.full(size, np.iinfo(np.int64).max, dtype=np.int64)
    rank[probes[np.lexsort((probes, cost[probes]))]] = np.arange(probes.shape[0])
    return rank


def _commit_threshold(measured: np.ndarray, fraction: float) -> float:
    """The lower `fraction` quantile of the measured costs (the value at position floor(fraction x (m - 1)))."""
    ordered = np.sort(measured)
    return float(ordered[int(math.floor(fraction * (ordered.shape[0] - 1)))])


def _checked_fraction(fraction: float) -> float:
    value = float(fraction)
    if not (math.isfinite(value) and 0.0 <= value <= 1.0):
        raise MetricError(f"commit fraction {fraction!r} must be in [0, 1] (e.g. {COMMIT_FRACTION})")
    return value


def batched_refinement(field: ReferenceField, seed: np.ndarray, count: int | None = None,
                       tolerance: float | None = None, fraction: float = COMMIT_FRACTION,
                       keep: np.ndarray | None = None, progress: Callable[[int, int], None] | None = None,
                       trace: Callable[[dict[str, Any]], None] | None = None) -> BatchedRefinement:
    """Decimate `seed` (point indices or a mask, >= 4 points not in one plane) by the rounds of the module text: down
    to `count` probes, or (with `tolerance`) as far as the mean irradiance error stays <= tolerance; exactly one of
    the two. A seed whose error already exceeds the tolerance is returned as it is (stop_reason says so). `keep`:
    point indices never removed (e.g. the bounds corners a Unity volume keeps). `trace` gets every round's inputs and
    decisions (the golden file's generator certifies them: Tools~/golden/make_batched_refinement_golden.py). `progress` gets (probes removed, probes the seed has beyond the goal) after every round."""
    if (count is None) == (tolerance is None):
        raise MetricError("give exactly one of count (probes to keep) and tolerance (a mean error, e.g. 0.05)")
    tau = None if tolerance is None else checked_tolerance(tolerance)
    fraction = _checked_fraction(fraction)
    n = field.point_count
    mask = initial_mask(seed, n)
    assert mask is not None
    goal = max(MINIMUM_PROBES, int(count)) if count is not None else MINIMUM_PROBES
    limit = math.inf if tau is None else tau * n  # the error sum allowed
    start = time.perf_counter()
    state = _evaluate(field, np.flatnonzero(mask))
    if tau is not None and state.error_sum > limit:  # nothing within the tolerance to start from: the caller's answer
        return BatchedRefinement(indices=state.probes.copy(), mean_error=state.error_sum / n, rounds=0,
                                 stop_reason="the seed exceeds the tolerance", seconds=time.perf_counter() - start)
    cost = np.full(n, UNMEASURED)
    fresh = np.zeros(n, dtype=bool)
    locked = np.zeros(n, dtype=bool)  # never removed: `keep`, probes brought back after an overshoot, flattening ones
    if keep is not None:
        locked[np.asarray(keep, dtype=np.int64)] = True
    seeded = int(state.probes.shape[0])
    rounds, stop_reason = 0, "count"
    while True:
        probes = state.probes
        if probes.shape[0] <= goal:
            stop_reason = "count" if count is not None else "minimum count"
            break
        movable = probes[~locked[probes]]
        rank = _ranks(movable, np.where(fresh, cost, UNMEASURED), n)  # stale and unmeasured costs first
        candidates = greedy_independent_set(movable, state.edges, rank)[:probes.shape[0] - MINIMUM_PROBES]
        if candidates.shape[0] == 0:  # every probe left was brought back after an overshoot
            stop_reason = "tolerance"
            break
        remaining = np.setdiff1d(probes, candidates)
        if flatness(field.local[remaining]) is not None:
            # Near the end only: the first unlocked probe (in the candidates' order) whose removal alone leaves a solid
            # set. A probe whose removal flattens P flattens every subset of P too: it is locked for good.
            solid = []
            for c in movable[np.argsort(rank[movable], kind="stable")].tolist():
                if flatness(field.local[np.setdiff1d(probes, [c])]) is None:
                    solid = [c]
                    break
                locked[c] = True
            if not solid:
                stop_reason = "the rest would lie in one plane"
                break
            candidates = np.asarray(solid, dtype=np.int64)
            remaining = np.setdiff1d(probes, candidates)
        rounds += 1
        trial = _trial(field, state, candidates)
        cost[candidates] = trial.costs
        fresh[candidates] = True
        measured = cost[probes][np.isfinite(cost[probes])]
        threshold = _commit_threshold(measured, fraction)
        ordered = candidates[np.lexsort((candidates, cost[candidates]))]
        commit = ordered[cost[ordered] <= threshold]
        settled = bool(np.all(fresh[probes] | locked[probes]))
        if commit.shape[0] == 0 and settled:  # every cost is fresh: the cheapest candidate is the cheapest removal
            commit = ordered[:1]
        if count is not None:
            commit = commit[:probes.shape[0] - goal]
        eligible = commit
        if tau is not None:
            fits = state.error_sum + np.cumsum(cost[commit]) <= limit  # costs can be negative: the longest prefix
            commit = commit[:commit.shape[0] if fits.all() else int(np.argmin(fits))]
        if trace is not None:
            trace({"probes": probes, "remaining": remaining, "candidates": candidates, "costs": cost[candidates],
                   "measured": measured, "threshold": threshold, "error_sum": state.error_sum, "eligible": eligible,
                   "commit": commit})
        if commit.shape[0] == 0:
            if tau is not None and settled:
                stop_reason = "tolerance"
                break
            continue  # the stale costs are candidates first next round
        removed = np.zeros(n, dtype=bool)
        removed[commit] = True
        fresh[state.edges[removed[state.edges[:, 0]], 1]] = False
        following = _without(field, state, commit, trial)
        back = commit.shape[0]
        while tau is not None and following.error_sum > limit and back > 0:  # an unattributed hull effect
            back -= 1
            locked[commit[back]] = True
            following = _without(field, state, commit[:back], trial)
        if trace is not None:
            trace({"following": following.probes, "following_sum": following.error_sum})
        state = following
        if progress is not None:
            progress(seeded - int(state.probes.shape[0]), seeded - goal)
    return BatchedRefinement(indices=state.probes.copy(), mean_error=state.error_sum / n, rounds=rounds,
                             stop_reason=stop_reason, seconds=time.perf_counter() - start)
