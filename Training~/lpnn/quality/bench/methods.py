"""The methods a benchmark run measures and its yardstick (bench/run.py's module text): each method's ranking (or
lazy insertion order) timed, and what every ratio divides by (the fast reference's error curve, the blockwise
reference's prefixes evaluated on demand, or none; and for the leak-aware rows the leak-aware reference too)."""

from __future__ import annotations

import math
import statistics
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable, TypeVar

import numpy as np

from ...core.capture import Capture
from ...core.capture_file import safe_file_stem
from ...core.grid import EvaluationGrid
from ..metric.metric import PRIMARY_METRIC, ReferenceField, mean_placement_error
from ..placement.apv import NEAREST_SURFACE, apv_ranking
from ..placement.baselines import heuristic_ranking, random_ranking, uniform_selector
from ..placement.decimation.blockwise import blockwise_reference
from ..placement.decimation.decimation import Decimation
from ..placement.decimation.reference_faithful import faithful_decimation
from ..placement.decimation.reference_fast import fast_decimation
from ..placement.insertion import InsertionOrder
from ..placement.leak_aware import LeakWeighting, leaks_to_avoid
from ..placement.policies import Placement, SelectionForCount, prefix_selection, reference_count, reference_tolerance
from .results import BenchConfig, BenchFailure, failure_reason

T = TypeVar("T")


@dataclass
class Method:
    name: str
    select: SelectionForCount
    seconds: float  # producing the ranking (e.g. curvature for the heuristic, the whole reference ordering)
    decimation: Decimation | None = None
    fresh: Callable[[], SelectionForCount] | None = None  # lazy methods: a new selection per row (run.py's module text)
    target: Placement | None = None  # a yardstick's own tolerance answer


@dataclass
class Yardstick:
    """What every ratio divides by: the fast reference's error curve, or the blockwise reference's prefixes evaluated
    on demand (run.py's module text); `target` its tolerance answer."""

    name: str
    method: Method
    error_at: Callable[[int], float]
    curve: np.ndarray
    target: Placement | None
    leak_aware: "Yardstick | None" = None  # what the leak-aware rows are measured against too (run.py's module text)


def _no_yardstick(point_count: int) -> Yardstick:
    """No reference (run.py's module text): every ratio NaN; the tolerance rows still run."""
    return Yardstick("none", Method("none", lambda count: np.zeros(0, dtype=np.int64), 0.0), lambda count: math.nan,
                     np.full(point_count + 1, np.nan), None)


def _fast_yardstick(method: Method, tolerance: float | None) -> Yardstick:
    decimation = method.decimation
    assert decimation is not None
    target = None if tolerance is None else reference_tolerance(decimation, tolerance)
    return Yardstick(method.name, method, lambda count: float(decimation.error_curve[count]), decimation.error_curve,
                      target)


def _errors_on_demand(field_: ReferenceField, select: Callable[[int], np.ndarray],
                      reaches: Callable[[int], bool] = lambda count: True) -> tuple[Callable[[int], float], np.ndarray]:
    """A yardstick's error at a count, evaluated the first time it is asked (the mean error of select(count)) and kept
    in the curve returned beside it; NaN at counts `reaches` says its ranking does not reach."""
    curve = np.full(field_.point_count + 1, np.nan)

    def error_at(count: int) -> float:
        if reaches(count) and np.isnan(curve[count]):
            curve[count] = mean_placement_error(field_, select(count))
        return float(curve[count])

    return error_at, curve


def _blockwise_yardstick(field_: ReferenceField, grid: EvaluationGrid, capture: Capture, config: BenchConfig,
                         name: str) -> Yardstick:
    tolerance = config.tolerance
    checkpoint = None if config.checkpoints is None else Path(config.checkpoints) / f"{safe_file_stem(name)}.blockwise.npz"
    blockwise, seconds = timed(lambda: blockwise_reference(field_, capture.ids, workers=config.workers or 1,
                                                           checkpoint=checkpoint), 1)
    select = prefix_selection(grid, blockwise.ranking)
    error_at, curve = _errors_on_demand(field_, select)
    target = None
    if tolerance is not None:  # completed to a tetrahedron from its own ranking (a volume of one flat block)
        indices = select(int(blockwise.within(tolerance).shape[0]))
        target = Placement(indices=indices, requested=int(indices.shape[0]), added_for_tetrahedron=0,
                           mean_error=mean_placement_error(field_, indices), metric=PRIMARY_METRIC)
    method = Method("blockwise-reference", select, seconds, target=target)
    return Yardstick(method.name, method, error_at, curve, target)


def _leak_aware_yardstick(field_: ReferenceField, method: Method, tolerance: float | None) -> Yardstick:
    """The leak-aware reference as a yardstick of plain errors: its set at a count evaluated on demand (its curve is
    the leak-weighted error it decimated), its tolerance answer (the fewest probes within tau, leak-weighted) with its
    plain mean error; NaN at counts its run did not reach (reference_stop)."""
    decimation = method.decimation
    assert decimation is not None
    error_at, curve = _errors_on_demand(field_, decimation.prefix,
                                        lambda count: decimation.smallest_count <= count <= decimation.start_count)
    target = None
    if tolerance is not None:
        answer = reference_tolerance(decimation, tolerance)
        target = replace(answer, mean_error=mean_placement_error(field_, answer.indices))
    return Yardstick(method.name, method, error_at, curve, target)


def _wants_leak_aware(config: BenchConfig) -> bool:
    """Whether a run measures the leak-aware reference: its own rows, or leak-aware rows to measure against it."""
    return config.leaks == "avoid" and any(config.wants(name) for name in
                                            ("leak-aware-reference", "insertion-refined", "guided-refined"))


def timed(function: Callable[[], T], repeats: int) -> tuple[T, float]:
    """Run `repeats` times (>= 1); the last result and the median wall time in seconds."""
    times, result = [], None
    for _ in range(max(1, int(repeats))):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return result, float(statistics.median(times))  # type: ignore[return-value]


def _ranking_method(name: str, grid: EvaluationGrid, make_ranking: Callable[[], np.ndarray], repeats: int) -> Method:
    ranking, seconds = timed(make_ranking, repeats)
    return Method(name, prefix_selection(grid, ranking), seconds)


def insertion_method(name: str, field_: ReferenceField, grid: EvaluationGrid, guide: np.ndarray | None = None) -> Method:
    """An insertion ranking read lazily (run.py's module text): every row starts a fresh order (its errors surface there and
    are recorded as that method's failure)."""
    def fresh() -> SelectionForCount:
        return InsertionOrder(field_, grid, guide=guide).selection()

    return Method(name, lambda count: fresh()(count), 0.0, fresh=fresh)


def _uniform_method(grid: EvaluationGrid) -> Method:
    return Method("uniform", uniform_selector(grid), 0.0)


def _reference_method(name: str, decimation: Decimation, seconds: float) -> Method:
    def select(count: int) -> np.ndarray:
        return reference_count(decimation, count).indices

    return Method(name, select, seconds, decimation=decimation)


def capture_methods(capture: Capture, field_: ReferenceField, grid: EvaluationGrid, config: BenchConfig,
                    reference: Decimation | None, failures: list[BenchFailure],
                    name: str) -> tuple[list[Method], Yardstick]:
    """Every method's ranking and the yardstick; a baseline whose ranking fails is recorded in `failures` and left out
    (the yardstick's failure fails the capture)."""
    rankings: list[tuple[str, Callable[[], np.ndarray], int]] = [
        ("random", lambda: random_ranking(grid.point_count, config.seed), config.repeats),
        ("heuristic", lambda: heuristic_ranking(grid, capture.sh, capture.lighting_scale), config.repeats),
    ]
    if NEAREST_SURFACE in capture.feature_names:
        rankings.append(("apv", lambda: apv_ranking(grid, capture.features, capture.feature_names), config.repeats))
    methods = [_uniform_method(grid)] if config.wants("uniform") else []
    for method, make_ranking, repeats in rankings:
        if not config.wants(method):
            continue
        try:
            methods.append(_ranking_method(method, grid, make_ranking, repeats))
        except Exception as error:  # recorded; the other methods go on
            failures.append(BenchFailure(name, method, failure_reason(error)))
    if config.wants("insertion"):
        methods.append(insertion_method("insertion", field_, grid))
    if reference is None and config.yardstick == "none":
        return methods, _no_yardstick(field_.point_count)
    if reference is None and field_.point_count > config.full_reference_limit:
        yardstick = _blockwise_yardstick(field_, grid, capture, config, name)
        return methods + [yardstick.method], yardstick
    if reference is None:
        computed, seconds = timed(lambda: fast_decimation(field_, workers=config.workers, stop_above=config.reference_stop),
                                  config.reference_repeats)
        fast = _reference_method("fast-reference", computed, seconds)
    else:  # computed before (e.g. stored with the labels): not re-timed
        fast = _reference_method("fast-reference", reference, reference.seconds)
    methods.append(fast)
    if field_.point_count <= config.faithful_limit and config.wants("faithful-reference"):
        faithful, faithful_seconds = timed(lambda: faithful_decimation(field_, max_candidates=config.faithful_limit),
                                           config.reference_repeats)
        methods.append(_reference_method("faithful-reference", faithful, faithful_seconds))
    yardstick = _fast_yardstick(fast, config.tolerance)
    raycaster = leaks_to_avoid(field_, config.leaks)
    if raycaster is not None and _wants_leak_aware(config):
        # One process: its replica would need the raycaster, which Embree's scene cannot be sent as (removal_costs.py).
        aware, aware_seconds = timed(lambda: fast_decimation(field_, stop_above=config.reference_stop,
                                                             leaks=LeakWeighting(raycaster)), config.reference_repeats)
        aware_method = _reference_method("leak-aware-reference", aware, aware_seconds)
        if config.wants("leak-aware-reference"):
            methods.append(aware_method)
        yardstick = replace(yardstick, leak_aware=_leak_aware_yardstick(field_, aware_method, config.tolerance))
    return methods, yardstick
