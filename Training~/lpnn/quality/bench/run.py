"""The speed/accuracy benchmark (quality.md §6): every method x budget (and the tolerance policy)
on every capture: probes kept, time, mean/p95 error (both metrics) and the ratio to the reference. This module runs a
capture and makes its rows; results.py holds the rows and their CSV, methods.py the methods' rankings and the yardstick.

Methods: uniform, random, heuristic, apv (APV-style geometry density, placement/apv.py; when the capture has the
`nearest_surface` feature), insertion (error-driven coarse-to-fine insertion, placement/insertion.py), insertion-refined
(insertion refined in batches, placement/refined_insertion.py: the best non-learned method, the bar for the learned
tier; the default placement, so leak-aware where the capture's geometry is known unless `leaks` is "ignore": leaks.md);
with a model the five methods that read the scores (placement/lpnn_placement.py, run as the table of
placement/methods.py says): network-topk (the raw top-K, for comparison), network (spread ranking), guided (insertion guided by the scores, placement/insertion.py), guided-refined (guided insertion
refined in batches: what a Unity volume does; above the guide's point limit its rows are insertion-refined's plus the
inference) and guided-exact-refined (guided insertion + seeded exact refinement, factor `refine`); the fast reference, and the
faithful one on small captures.

Leaks. The fast reference is leak-blind; the leak-aware default (insertion-refined, guided-refined with `leaks` "avoid"
where the capture's geometry is known) refines a leak-weighted error, so its rows are also measured against the
leak-aware reference (quality.md §3.2: the exact greedy of that error, rows `leak-aware-reference`, computed when the
geometry is known and `leaks` is "avoid"): columns leak_reference_error / leak_error_ratio (its plain error at the same
count) and leak_reference_probes / leak_probes_ratio (its answer at tau: the fewest probes whose leak-weighted mean
error is within tau). The other columns stay against the leak-blind yardstick for every row, so both comparisons are
in each leak-aware row; the leak-aware reference's own rows against the leak-blind one give the price of avoiding
leaks at the optimum.

The yardstick every ratio divides by is the fast reference (quality.md §3.2) up to `full_reference_limit` points
(150,000 by default: ~20 minutes and ~3 GB), and above it the blockwise reference (quality.md §3.3, rows
`blockwise-reference`): its error at a budget's count is its ranking's prefix evaluated, its tolerance answer the
union of the blocks' answers (which lands ~10 % above tau on the whole volume). Above the limit the methods that run
the full reference (the fast and faithful references, guided-exact-refined) are not run; guided-exact-refined, which decimates again
for every row, runs only up to `refine_limit` points (20,000). The insertion methods rank lazily, as
`lpnn place` does: a budget row costs the rounds up to its count (a fresh order per row, so each row's time is what
placing at that budget costs), the tolerance row the rounds its search reads. Above the guide's point limit
(insertion.GUIDED_POINT_LIMIT) guided is plain insertion, and its rows are the insertion rows plus the inference.
Times are medians over `repeats` runs for the cheap methods; the references and guided-exact-refined run
`reference_repeats` times (default 1: they take seconds). LPNN's time is split into features (the
capture's `source.feature_seconds`, when the importer recorded it), inference (onnxruntime, shared by
the tiers), selection (ranking + prefix + tetrahedron guarantee) and refinement. A tolerance
row's time includes its error evaluations (the search needs them).

Three options shape a run on whole levels (the trade table, benchmarks.md "The speed/accuracy trade"): `methods` runs only
the named methods (the yardstick is always computed); `reference_stop` stops the fast reference once its error exceeds it
(its curve is the full one down to that count, where the last and dearest removals are left out; budgets whose counts lie
below get no ratio); `yardstick="none"` computes no reference at all (every ratio NaN, column `yardstick` "none": where
neither reference fits in the time, the rows still give each method's probes, error and time).
"""


from __future__ import annotations

import math
import statistics
import time
from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import numpy as np

from ...core.capture import Capture
from ...core.features import Raycaster
from ...core.grid import EvaluationGrid
from ..metric.metric import PRIMARY_METRIC, PlacementQuality, ReferenceField, evaluate_placement, guarded_ratio
from ..placement.decimation.decimation import MINIMUM_PROBES, Decimation
from ..placement.insertion import guide_of
from ..placement.lpnn_placement import feature_seconds, lpnn_placement
from ..placement.methods import BY_NAME, SCORED
from ..placement.policies import Placement, budget_count, place_tolerance, reference_tolerance
from ..placement.leak_aware import leaks_to_avoid
from ..placement.refined_insertion import refined_insertion
from .methods import Method, Yardstick, capture_methods, insertion_method, timed
from .results import BenchConfig, BenchFailure, BenchRow, CaptureResult, failure_reason



@dataclass(frozen=True)
class _Timing:
    seconds: float  # time to place, total
    features: float | None = None
    inference: float | None = None
    selection: float | None = None
    refine: float | None = None



def _row(name: str, field_: ReferenceField, method: str, policy: str, parameter: float, quality: PlacementQuality,
         timing: _Timing, reference_error: float, yardstick: str) -> BenchRow:
    return BenchRow(
        capture=name, points=field_.point_count, method=method, policy=policy, parameter=parameter,
        probes=quality.probes, seconds=timing.seconds, feature_seconds=timing.features,
        inference_seconds=timing.inference, selection_seconds=timing.selection, refine_seconds=timing.refine,
        mean_error=quality.irradiance.mean, p95_error=quality.irradiance.p95, smape_mean=quality.smape.mean,
        smape_p95=quality.smape.p95, reference_error=reference_error,
        error_ratio=math.nan if math.isnan(reference_error) else guarded_ratio(quality.irradiance.mean, reference_error),
        yardstick=yardstick,
        in_use_error=quality.in_use_error, leaking=quality.leaking)


def _with_leak_aware(row: BenchRow, leak_aware: Yardstick | None) -> BenchRow:
    """A leak-aware row with its ratios to the leak-aware reference too (module text), when it was computed."""
    if leak_aware is None:
        return row
    if row.policy == "budget":
        row.leak_reference_error = leak_aware.error_at(max(row.probes, MINIMUM_PROBES))
    elif leak_aware.target is not None:
        row.leak_reference_error = leak_aware.target.mean_error
        row.leak_reference_probes = int(leak_aware.target.indices.shape[0])
        row.leak_probes_ratio = row.probes / row.leak_reference_probes
    if not math.isnan(row.leak_reference_error):
        row.leak_error_ratio = guarded_ratio(row.mean_error, row.leak_reference_error)
    return row


def _with_target(row: BenchRow, target: Placement) -> BenchRow:
    """A tolerance row with the reference's smallest count within the same tau."""
    row.reference_probes = int(target.indices.shape[0])
    row.probes_ratio = row.probes / row.reference_probes
    return row


def _policies(config: BenchConfig, yardstick: Yardstick) -> list[tuple[str, float, dict[str, float]]]:
    """(policy, parameter, keyword arguments) of every row a placement method gets: each budget, and the tolerance when
    the yardstick has a tolerance answer (or there is no yardstick)."""
    policies = [("budget", fraction, {"budget": fraction}) for fraction in config.budgets]
    if _has_tolerance_rows(config, yardstick):
        policies.append(("tolerance", config.tolerance, {"tolerance": config.tolerance}))
    return policies


def _policy_row(name: str, field_: ReferenceField, method: str, policy: str, parameter: float,
                quality: PlacementQuality, timing: _Timing, yardstick: Yardstick) -> BenchRow:
    """One placement's row against the yardstick: its error at the same count (budget), or its answer's (tolerance)."""
    if policy == "budget":
        return _row(name, field_, method, policy, parameter, quality, timing,
                    yardstick.error_at(max(quality.probes, MINIMUM_PROBES)), yardstick.name)
    if yardstick.target is None:  # no yardstick (module text): the answer without a ratio
        return _row(name, field_, method, policy, parameter, quality, timing, math.nan, yardstick.name)
    return _with_target(_row(name, field_, method, policy, parameter, quality, timing, yardstick.target.mean_error,
                             yardstick.name), yardstick.target)


def _ranking_rows(name: str, field_: ReferenceField, method: Method, config: BenchConfig,
                  yardstick: Yardstick) -> list[BenchRow]:
    rows = []
    precomputed = method.decimation is not None or method.target is not None  # a reference: all in method.seconds
    repeats = config.reference_repeats if method.fresh is not None else config.repeats
    for fraction in config.budgets:
        count = budget_count(fraction, field_.point_count)
        indices, selection_seconds = timed(lambda count=count: method.select(count), repeats)  # lazy: a fresh order
        timing = _Timing(method.seconds + (0.0 if precomputed else selection_seconds),
                         selection=None if precomputed else selection_seconds)
        rows.append(_policy_row(name, field_, method.name, "budget", fraction, evaluate_placement(field_, indices),
                                timing, yardstick))
    if _has_tolerance_rows(config, yardstick):
        start = time.perf_counter()
        if method.decimation is not None:
            placement = reference_tolerance(method.decimation, config.tolerance)
        elif method.target is not None:
            placement = method.target
        else:
            select = method.fresh() if method.fresh is not None else method.select
            placement = place_tolerance(field_, select, config.tolerance, PRIMARY_METRIC)
        search_seconds = 0.0 if precomputed else time.perf_counter() - start
        rows.append(_policy_row(name, field_, method.name, "tolerance", config.tolerance,
                                evaluate_placement(field_, placement.indices),
                                _Timing(method.seconds + search_seconds, selection=None if precomputed else search_seconds),
                                yardstick))
    return rows


def _has_tolerance_rows(config: BenchConfig, yardstick: Yardstick) -> bool:
    return config.tolerance is not None and (yardstick.target is not None or yardstick.name == "none")


def _lpnn_rows(name: str, capture: Capture, field_: ReferenceField, config: BenchConfig, scorer: Any,
               yardstick: Yardstick, log: Callable[[str], None] | None, failures: list[BenchFailure],
               insertion_rows: Sequence[BenchRow], refined_rows: Sequence[BenchRow] = ()) -> list[BenchRow]:
    """The methods that read the scores (network-topk, network, guided, guided-refined, guided-exact-refined) on the
    same scores (inference timed once, shared); a tier that fails on a policy is recorded in `failures` and the others
    go on. guided-exact-refined runs the full reference: not above the full reference's limit, nor
    above `refine_limit` points (a decimation per row)."""
    scores, inference = timed(lambda: scorer.score_capture(capture, name), config.repeats)
    features = feature_seconds(capture)
    tiers = [(tier, BY_NAME[tier].lpnn_options(), config.repeats) for tier in ("network-topk", "network")
             if config.wants(tier)]
    if yardstick.name == "fast-reference" and field_.point_count <= config.refine_limit and config.wants("guided-exact-refined"):
        tiers.append(("guided-exact-refined", BY_NAME["guided-exact-refined"].lpnn_options(config.refine),
                      config.reference_repeats))
    policies = _policies(config, yardstick)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    rows: list[BenchRow] = []
    if config.wants("guided"):
        rows.extend(_guided_tier_rows(name, "guided", scores, inference, features, failures, insertion_rows,
                                      lambda guide: _ranking_rows(name, field_, insertion_method("guided", field_,
                                                                                                  grid, guide),
                                                                  config, yardstick)))
        if log is not None:
            log(f"{name}: guided done")
    if config.wants("guided-refined"):
        rows.extend(_guided_tier_rows(name, "guided-refined", scores, inference, features, failures, refined_rows,
                                      lambda guide: _refined_rows(name, field_, grid, config, yardstick, "guided-refined",
                                                                  guide)))
        if log is not None:
            log(f"{name}: guided-refined done")
    for method, options, repeats in tiers:
        for policy, parameter, chosen in policies:
            try:
                runs = [lpnn_placement(capture, scores=scores, reference=field_, workers=config.workers, name=name,
                                       **chosen, **options) for _ in range(max(1, int(repeats)))]
            except Exception as error:  # recorded; the other tiers and policies go on
                failures.append(BenchFailure(name, f"{method} {policy}={parameter:g}", failure_reason(error)))
                continue
            selection = float(statistics.median(r.timing.selection for r in runs))
            refine = float(statistics.median(r.timing.refinement for r in runs)) if BY_NAME[method].refinement else None
            timing = _Timing((features or 0.0) + inference + selection + (refine or 0.0), features, inference,
                             selection, refine)
            rows.append(_policy_row(name, field_, method, policy, parameter, runs[-1].quality, timing, yardstick))
        if log is not None:
            log(f"{name}: {method} done")
    return rows


def _guided_tier_rows(name: str, method: str, scores: np.ndarray, inference: float, features: float | None,
                      failures: list[BenchFailure], unguided_rows: Sequence[BenchRow],
                      compute: Callable[[np.ndarray], list[BenchRow]]) -> list[BenchRow]:
    """A tier seeded by insertion guided by the scores (quality.md §5.2): `compute(guide)`, or above the guide's point
    limit, where the tier is its unguided method, that method's rows (when they ran; minutes on a whole level, not
    computed again). Its time adds the features and the inference; a failure is recorded and the other tiers go on."""
    guide = guide_of(scores)
    try:
        rows = ([replace(row, method=method) for row in unguided_rows] if guide is None and unguided_rows
                else compute(guide))
    except Exception as error:  # recorded; the other tiers go on
        failures.append(BenchFailure(name, method, failure_reason(error)))
        return []
    for row in rows:
        row.inference_seconds, row.feature_seconds = inference, features
        row.seconds += inference + (features or 0.0)
    return rows


def _refined_rows(name: str, field_: ReferenceField, grid: EvaluationGrid, config: BenchConfig, yardstick: Yardstick,
                  method: str = "insertion-refined", guide: np.ndarray | None = None) -> list[BenchRow]:
    """Insertion refined in batches (placement/refined_insertion.py; guided by `guide` when given) at every budget and
    the tolerance: each row places afresh, so its time is what that placement costs (selection + refinement). The
    rows are leak-aware with the capture's geometry unless config.leaks is "ignore" (the default placement's rule;
    Unity's refined methods follow the volume's Avoid light leaks the same way)."""
    policies = _policies(config, yardstick)
    leaks = leaks_to_avoid(field_, config.leaks)  # both refined rows (insertion-refined, guided-refined) avoid leaks
    rows = []
    for policy, parameter, chosen in policies:
        placed = refined_insertion(field_, grid, refine=config.refine, guide=guide, leaks=leaks,
                                   **chosen)  # minutes on a level: once
        timing = _Timing(placed.selection_seconds + placed.refinement_seconds, selection=placed.selection_seconds,
                         refine=placed.refinement_seconds)
        row = _policy_row(name, field_, method, policy, parameter, evaluate_placement(field_, placed.indices), timing,
                          yardstick)
        rows.append(row if leaks is None else _with_leak_aware(row, yardstick.leak_aware))
    return rows


def bench_capture(name: str, capture: Capture, config: BenchConfig, scorer: Any | None = None,
                  log: Callable[[str], None] | None = None, reference: Decimation | None = None,
                  partial: Callable[[list[BenchRow]], None] | None = None,
                  geometry: Raycaster | None = None) -> CaptureResult:
    """Every method on one capture. `reference`: the capture's fast-reference decimation when already
    known (its time is then its own `seconds`, and the faithful reference is skipped). `partial` gets the rows so far
    after every method (a whole level's methods take minutes each: the CLI writes them as they come). `geometry`: the
    capture's surfaces (scenes.capture_geometry), so every row reports its leaking share (leaks.md)."""
    field_ = replace(ReferenceField.from_capture(capture), geometry=geometry)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    if reference is not None and reference.point_count != field_.point_count:
        raise ValueError(f"{name}: the given reference covers {reference.point_count:,} points, the capture {field_.point_count:,}")
    failures: list[BenchFailure] = []
    methods, yardstick = capture_methods(capture, field_, grid, config, reference, failures, name)
    rows: list[BenchRow] = []
    for method in methods:
        try:
            rows.extend(_ranking_rows(name, field_, method, config, yardstick))
        except Exception as error:  # one method's failure must not cost the others' results
            failures.append(BenchFailure(name, method.name, failure_reason(error)))
            continue
        if log is not None:
            log(f"{name}: {method.name} done ({method.seconds:.3f} s to rank)")
        if partial is not None:
            partial(rows)
    try:
        if config.wants("insertion-refined"):
            rows.extend(_refined_rows(name, field_, grid, config, yardstick))
            if log is not None:
                log(f"{name}: insertion-refined done")
            if partial is not None:
                partial(rows)
    except Exception as error:  # recorded; the others go on
        failures.append(BenchFailure(name, "insertion-refined", failure_reason(error)))
    if scorer is not None and any(config.wants(tier) for tier in SCORED):
        rows.extend(_lpnn_rows(name, capture, field_, config, scorer, yardstick, log, failures,
                               [row for row in rows if row.method == "insertion"],
                               [row for row in rows if row.method == "insertion-refined"]))
    return CaptureResult(name=name, points=field_.point_count, rows=rows, reference_curve=yardstick.curve,
                         yardstick=yardstick.name, failures=failures)

