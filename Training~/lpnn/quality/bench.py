"""The speed/accuracy benchmark (quality.md §6): every method x budget (and the tolerance policy)
on every capture: probes kept, time, mean/p95 error (both metrics) and the ratio to the reference.

Times are medians over `repeats` runs for the cheap methods (uniform, random, heuristic, LPNN); the
references run `reference_repeats` times (default 1: they take seconds to minutes). LPNN's time is
split into features (the capture's `source.feature_seconds`, when the importer recorded it),
inference (onnxruntime) and selection (ranking + prefix + tetrahedron guarantee). A tolerance row's
time includes its error evaluations (the search needs them).
"""

from __future__ import annotations

import statistics
import time
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Sequence, TypeVar

import numpy as np

from ..core.capture import Capture
from ..core.grid import EvaluationGrid
from ..core.selection import ensure_tetrahedron, rank
from .baselines import DEFAULT_SEED, heuristic_ranking, random_ranking, uniform_selection
from .decimation import Decimation
from .metric import PRIMARY_METRIC, ReferenceField, evaluate_placement
from .policies import (SelectionForCount, budget_count, place_tolerance, prefix_selection, reference_count,
                       reference_tolerance)
from .reference_faithful import FAITHFUL_MAX_CANDIDATES, faithful_decimation
from .reference_fast import fast_decimation

DEFAULT_BUDGETS = (0.1, 0.2, 0.3)
DEFAULT_TOLERANCE = 0.02
CSV_COLUMNS = (
    "capture", "points", "method", "policy", "parameter", "probes", "seconds", "feature_seconds",
    "inference_seconds", "selection_seconds", "mean_error", "p95_error", "smape_mean", "smape_p95",
    "reference_error", "error_ratio", "reference_probes", "probes_ratio",
)
T = TypeVar("T")


@dataclass(frozen=True)
class BenchConfig:
    budgets: tuple[float, ...] = DEFAULT_BUDGETS
    tolerance: float | None = DEFAULT_TOLERANCE
    repeats: int = 3
    reference_repeats: int = 1
    seed: int = DEFAULT_SEED
    faithful_limit: int = FAITHFUL_MAX_CANDIDATES
    workers: int | None = None  # fast reference processes (None: 1)


@dataclass
class BenchRow:
    capture: str
    points: int
    method: str
    policy: str  # "budget" or "tolerance"
    parameter: float
    probes: int
    seconds: float
    feature_seconds: float | None
    inference_seconds: float | None
    selection_seconds: float | None
    mean_error: float
    p95_error: float
    smape_mean: float
    smape_p95: float
    reference_error: float  # fast reference at the same probe count (budget rows) / its tolerance set
    error_ratio: float
    reference_probes: int | None = None  # tolerance rows: the reference's smallest count within tau
    probes_ratio: float | None = None


@dataclass
class CaptureResult:
    name: str
    points: int
    rows: list[BenchRow]
    reference_curve: np.ndarray  # fast reference: mean error by probe count
    extra: dict[str, Any] = field(default_factory=dict)


@dataclass
class _Method:
    name: str
    select: SelectionForCount
    seconds: float  # producing the ranking (features + inference for LPNN, scores for the heuristic...)
    feature_seconds: float | None = None
    inference_seconds: float | None = None
    decimation: Decimation | None = None


def timed(function: Callable[[], T], repeats: int) -> tuple[T, float]:
    """Run `repeats` times (>= 1); the last result and the median wall time in seconds."""
    times, result = [], None
    for _ in range(max(1, int(repeats))):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return result, float(statistics.median(times))  # type: ignore[return-value]


def _ranking_method(name: str, grid: EvaluationGrid, make_ranking: Callable[[], np.ndarray], repeats: int,
                    feature_seconds: float | None = None, inference_seconds: float | None = None) -> _Method:
    ranking, seconds = timed(make_ranking, repeats)
    return _Method(name, prefix_selection(grid, ranking), seconds, feature_seconds, inference_seconds)


def _uniform_method(grid: EvaluationGrid) -> _Method:
    fallback = np.arange(grid.point_count, dtype=np.int64)  # grid order completes a flat subsample

    def select(count: int) -> np.ndarray:
        return ensure_tetrahedron(grid, fallback, uniform_selection(grid.ids, count))[0]

    return _Method("uniform", select, 0.0)


def _reference_method(name: str, decimation: Decimation, seconds: float) -> _Method:
    def select(count: int) -> np.ndarray:
        return reference_count(decimation, count).indices

    return _Method(name, select, seconds, decimation=decimation)


def _methods(capture: Capture, field_: ReferenceField, grid: EvaluationGrid, config: BenchConfig,
             scorer: Any | None) -> list[_Method]:
    methods = [
        _uniform_method(grid),
        _ranking_method("random", grid, lambda: random_ranking(grid.point_count, config.seed), config.repeats),
        _ranking_method("heuristic", grid, lambda: heuristic_ranking(grid, capture.sh, capture.lighting_scale),
                        config.repeats),
    ]
    if scorer is not None:
        scores, inference = timed(lambda: scorer.score_capture(capture), config.repeats)
        feature_seconds = capture.source.get("feature_seconds")
        feature_seconds = float(feature_seconds) if isinstance(feature_seconds, (int, float)) else None
        lpnn = _ranking_method("lpnn", grid, lambda: rank(scores), config.repeats, feature_seconds, inference)
        lpnn.seconds += inference + (feature_seconds or 0.0)
        methods.append(lpnn)
    fast, fast_seconds = timed(lambda: fast_decimation(field_, workers=config.workers), config.reference_repeats)
    methods.append(_reference_method("fast-reference", fast, fast_seconds))
    if field_.point_count <= config.faithful_limit:
        faithful, faithful_seconds = timed(lambda: faithful_decimation(field_, max_candidates=config.faithful_limit),
                                           config.reference_repeats)
        methods.append(_reference_method("faithful-reference", faithful, faithful_seconds))
    return methods


def _row(name: str, field_: ReferenceField, method: _Method, policy: str, parameter: float, indices: np.ndarray,
         seconds: float, selection_seconds: float | None, reference_error: float) -> BenchRow:
    quality = evaluate_placement(field_, indices)
    return BenchRow(
        capture=name, points=field_.point_count, method=method.name, policy=policy, parameter=parameter,
        probes=int(indices.shape[0]), seconds=seconds, feature_seconds=method.feature_seconds,
        inference_seconds=method.inference_seconds, selection_seconds=selection_seconds,
        mean_error=quality.irradiance.mean, p95_error=quality.irradiance.p95, smape_mean=quality.smape.mean,
        smape_p95=quality.smape.p95, reference_error=reference_error,
        error_ratio=quality.irradiance.mean / reference_error if reference_error > 0 else
        (1.0 if quality.irradiance.mean == 0 else float("inf")))


def bench_capture(name: str, capture: Capture, config: BenchConfig, scorer: Any | None = None,
                  log: Callable[[str], None] | None = None) -> CaptureResult:
    field_ = ReferenceField.from_capture(capture)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    methods = _methods(capture, field_, grid, config, scorer)
    reference = next(m for m in methods if m.name == "fast-reference").decimation
    assert reference is not None
    rows: list[BenchRow] = []
    for method in methods:
        for fraction in config.budgets:
            count = budget_count(fraction, field_.point_count)
            indices, selection_seconds = timed(lambda: method.select(count), config.repeats)
            total = method.seconds + (0.0 if method.decimation is not None else selection_seconds)
            rows.append(_row(name, field_, method, "budget", fraction, indices, total,
                             None if method.decimation is not None else selection_seconds,
                             float(reference.error_curve[max(indices.shape[0], 4)])))
        if config.tolerance is not None:
            start = time.perf_counter()
            placement = (reference_tolerance(method.decimation, config.tolerance) if method.decimation is not None
                         else place_tolerance(field_, method.select, config.tolerance, PRIMARY_METRIC))
            search_seconds = time.perf_counter() - start
            target = reference_tolerance(reference, config.tolerance)
            row = _row(name, field_, method, "tolerance", config.tolerance, placement.indices,
                       method.seconds + search_seconds, search_seconds, target.mean_error)
            row.reference_probes = int(target.indices.shape[0])
            row.probes_ratio = row.probes / row.reference_probes
            rows.append(row)
        if log is not None:
            log(f"{name}: {method.name} done ({method.seconds:.3f} s to rank)")
    return CaptureResult(name=name, points=field_.point_count, rows=rows, reference_curve=reference.error_curve)


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        number = float(value)
        if np.isnan(number):
            return "nan"
        if np.isinf(number):
            return "inf" if number > 0 else "-inf"
        return format(number, ".6g")  # '.' decimals, no grouping: culture-invariant
    text = str(value)
    return '"' + text.replace('"', '""') + '"' if any(c in text for c in ',"\n') else text


def rows_csv(rows: Sequence[BenchRow]) -> str:
    lines = [",".join(CSV_COLUMNS)]
    for row in rows:
        values = asdict(row)
        lines.append(",".join(_cell(values[column]) for column in CSV_COLUMNS))
    return "\n".join(lines) + "\n"
