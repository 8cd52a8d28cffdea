"""LPNN placement tiers (quality.md §4): network scores -> spread ranking (or guided insertion) -> probes, optionally
refined.

    lpnn_placement(capture, scorer, budget=0.2)                # LPNN: milliseconds
    lpnn_placement(capture, scorer, budget=0.2, refine=2.0)    # LPNN + exact refinement: about a second
    lpnn_placement(capture, scorer, tolerance=0.02)            # fewest probes within tau
    lpnn_placement(capture, scores=s, tolerance=0.02, refine=2.0)

- budget f: K = round(f N); the spread ranking's first K points (+ tetrahedron guarantee).
- tolerance tau: the smallest spread prefix within tau (the search of policies.place_tolerance).
- refine F (> 1; 2 recommended): seed the exact greedy decimation (reference_fast, initial=...) with
  the guided insertion order's first min(N, max(round(F K), MINIMUM_SEED)) points (+ tetrahedron
  guarantee; the raw score ranking's with topk) and decimate down to K. Guided insertion, not the spread
  ranking, since 2026-11-26: a better start for the same greedy (today 0.99-1.07x the reference's error at
  1/5/10/20/30 % on the crops, benchmarks.md "The speed/accuracy trade, every method"). The floor of 64 points: at a 1 % budget (K ~ 8) a seed of 2K points cannot
  reach the reference's sparse answer (8 crops of training levels: 1.39x the reference's error with
  2K, 1.02x with 64, at 0.9 s instead of 0.3 s; 5 % budgets unchanged). With a tolerance: K0 = the bounded tolerance search over the guided insertion order, seed with round(F K0) points, decimate
  until the mean error exceeds REFINE_STOP_FACTOR x tau (or 4 probes are left) and read the exact smallest count
  within tau from the decimation's error curve (the answer K0 is kept if the decimation never gets below it within
  tau).
  A seed of more than FULL_REFERENCE_FRACTION x N points (K > floor(0.4 N / F)) runs the full
  reference decimation instead (every point as the seed): a seeded decimation removes probes from
  sparser meshes, each removal touching more evaluation points, and costs as much as the full one
  from about half the points on (oa_dm1, 1,272 points: seeds of 0.5 N / 0.7 N took 0.75x / 1.4x the
  full reference's time), so the tier is not the slower way to the reference's answer
  (benchmarks.md "The speed/accuracy trade, every method": every held-out budget row faster; with the stop at 2 tau, which the fallback to the full
  reference shares, every held-out tolerance row at most 0.85x the complete reference's time). With a tolerance the search for K0
  (bounded: it never evaluates more than floor(0.4 N / F) + 1 points) gives up as soon as K0 is known
  to exceed that bound; the spread ranking's search (milliseconds) decides it first, so guided
  insertion's rounds are not paid for when the full reference runs anyway.
- topk=True ranks by raw score instead (the old behaviour, for comparison).

Timing split: features (the capture's `source.feature_seconds`, when the importer recorded it),
inference (onnxruntime), selection (ranking, prefix, tetrahedron guarantee; with a tolerance also the
search's error evaluations; guided insertion's rounds up to the count, and its set-up) and refinement
(the seed's further insertion rounds and the seeded decimation). Building the dense reference field
counts where it is needed (tolerance or guided insertion: selection; refinement), unless the caller
passes one.
The final error evaluation is reporting, not placement, and is not timed.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Protocol

import numpy as np

from ...core.features import Raycaster
from ...core.capture import Capture
from ...core.grid import EvaluationGrid
from ...core.selection import rank
from ...core.spread import SpreadPrefix, spread_ranking
from .decimation.decimation import MINIMUM_PROBES
from .insertion import InsertionOrder, guide_of
from ..metric.metric import PlacementQuality, ReferenceField, evaluate_placement
from .policies import (PolicyError, bounded_tolerance, budget_count, checked_tolerance, prefix_selection,
                       spread_prefix_selection)
from .decimation.reference_fast import fast_decimation
from .refined_insertion import RECOMMENDED_REFINE, refined_insertion, seed_count

# At a tolerance tau the refinement's greedy stops once the mean error exceeds this multiple of tau (reference_fast's
# stop_above): on the full reference curves of the 154 labelled recipe crops of training and validation levels, tau =
# 0.02/0.05/0.1, stopping at 2 tau gave the full curve's smallest count within tau in all 462 cases (stopping at tau:
# 4 differed, up to 1.5x), and it skips the dearest removals.
REFINE_STOP_FACTOR = 2.0
FULL_REFERENCE_FRACTION = 0.4  # seeds above this fraction of the points: run the full reference (module text)


class Scorer(Protocol):
    """What lpnn_placement needs of lpnn.train.onnx_scoring.OnnxScorer."""

    def score_capture(self, capture: Any, name: str = ...) -> np.ndarray: ...


@dataclass(frozen=True)
class PlacementTiming:
    """Seconds per stage; `features` is None when the capture does not record it."""

    features: float | None
    inference: float
    selection: float
    refinement: float

    @property
    def total(self) -> float:
        return (self.features or 0.0) + self.inference + self.selection + self.refinement


@dataclass(frozen=True)
class LpnnPlacement:
    indices: np.ndarray  # (K,) int64 point indices, sorted
    quality: PlacementQuality | None  # irradiance (primary) and SMAPE errors of `indices` (None: report=False)
    ranking: np.ndarray  # (N,) the spread, top-K or guided insertion ranking the probes came from (full_ranking=False: its computed prefix)
    requested: int  # the count asked for (budget K, or the tolerance search's answer)
    added_for_tetrahedron: int
    refine: float | None
    timing: PlacementTiming
    checked: dict[int, float] = field(default_factory=dict)  # tolerance: count -> mean error evaluated
    seed_count: int | None = None  # refinement: points the decimation started from

    @property
    def mean_error(self) -> float:
        """The irradiance mean error (report=False: the tolerance search's for the kept prefix, else NaN)."""
        if self.quality is not None:
            return self.quality.irradiance.mean
        return self.checked.get(self.requested, math.nan)


def checked_refine(refine: float | None) -> float | None:
    if refine is None:
        return None
    value = float(refine)
    if not (math.isfinite(value) and value > 1.0):
        raise PolicyError(f"refine {refine!r} must be a factor > 1 (the seed holds refine x K points; "
                          f"{RECOMMENDED_REFINE:g} is recommended), or None for no refinement")
    return value


def largest_seeded_count(refine: float, point_count: int) -> int:
    """The largest K guided-exact-refined seeds with a prefix of its ranking; above it runs the full reference."""
    return int(math.floor(FULL_REFERENCE_FRACTION * point_count / refine))


def feature_seconds(capture: Capture) -> float | None:
    value = capture.source.get("feature_seconds")
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def lpnn_placement(capture: Capture, scorer: Scorer | None = None, *, scores: np.ndarray | None = None,
                   budget: float | None = None, tolerance: float | None = None, refine: float | None = None,
                   topk: bool = False, guided: bool = False, batched: bool = False,
                   reference: ReferenceField | None = None,
                   workers: int | None = None, name: str = "the capture", full_ranking: bool = True,
                   report: bool = True, progress: Callable[[int, int], None] | None = None,
                   leaks: Raycaster | None = None) -> LpnnPlacement:
    """Probes for `capture` from an LPNN scorer (or precomputed `scores`, (N,)): exactly one of
    `budget` (fraction in (0, 1]) and `tolerance` (mean error > 0); `refine` F > 1 adds the seeded
    exact refinement, seeded by guided insertion; `topk` ranks by raw score instead of the spread ranking;
    `guided` ranks by insertion guided by the scores (insertion.py, quality.md §5.2: lazily, as far as the
    policy reads; `progress` gets its rounds' points ranked of the count asked for); `reference` reuses
    ReferenceField.from_capture(capture); `workers` (1 or 2) goes to the refinement's decimation;
    `batched` (with `refine`) refines by batched refinement instead of the exact greedy (refined_insertion.py,
    quality.md §5.3: what Unity volumes run; seconds instead of minutes on whole levels, never the full reference);
    `name` appears in error messages; full_ranking=False ranks only the points the policy reads
    (spread ranking: core.spread.SpreadPrefix; guided: the insertion rounds up to the count; the same probes;
    `ranking` is then the computed prefix; guided-exact-refined always returns its computed prefix); report=False skips the final error evaluation (`quality` None: no dense reference field
    for a budget, no tetrahedralisation of the result); `leaks` (with `batched`: guided-refined) the scene's raycaster,
    for the leak-aware refinement of the default (refined_insertion's `leaks`, leaks.md). Raises PolicyError for bad
    parameters."""
    if (budget is None) == (tolerance is None):
        raise PolicyError("give exactly one of budget (a fraction, e.g. 0.2) and tolerance (a mean error, e.g. 0.02)")
    if (scorer is None) == (scores is None):
        raise PolicyError("give exactly one of scorer (an OnnxScorer) and scores (one value per point)")
    factor = checked_refine(refine)
    if guided and topk:
        raise PolicyError("guided insertion ranks by itself: use it without topk")
    if batched and (factor is None or topk):
        raise PolicyError("batched is a way to refine guided insertion: use it with refine (e.g. 2) and without topk")
    if leaks is not None and not batched:  # the leak weighting acts through the batched refinement (leaks.md)
        raise PolicyError("leaks apply to the refinement in batches (guided-refined): use them with batched")
    # The refinement's seed and its tolerance search come from the guided insertion order (unless topk): a better
    # start than the spread ranking's (benchmarks.md "The speed/accuracy trade, every method": within 1.07x the reference's error at every budget on the
    # crops).
    by_insertion = guided or (factor is not None and not topk)
    tau = None if tolerance is None else checked_tolerance(tolerance)
    n = capture.point_count
    inference = 0.0
    if scorer is not None:
        start = time.perf_counter()
        scores = scorer.score_capture(capture, name)
        inference = time.perf_counter() - start
    values = np.asarray(scores)
    if values.shape != (n,):
        raise PolicyError(f"{name}: scores of shape {list(values.shape)} for {n:,} points: give one score per point")

    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    if batched:
        return _batched_placement(capture, grid, values, budget, tolerance, factor, reference, inference, report,
                                  progress, leaks)
    start = time.perf_counter()
    lazy = None if (full_ranking or topk or by_insertion) else SpreadPrefix(capture.positions, values)
    order = None
    if by_insertion:
        reference = ReferenceField.from_capture(capture) if reference is None else reference
        order = InsertionOrder(reference, grid, progress=progress, guide=guide_of(values))
        select = order.selection()
    elif lazy is None:
        ranking = rank(values) if topk else spread_ranking(capture.positions, values)
        select = prefix_selection(grid, ranking)
    else:
        select = spread_prefix_selection(grid, lazy)
    checked: dict[int, float] = {}
    largest = None if factor is None else largest_seeded_count(factor, n)
    if tau is None:
        requested = budget_count(budget, n)  # type: ignore[arg-type]
        if largest is not None and requested > largest:  # the refinement runs the full reference: no prefix needed
            indices = np.arange(n, dtype=np.int64)
        else:
            indices = select(requested)
    else:
        reference = ReferenceField.from_capture(capture) if reference is None else reference
        found = None
        if order is None or largest is None or not _spread_answer_too_large(reference, grid, capture.positions, values,
                                                                            tau, largest):
            found = bounded_tolerance(reference, select, tau, largest=largest)
        if found is None:  # K0 > largest: the refinement below runs the full reference
            requested, indices = n, np.arange(n, dtype=np.int64)
        else:
            requested, indices, checked = found.requested, found.indices, found.checked
    selection = time.perf_counter() - start

    refinement, seeded = 0.0, None
    if factor is not None:
        start = time.perf_counter()
        reference = ReferenceField.from_capture(capture) if reference is None else reference
        target = requested if tau is None else int(indices.shape[0])
        seed = None
        if target <= int(largest):  # type: ignore[arg-type]
            seed = select(seed_count(factor, target, n))  # the ranking's prefix, completed to a tetrahedron
        seeded = n if seed is None else int(seed.shape[0])
        refined = _refined(reference, seed, target, tau, workers)
        if refined is not None:
            requested, indices = refined
        refinement = time.perf_counter() - start
    if lazy is not None:
        ranking = lazy.prefix(lazy.computed)
    elif order is not None:  # the whole order only for the guided tier asked for it: refinement never reads it
        ranking = order.prefix(order.point_count if (full_ranking and guided) else order.computed)
    quality = None
    if report:
        reference = ReferenceField.from_capture(capture) if reference is None else reference
        quality = evaluate_placement(reference, indices)
    return LpnnPlacement(indices=indices, quality=quality, ranking=ranking,
                         requested=int(requested), added_for_tetrahedron=max(0, int(indices.shape[0]) - int(requested)),
                         refine=factor, timing=PlacementTiming(feature_seconds(capture), inference, selection, refinement),
                         checked=checked, seed_count=seeded)


def _batched_placement(capture: Capture, grid: EvaluationGrid, scores: np.ndarray, budget: float | None,
                       tolerance: float | None, factor: float, reference: ReferenceField | None, inference: float,
                       report: bool, progress: Callable[[int, int], None] | None,
                       leaks: Raycaster | None = None) -> LpnnPlacement:
    """guided-refined (methods.md): refined_insertion seeded by guided insertion (plain above its point limit);
    leak-aware with `leaks` (the scene's raycaster), as the default insertion-refined is (leaks.md)."""
    reference = ReferenceField.from_capture(capture) if reference is None else reference
    placed = refined_insertion(reference, grid, budget=budget, tolerance=tolerance, refine=factor,
                               guide=guide_of(scores), insertion_progress=progress, leaks=leaks)
    quality = evaluate_placement(reference, placed.indices) if report else None
    checked = {} if tolerance is None else {placed.requested: placed.mean_error}
    return LpnnPlacement(indices=placed.indices, quality=quality, ranking=placed.indices, requested=placed.requested,
                         added_for_tetrahedron=0, refine=factor,
                         timing=PlacementTiming(feature_seconds(capture), inference, placed.selection_seconds,
                                                placed.refinement_seconds),
                         checked=checked, seed_count=placed.seed_count)


def _spread_answer_too_large(reference: ReferenceField, grid: EvaluationGrid, positions: np.ndarray, scores: np.ndarray,
                             tau: float, largest: int) -> bool:
    """Whether the spread ranking's tolerance answer exceeds `largest`, found in its milliseconds (the search gives up
    past largest + 1): guided-exact-refined then runs the full reference at once instead of first paying for guided
    insertion's rounds up to `largest` (14 held-out crops at tau: 4 rows were up to 1.52x the reference's time with
    that search, benchmarks.md "The speed/accuracy trade, every method"). The spread answer is the larger one on nearly every crop (2.06x against 1.57x
    the reference's probes, benchmarks.md "The speed/accuracy trade, every method"), so this sends to the full reference at most the volumes near the bound."""
    return bounded_tolerance(reference, spread_prefix_selection(grid, SpreadPrefix(positions, scores)), tau,
                             largest=largest) is None


def _refined(reference: ReferenceField, seed: np.ndarray | None, target: int, tau: float | None,
             workers: int | None) -> tuple[int, np.ndarray] | None:
    """(count, indices) from the exact greedy seeded with `seed` (None: every point, the full
    reference): down to `target` (budget), or the smallest count within `tau` if it is <= `target`
    (tolerance); None = keep the unrefined answer."""
    start_count = reference.point_count if seed is None else int(seed.shape[0])
    if start_count <= (max(target, MINIMUM_PROBES) if tau is None else MINIMUM_PROBES):
        return None  # nothing to decimate: the seed is the answer already
    decimation = fast_decimation(reference, workers=workers, initial=seed,
                                 min_count=target if tau is None else MINIMUM_PROBES,
                                 stop_above=None if tau is None else REFINE_STOP_FACTOR * tau)
    if tau is None:
        return target, decimation.prefix(max(target, decimation.smallest_count))
    best = decimation.smallest_count_within(tau)
    return None if best is None or best > target else (best, decimation.prefix(best))
