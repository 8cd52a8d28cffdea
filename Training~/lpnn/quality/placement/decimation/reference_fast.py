"""The fast error-driven reference: exact greedy decimation with local updates (quality.md §3.2).

It removes probes in exactly the order of the faithful decimation (reference_faithful.py: the
probe whose removal gives the smallest error against the dense reference; ties to the lowest
index), but never recomputes anything globally:

1. **Locality.** The tetrahedralisation is a regular triangulation with fixed per-point tie-break
   heights (metric/triangulation.py), hence unique, and removing probe v changes only star(v), the
   tetrahedra around v. The tetrahedra that fill the hole are those of the triangulation of
   link(v) (v's neighbours, ~12-20 points) that conflict with v (v lies in their circumsphere):
   gift-wrapped from the hole's boundary for probes inside the hull (hole_wrap.py), else one small
   Qhull call; near-degenerate links are settled by which centroids lie in star(v).
2. **Additivity.** The error is a sum over evaluation points and only the points located in
   star(v) (and v itself) change their stencil, so the removal cost
   delta(v) = sum(new errors) - sum(old errors) over those few points is exact.
3. **Exact priority queue.** After removing v only the costs of link(v) change (other stars are
   untouched); they are recomputed at once, in one vectorised batch, and pushed on a heap keyed by
   (rounded cost, index). Every popped entry is fresh, so the order is exactly greedy.

Hull probes. Removing a probe that is a vertex of the convex hull ("extreme") shrinks the hull:
points of its star that fall outside are projected onto the new hull surface, which is the old
surface minus star(v)'s triangles plus the hole's new boundary triangles. A point whose
tetrahedron or hull triangle survives keeps its stencil (the nearest point of a smaller hull that
still contains the old nearest point is unchanged), so the update stays local. Every local result
is checked (the hole's volume equals the star's; every affected point is located) and falls back to
re-tetrahedralising the whole set when a check fails, so correctness never depends on the fast path.

Cost: one tetrahedralisation of the N candidates, then per removal ~|link| hole fillings and
O(|link| x affected points) vectorised work: O(N log N + N d (d log d + a)) in total, with d the
vertex degree (~15) and a the points per star. Memory O(N + T). With `workers=2` two identical
replicas share the cost evaluations (removal_costs.py); the result is the same.

Leaks. With a leak weighting (`leaks=LeakWeighting(raycaster)`, placement/leak_aware.py) every error the greedy sums is
the leak-weighted one of the leak-aware default (Documentation~/leaks.md "A leak-aware default"): a point whose stencil
reaches through a wall counts its error `weight` times, in each removal's delta, in the state's sum, in the error
curve and so at the stop and at tau. A point's weighted error still depends on its stencil only, so locality,
additivity and the exact queue hold as above: it is the exact greedy decimation of the weighted error, the yardstick of
the leak-aware default (quality.md §3.2). One segment memo (leak_rule.SegmentVisibility) serves the whole decimation.

Modules: decimation_mesh.py (the mesh, stencils and applying a removal), decimation_state.py (exact
local removal costs), hole_wrap.py (refilling holes), removal_costs.py (one or two processes), this file
(the greedy loop).
"""

from __future__ import annotations

import heapq
import time
from typing import Callable

import numpy as np

from .decimation import MINIMUM_PROBES, Decimation, error_curve_from, initial_mask, tie_key
from ...metric.metric import PRIMARY_METRIC, ReferenceField, checked_metric, probe_stencil, stencil_point_errors
from .removal_costs import CostEntry, ParallelCosts, SerialCosts
from ...metric.triangulation import flatness
from .weighing import Weighing


def fast_decimation(field: ReferenceField, metric: str = PRIMARY_METRIC, min_count: int = MINIMUM_PROBES,
                    workers: int | None = None, progress: Callable[[int, int], None] | None = None,
                    initial: np.ndarray | None = None, stop_above: float | None = None,
                    leaks: Weighing | None = None) -> Decimation:
    """Greedy decimation down to `min_count` (>= 4) probes; its ordering ranks every candidate.

    initial: the starting probe set, a boolean mask (N,) or point indices (>= 4 points, not all in one
    plane); None = every point (the reference placement). Seeded with a good superset of the wanted
    count (e.g. the spread ranking's first 2K points), the greedy refines it down to K in a fraction of
    the full run (quality.md §4). Points outside the initial set are never probes but are always
    evaluated. workers: 1 (this process, the default) or 2 (plus one identical replica process, which
    helps only when the second core is idle). The result does not depend on it.
    stop_above: stop once the mean error exceeds this (None: down to `min_count`). A tolerance answer needs the
    curve only until it leaves the tolerance for good, and the last removals, with few probes and large holes,
    are the dearest (35-40 % of the time on two validation crops at tau = 0.05); the ordering then ranks only
    the candidates removed before the stop (the survivors follow by index, as below `min_count`).
    leaks: a leak weighting (module text): every error summed, the curve and so the stop and a tolerance answer are
    leak-weighted (the Decimation's `leak_weight` says so), with one fresh segment memo for the call; None: leak-blind.
    """
    checked_metric(metric)
    n = field.point_count
    floor = max(int(min_count), MINIMUM_PROBES)
    count = 1 if workers is None else int(workers)
    if count not in (1, 2):
        raise ValueError(f"workers must be 1 or 2, got {workers!r}")
    start = time.perf_counter()
    mask = initial_mask(initial, n)
    start_count = n if mask is None else int(np.count_nonzero(mask))
    weighting = None if leaks is None else leaks.remembering(field)
    leak_weight = None if weighting is None else weighting.weight
    if start_count <= floor:
        start_error = 0.0 if mask is None else _mean_error(field, np.flatnonzero(mask), metric, weighting)
        return Decimation(method="fast-greedy", metric=metric, removed=np.zeros(0, dtype=np.int64),
                          error_curve=error_curve_from([], n, start_count, start_error), stop_reason="minimum count",
                          seconds=time.perf_counter() - start, initial=mask, leak_weight=leak_weight)
    with (ParallelCosts(field, metric, mask, weighting) if count == 2
          else SerialCosts(field, metric, mask, weighting)) as costs:
        start_error = float(costs.state.errors.sum()) / n
        removed, errors, stop_reason = _greedy(costs, floor, progress, stop_above)
    removed, errors, stop_reason = _without_flat_tail(field, mask, removed, errors, stop_reason)
    return Decimation(method="fast-greedy", metric=metric, removed=np.asarray(removed, dtype=np.int64),
                      error_curve=error_curve_from(errors, n, start_count, start_error), stop_reason=stop_reason,
                      seconds=time.perf_counter() - start, initial=mask, leak_weight=leak_weight)


def _mean_error(field: ReferenceField, probes: np.ndarray, metric: str, weighting: Weighing | None) -> float:
    """Mean error of the placement `probes`, leak-weighted when `weighting` is given (a seed the greedy leaves as
    it is)."""
    indices, others, stencil = probe_stencil(field, probes, coherent=True)
    errors = stencil_point_errors(field, indices, others, stencil, metric)
    if weighting is not None:
        errors = weighting.weighted(field, indices, others, stencil, errors)
    return float(errors.mean())


def _without_flat_tail(field: ReferenceField, mask: np.ndarray | None, removed: list[int], errors: list[float],
                       stop_reason: str) -> tuple[list[int], list[float], str]:
    """Undo the last removals while the probes left lie in one plane (or on one line).

    A local removal can miss that it flattens the set: float32 noise gives three collinear lattice
    points a tetrahedron of 6 x volume ~1e-9 (not flat for tet_geometry.FLAT_VOLUME), so removing
    the last probe off their plane keeps a "tetrahedron" and a finite cost. Every subset of a flat
    set is flat, so flat states form the tail of the removal order: checking from the end and
    stopping at the first solid set costs a few SVDs of the survivors.
    """
    kept = np.ones(field.point_count, dtype=bool) if mask is None else mask.copy()
    kept[removed] = False
    cut = len(removed)
    while cut and flatness(field.local[kept]) is not None:
        cut -= 1
        kept[removed[cut]] = True
    if cut == len(removed):
        return removed, errors, stop_reason
    return removed[:cut], errors[:cut], "the rest would lie in one plane"


def _greedy(costs: SerialCosts, floor: int, progress: Callable[[int, int], None] | None,
            stop_above: float | None = None) -> tuple[list[int], list[float], str]:
    """Exact greedy from the alive set: pop the cheapest fresh removal, apply it, recompute every cost it changed;
    until `floor` probes are left or the mean error exceeds `stop_above`."""
    state = costs.state
    n = state.field.point_count
    alive = np.flatnonzero(state.alive)
    start_count = int(alive.shape[0])
    version = np.zeros(n, dtype=np.int64)
    heap: list[tuple[float, int, int]] = []
    # A hull-shrinking cost depends on the hull triangles its points project onto: remember which
    # surviving tetrahedra own them, and which costs came from the global path (they depend on the
    # whole hull), so that exactly those are recomputed when the hull changes there.
    projecting_onto: dict[int, set[int]] = {}
    global_costs: set[int] = set()

    def push(entries: list[CostEntry]) -> None:
        for entry in entries:
            global_costs.discard(entry.vertex)
            if entry.is_global:
                global_costs.add(entry.vertex)
            for t in entry.projects_onto:
                projecting_onto.setdefault(t, set()).add(entry.vertex)
            heapq.heappush(heap, (tie_key(entry.delta), entry.vertex, int(version[entry.vertex])))

    push(costs.evaluate(alive.tolist()))
    removed: list[int] = []
    errors: list[float] = []
    while start_count - len(removed) > floor:
        if not heap:
            return removed, errors, "no removable probe"
        key, v, entry_version = heapq.heappop(heap)
        if not state.alive[v] or entry_version != version[v]:
            continue  # superseded by a fresher entry
        if not np.isfinite(key):
            return removed, errors, "no removable probe"
        changed, dead, hull_changed = costs.remove(v)
        stale = set(changed.tolist())
        for t in dead.tolist():
            stale.update(projecting_onto.pop(t, ()))
        if hull_changed:
            stale.update(global_costs)
        stale_list = sorted(u for u in stale if state.alive[u])
        removed.append(v)
        errors.append(float(state.errors.sum()) / n)  # summed afresh: no drift over thousands of removals
        if stop_above is not None and errors[-1] > stop_above:
            return removed, errors, "error above the stop"
        version[stale_list] += 1
        push(costs.evaluate(stale_list))
        if progress is not None:
            progress(len(removed), start_count - floor)
    return removed, errors, "minimum count"
