"""Refined insertion: the insertion order's answer, refined by batched_refinement (quality.md §5.3).

    refined_insertion(field, grid, budget=0.2)             # K = round(f N) probes
    refined_insertion(field, grid, tolerance=0.05)         # the fewest probes found within tau
    refined_insertion(field, grid, budget=0.2, guide=w)    # seeded by guided insertion (the LPNN tier)
    refined_insertion(field, grid, tolerance=0.05, leaks=raycaster)   # leak-aware (the callers' default: leaks.md)

- budget f: K = round(f N); seed = the insertion order's first
  min(N, max(round(F K), min(round(1.5 F K), round(0.5 N)), MINIMUM_SEED)) points (budget_seed_count: 3K for small
  budgets, at most 0.5 N, never fewer than 2K) (+ tetrahedron guarantee), decimated in batches down to K. The wider
  seed because 2K is too few points at small budgets (the validation crops: 1.08x the reference's error at 5 %, 1.04x
  with 3K), and the cap because from 25 % on 2K already holds 0.5 N and a wider seed there costs much time (3K:
  +51 % CPU at 30 %) for little (benchmarks.md "A wider seed for small budgets"; the cap 0.5 N since 2026-11-29, when the
  crops' time at 20 % had room for it: "The budget seed's cap re-chosen").
- tolerance tau: K0 = the tolerance search over the insertion order's prefixes (policies.place_tolerance); seed =
  its first round(F K0) points (at least MINIMUM_SEED), decimated in batches while the mean error stays <= tau; the
  answer is the refinement's set if it has fewer than K0 probes, else the search's (never worse than insertion).
- leaks (the scene's raycaster; leak_aware.py, benchmarks.md "Light leaks"): the seed gets leak repair rounds
  (leak_repaired) and the refinement weighs leaking points' errors LEAK_WEIGHT times in its costs and its tolerance;
  with tau the answer is the refinement's set whenever its weighted mean error is <= tau (it may hold more probes than
  K0: that is the price of fewer leaks), else the search's. `mean_error` is always the plain, unweighted error.
  Without `leaks` the placement is leak-blind; the callers that place by default (`lpnn place`, `lpnn bench`'s
  insertion-refined row, the demo) pass the capture's geometry when it is known (field.geometry), unless told to
  ignore leaks (`--leaks ignore`).
- pins (pins.py): insertion starts from them, the refinement never removes them (`keep`), a budget counts them; with
  `leaks` the repair adds no probe within their keep distance (a leaking point there is left to the pinned probe).
F = RECOMMENDED_REFINE (2), the refined methods' seed factor (methods.py). The C# core runs the same steps (BatchedRefinement.cs) with
Unity's tetrahedralisation: what an LPNN volume does by default. The C# core has the leak option too (LeakWeighting,
LeakRepair, RefinedSelection; Tests/Data/leak_aware_golden.json), which a Unity volume's Apply turns on by default
(LpnnVolume "Avoid light leaks").
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ...core.features import Raycaster
from ...core.grid import EvaluationGrid
from .batched_refinement import batched_refinement
from .insertion import InsertionOrder
from .methods import RECOMMENDED_REFINE  # re-exported: the refined tiers' seed factor
from .leak_aware import LEAK_WEIGHT, REPAIR_ROUNDS, LeakWeighting, leak_repaired_with_mesh
from ..metric.leak_rule import SegmentVisibility
from ..metric.metric import PRIMARY_METRIC, Evaluated, MetricError, ReferenceField, evaluated
from .pins import Pins, checked_pinned_count, pinned_smallest
from .policies import budget_count, place_tolerance

MINIMUM_SEED = 64  # a seed of 2K points cannot reach a sparse answer at tiny K (lpnn_placement.MINIMUM_SEED)
# The budget path's wider seed (module text): BUDGET_SEED_WIDENING x F x K points (3K), but no more than BUDGET_SEED_CAP x N
# unless F x K is more. Chosen on the 10 validation crops (benchmarks.md "A wider seed for small budgets", "The budget
# seed's cap re-chosen"). The C# core's RefinedSelection.BudgetSeedWidening and BudgetSeedCap.
BUDGET_SEED_WIDENING = 1.5
BUDGET_SEED_CAP = 0.5


@dataclass(frozen=True)
class RefinedPlacement:
    indices: np.ndarray  # (K,) int64 point indices, sorted
    requested: int  # the budget's count, or the count the tolerance answer kept
    seed: np.ndarray  # (S,) int64 point indices the refinement started from (after the leak repair)
    mean_error: float  # irradiance mean error of `indices`
    selection_seconds: float  # insertion rounds and the tolerance search
    refinement_seconds: float  # the seed's further rounds and the batched refinement
    rounds: int  # batched refinement rounds
    # `indices` located and evaluated afresh when the answer was checked so (the tolerance path's refined set), else
    # None; and the placement's remembered segments (leak-aware), None leak-blind: a report of this answer reuses both
    # (metric.evaluate_placement(field, indices, evaluation, segments)).
    evaluation: Evaluated | None = None
    segments: SegmentVisibility | None = None

    @property
    def seed_count(self) -> int:
        """Points the refinement started from."""
        return int(self.seed.shape[0])


def _rounded(value: float) -> int:
    """Halves up, as the C# core's (int)Math.Floor(x + 0.5)."""
    return int(math.floor(value + 0.5))


def seed_count(refine: float, count: int, point_count: int) -> int:
    """The tolerance path's seed, and guided-exact-refined's (lpnn_placement): min(N, max(round(F K), MINIMUM_SEED)), halves up."""
    return min(point_count, max(_rounded(refine * count), MINIMUM_SEED))


def budget_seed_count(refine: float, count: int, point_count: int) -> int:
    """The budget path's seed: min(N, max(round(F K), min(round(1.5 F K), round(0.5 N)), MINIMUM_SEED)), halves up
    (module text; 1.5 = BUDGET_SEED_WIDENING, 0.5 = BUDGET_SEED_CAP)."""
    wider = min(_rounded(BUDGET_SEED_WIDENING * refine * count), _rounded(BUDGET_SEED_CAP * point_count))
    return min(point_count, max(seed_count(refine, count, point_count), wider))


def refined_insertion(field: ReferenceField, grid: EvaluationGrid, *, budget: float | None = None,
                      tolerance: float | None = None, refine: float = RECOMMENDED_REFINE,
                      guide: np.ndarray | None = None,
                      insertion_progress: Callable[[int, int], None] | None = None,
                      refinement_progress: Callable[[int, int], None] | None = None,
                      leaks: Raycaster | None = None, leak_weight: float = LEAK_WEIGHT,
                      repair_rounds: int = REPAIR_ROUNDS, pins: Pins | None = None,
                      head: np.ndarray | None = None) -> RefinedPlacement:
    """The module text's placement; exactly one of `budget` and `tolerance`. `guide` (insertion.checked_guide) seeds
    from guided insertion. `leaks`: the scene's raycaster, for the leak-aware variant (module text; `leak_weight` and
    `repair_rounds` tune it). The progress callbacks get (points ranked, points asked for) during the insertion rounds
    and (probes removed, probes to remove at most) during the refinement. `pins` (pins.py): insertion starts from them
    and never ranks a point near one, the refinement never removes them, a budget counts them, and the leak repair
    adds no probe near one. `head` (InsertionOrder's; the network-seed experiment, Tools~/experiments/network-seed.py):
    insertion starts from these points too, and the tolerance search from the count of start + head."""
    if (budget is None) == (tolerance is None):
        raise MetricError("give exactly one of budget (a fraction, e.g. 0.2) and tolerance (a mean error, e.g. 0.05)")
    factor = float(refine)
    if not (math.isfinite(factor) and factor > 1.0):
        raise MetricError(f"refine {refine!r} must be a factor > 1 (the seed holds refine x K points; "
                          f"{RECOMMENDED_REFINE:g} is recommended)")
    # Checks the weight before any work; one memo of the segments for the repair and the refinement (leak_aware.py).
    weighting = None if leaks is None else LeakWeighting(leaks, leak_weight).remembering(field)
    n = field.point_count
    start = time.perf_counter()
    order = InsertionOrder(field, grid, guide=guide, progress=insertion_progress, pins=pins, head=head)
    select = order.selection()
    keep = None if pins is None else pins.indices
    found = None
    if tolerance is None:
        target = checked_pinned_count(budget_count(budget, n), pins)  # type: ignore[arg-type]
    else:
        smallest = pinned_smallest(pins) if head is None else order.computed  # with a head: no count below it
        found = place_tolerance(field, select, tolerance, PRIMARY_METRIC, smallest, order.mean_error)
        target = int(found.indices.shape[0])
    selection_seconds = time.perf_counter() - start
    start = time.perf_counter()
    seed = select((seed_count if tolerance is not None else budget_seed_count)(factor, target, n))
    # The seed's tetrahedra and the repair's, derived from the insertion rounds' (quality.md §5.1 step 6).
    seed_mesh = order.mesh_of(seed)
    if weighting is not None:
        seed, seed_mesh = leak_repaired_with_mesh(field, seed, weighting.raycaster, repair_rounds,
                                                  None if pins is None else pins.blocked, weighting.visibility,
                                                  seed_mesh, order.tetrahedra)
    evaluation = None
    if tolerance is None:
        refined = batched_refinement(field, seed, count=target, keep=keep, progress=refinement_progress,
                                     leaks=weighting, seed_mesh=seed_mesh)
        # With leaks the refinement's mean is the weighted one, not the metric's.
        indices = refined.indices
        if weighting is not None:
            evaluation = evaluated(field, indices)
        error = refined.mean_error if evaluation is None else evaluation.mean_error
    else:
        refined = batched_refinement(field, seed, tolerance=tolerance, keep=keep, progress=refinement_progress,
                                     leaks=weighting, seed_mesh=seed_mesh)
        assert found is not None
        # Leak-aware: the weighted tolerance met is the goal, whatever the count; else fewer probes than the search's.
        # The refinement updates its errors incrementally, locating only the points a removal touched; the metric locates
        # every point afresh by its coherent walk, and the two can disagree (ctf_compromise's reachable points: about 70
        # points; one, inside the hull on an interior edge, the walk calls outside and projects onto a hull triangle
        # 1.6 m away, where it leaks; plain error 0.0513 > tau; leaks.md). So the set's plain error is evaluated afresh
        # before it replaces the search's answer, as the C# core's RefinedSelection does.
        checked = (evaluated(field, refined.indices)
                   if refined.mean_error <= tolerance and (weighting is not None or refined.indices.shape[0] < target)
                   else None)
        if checked is not None and checked.mean_error <= tolerance:
            indices, error, evaluation = refined.indices, checked.mean_error, checked
        else:
            indices, error = found.indices, found.mean_error
    return RefinedPlacement(indices=indices, requested=int(indices.shape[0]) if tolerance is not None else target,
                            seed=seed, mean_error=float(error),
                            selection_seconds=selection_seconds, refinement_seconds=time.perf_counter() - start,
                            rounds=refined.rounds, evaluation=evaluation,
                            segments=None if weighting is None else weighting.visibility)
