"""Batched refinement: greedy decimation of a seed set by whole independent sets of probes (quality.md §5.3).

    batched_refinement(field, seed, count=K)          # down to K probes
    batched_refinement(field, seed, tolerance=tau)    # the fewest probes it finds within tau
    batched_refinement(field, seed, tolerance=tau, leaks=LeakWeighting(raycaster))   # leaking points weigh more

Why it exists. The exact refinement (reference_fast, seeded) is within 1.02-1.06x of the reference, but it needs
local Delaunay removal with hole filling and hull handling (~1,900 lines) and takes ~0.2 s per removal on a
137k-point level (636 s on ctf_compromise). This one needs only what every placement already has: a global
tetrahedralisation of a probe set, point location and the per-point error. That is what the C# core has
(Unity's Lightmapping.Tetrahedralize), so Unity volumes get a refinement too (BatchedRefinement.cs, the same rules).

Why it is nearly exact. Two probes that share no Delaunay edge share no tetrahedron, so their stars are disjoint,
and removing one changes only the tetrahedra of its own star (metric/triangulation.py: the tie-broken triangulation is
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
   A candidate whose cost is fresh and that lies on no face without a tetrahedron across (the hull's, a crack's) is
   left out of the trial and keeps its cost: its star, the points in it, their old errors and its refill are what they
   were when it was measured, so the trial would measure the same number up to rounding (batched_state.boundary_vertices).
   On ctf_compromise (leak-aware) that spares 15 % of the trials' points, most of them in the late rounds.
3. Commit: the candidates whose cost is at most the COUNT_COMMIT_FRACTION (down to a count) or
   TOLERANCE_COMMIT_FRACTION (within a tolerance) quantile (the lower one, no interpolation) of
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

The fractions were chosen on the 10 validation crops and 5 whole validation levels (none held out), seeded with
insertion's first 2 K0 points (2026-11-27, today's rules). Within tau, 0.05 and 0.1 keep the same 1.03x the
reference's probes on the crops (0.2: 1.06x), and on the whole levels (q3dm6ish, fan, oa_bases7, oa_koth1,
ctf_compromise) 0.1 keeps 305/968/1,670/183/753 probes against 0.05's 305/968/1,665/176/704 (+1.6 % in all) in 24-41 %
fewer rounds; at 1,151,667 points (ctf_compromise at 0.81 m) 932 against 906, 61 s against 75 s in all. Down to a
count, 0.1 raised the crops' error over the reference's at 1/5/10/20/30 % from 1.010/1.082/1.050/1.048/1.044x to
1.007/1.108/1.070/1.064/1.080x, so budgets keep 0.05 (benchmarks.md "The speed/accuracy trade, every method").
Each round costs the trial's tetrahedra, refilled star by star rather than tetrahedralised (trial_fills.py; Qhull only
where a refill fails its checks), the trial's location of the points whose stencil weighs a candidate (~40 % of them;
no other point enters a cost) and the commit's of the points its removed probes touched (a few %); the committed set's
tetrahedra are derived, not recomputed (batched_state.py; the C# core, with Unity's native tetrahedraliser, calls it
twice). Against two Qhull calls and two locations of every point per round: 2.0-3.8x less
CPU on whole levels (oa_bases7 53 -> 23 s, ctf_compromise 52 -> 26 s; the same tau counts on the validation crops;
measured 2026-11-26; today's times: benchmarks.md "Scale: whole levels").
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .batched_state import boundary_vertices, evaluate, restore, trial_of, without
from .decimation.decimation import MINIMUM_PROBES, initial_mask
from .insertion import TIE, largest_first
from .leak_aware import LeakWeighting
from ..metric.metric import MetricError, ReferenceField
from .policies import checked_tolerance
from .refinement_kernel import sequential_greedy
from ..metric.triangulation import Tetrahedralization, flatness

COUNT_COMMIT_FRACTION = 0.05  # down to a count: commit candidates within this quantile of the measured costs
TOLERANCE_COMMIT_FRACTION = 0.1  # within a tolerance: the same, a larger quantile (module text)
UNMEASURED = -math.inf  # the cost of a probe never measured, and the key of any cost not fresh: candidates first
REMEASURE_FRESH_COSTS = False  # tests only: True re-measures every candidate's cost in every trial, as before 2026-11-28


@dataclass(frozen=True)
class BatchedRefinement:
    indices: np.ndarray  # (K,) int64 point indices, sorted
    mean_error: float  # the irradiance mean error of `indices` (with `leaks`: leaking points' errors weighted)
    rounds: int
    stop_reason: str  # "count", "tolerance", "minimum count", "the rest would lie in one plane" or
    # "the seed exceeds the tolerance" (then `indices` is the seed, unrefined)
    seconds: float


def greedy_independent_set(vertices: np.ndarray, edges: np.ndarray, rank: np.ndarray) -> np.ndarray:
    """The independent set the sequential greedy takes when it visits `vertices` by ascending `rank` (distinct,
    indexed by vertex id) and keeps every vertex none of whose neighbours it kept; returned in rank order
    (refinement_kernel.sequential_greedy, over the edges sorted by their first vertex)."""
    ordered = np.asarray(vertices, dtype=np.int64)
    ordered = ordered[np.argsort(rank[ordered], kind="stable")]
    if edges.shape[0] > 1 and np.any(edges[1:, 0] < edges[:-1, 0]):  # a state's edges come sorted (graph_edges)
        edges = edges[np.argsort(edges[:, 0], kind="stable")]
    return sequential_greedy(ordered, np.ascontiguousarray(edges[:, 0]), np.ascontiguousarray(edges[:, 1]),
                             rank.shape[0])


def cheapest_first(ids: np.ndarray, cost: np.ndarray) -> np.ndarray:
    """`ids` by ascending cost, where a cost within TIE of the next smaller one counts as equal to it: each run of such
    costs goes by id, lowest first. Costs the same removal gets from the same tetrahedra listed in another vertex order
    differ in the last bits, and many are exactly 0 where the light is even: compared exactly, such ties would commit
    by rounding (quality.md §5.3 "Ties"; the C# core's BatchedRefinement.CheapestFirst)."""
    return ids[largest_first(-cost[ids], ids)]


def _ranks(probes: np.ndarray, cost: np.ndarray, size: int) -> np.ndarray:
    """Each probe's position in cheapest_first's order; other ids rank last."""
    rank = np.full(size, np.iinfo(np.int64).max, dtype=np.int64)
    rank[cheapest_first(probes, cost)] = np.arange(probes.shape[0])
    return rank


def _commit_threshold(measured: np.ndarray, fraction: float) -> float:
    """The lower `fraction` quantile of the measured costs (the value at position floor(fraction x (m - 1)))."""
    ordered = np.sort(measured)
    return float(ordered[int(math.floor(fraction * (ordered.shape[0] - 1)))])


def _checked_fraction(fraction: float) -> float:
    value = float(fraction)
    if not (math.isfinite(value) and 0.0 <= value <= 1.0):
        raise MetricError(f"commit fraction {fraction!r} must be in [0, 1] (e.g. {TOLERANCE_COMMIT_FRACTION})")
    return value


def batched_refinement(field: ReferenceField, seed: np.ndarray, count: int | None = None,
                       tolerance: float | None = None, fraction: float | None = None,
                       keep: np.ndarray | None = None, progress: Callable[[int, int], None] | None = None,
                       trace: Callable[[dict[str, Any]], None] | None = None,
                       leaks: LeakWeighting | None = None,
                       seed_mesh: Tetrahedralization | None = None,
                       settled_commits: bool = False) -> BatchedRefinement:
    """Decimate `seed` (point indices or a mask, >= 4 points not in one plane) by the rounds of the module text: down
    to `count` probes, or (with `tolerance`) as far as the mean irradiance error stays <= tolerance; exactly one of
    the two. A seed whose error already exceeds the tolerance is returned as it is (stop_reason says so). `keep`:
    point indices never removed (e.g. the bounds corners a Unity volume keeps). `trace` gets every round's inputs and
    decisions (the golden file's generator certifies them: Tools~/golden/make_batched_refinement_golden.py). `progress` gets (probes removed, probes the seed has beyond the goal) after every round.
    `leaks` (leak_aware.py): every error summed — costs, tolerance, mean_error — is the leak-weighted one; its segments
    are remembered for the whole call (a fresh memo unless `leaks` brings one: LeakWeighting.remembering). `seed_mesh`:
    the seed's tetrahedralisation (vertex i its i-th smallest point) when the caller derived it (refined_insertion).
    `settled_commits` (experiments; the default and the C# core never set it): commit only in a round that starts with
    every unlocked probe's cost fresh, measuring the stale ones in the rounds between. Then the candidates are ranked by
    their costs, so the first is the cheapest removal there is, and with `fraction` 0 the rounds follow the exact greedy
    from the same seed (fast_decimation(initial=seed)) wherever the trial costs are its exact removal costs (not where
    a point weighs a candidate only with weight 0, module text), up to tied costs (which commit together here), until
    an overshoot brings a probe back; and they stop at the greedy's first crossing of the tolerance, where its curve
    may dip below it again later: benchmarks.md "where the whole-level gap to the exact greedy comes from"
    (Tools~/experiments/greedy-gap.py)."""
    if (count is None) == (tolerance is None):
        raise MetricError("give exactly one of count (probes to keep) and tolerance (a mean error, e.g. 0.05)")
    tau = None if tolerance is None else checked_tolerance(tolerance)
    fraction = _checked_fraction((COUNT_COMMIT_FRACTION if tolerance is None else TOLERANCE_COMMIT_FRACTION)
                                 if fraction is None else fraction)
    n = field.point_count
    mask = initial_mask(seed, n)
    assert mask is not None
    goal = max(MINIMUM_PROBES, int(count)) if count is not None else MINIMUM_PROBES
    limit = math.inf if tau is None else tau * n  # the error sum allowed
    start = time.perf_counter()
    if leaks is not None and leaks.visibility is None:
        leaks = leaks.remembering(field)
    state = evaluate(field, np.flatnonzero(mask), leaks, seed_mesh)
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
        remaining = np.setdiff1d(probes, candidates, assume_unique=True)
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
            remaining = np.setdiff1d(probes, candidates, assume_unique=True)
        rounds += 1
        # Every cost fresh before the trial: the candidates are ranked by cost, the first the cheapest removal there is.
        settled_at_start = settled_commits and bool(np.all(fresh[probes] | locked[probes]))
        # Step 2 for the candidates whose cost can have changed; a fresh cost off the boundary is what the trial would
        # measure (batched_state.boundary_vertices), so it is kept and the trial spared its points.
        again = candidates if REMEASURE_FRESH_COSTS else candidates[~(fresh[candidates] & ~boundary_vertices(state)[candidates])]
        trial = trial_of(field, state, again) if again.shape[0] else None
        if trial is not None:
            cost[again] = trial.costs
        fresh[candidates] = True
        measured = cost[probes][np.isfinite(cost[probes])]
        threshold = _commit_threshold(measured, fraction)
        ordered = cheapest_first(candidates, cost)
        commit = ordered[cost[ordered] <= threshold + TIE]  # a cost tied with the threshold is within it
        # With settled_commits only a round that started with every cost fresh commits (or stops).
        settled = settled_at_start if settled_commits else bool(np.all(fresh[probes] | locked[probes]))
        if settled_commits and not settled:
            commit = commit[:0]
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
        following = without(field, state, commit, trial, reuse=True)
        back = commit.shape[0]
        while tau is not None and following.error_sum > limit and back > 0:  # an unattributed hull effect
            back -= 1
            locked[commit[back]] = True
            restore(following)
            following = without(field, state, commit[:back], trial, reuse=True)
        if trace is not None:
            trace({"following": following.probes, "following_sum": following.error_sum})
        state = following
        if progress is not None:
            progress(seeded - int(state.probes.shape[0]), seeded - goal)
    return BatchedRefinement(indices=state.probes.copy(), mean_error=state.error_sum / n, rounds=rounds,
                             stop_reason=stop_reason, seconds=time.perf_counter() - start)
