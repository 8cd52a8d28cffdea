"""The benchmark's rows (bench/run.py's module text): the run's options, one row per method x policy, a failure,
a capture's result, and their CSV (culture-invariant: '.' decimals, no grouping)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any, Sequence

import numpy as np

from ..placement.baselines import DEFAULT_SEED
from ..placement.decimation.reference_faithful import FAITHFUL_MAX_CANDIDATES
from ..placement.lpnn_placement import RECOMMENDED_REFINE
from ..placement.policy_rules import DEFAULT_BUDGETS, DEFAULT_TOLERANCE, FULL_REFERENCE_LIMIT, REFINE_BENCH_LIMIT

CSV_COLUMNS = (
    "capture", "points", "method", "policy", "parameter", "probes", "pinned", "seconds", "feature_seconds",
    "inference_seconds", "selection_seconds", "refine_seconds", "mean_error", "p95_error", "smape_mean", "smape_p95",
    "reference_error", "error_ratio", "reference_probes", "probes_ratio", "leak_reference_error", "leak_error_ratio",
    "leak_reference_probes", "leak_probes_ratio", "yardstick", "in_use_error", "leaking",
)


@dataclass(frozen=True)
class BenchConfig:
    budgets: tuple[float, ...] = DEFAULT_BUDGETS
    tolerance: float | None = DEFAULT_TOLERANCE
    repeats: int = 3
    reference_repeats: int = 1
    seed: int = DEFAULT_SEED
    faithful_limit: int = FAITHFUL_MAX_CANDIDATES
    workers: int | None = None  # processes of the fast reference and of the blockwise reference's blocks (None: 1)
    refine: float = RECOMMENDED_REFINE  # guided-exact-refined's seed factor
    full_reference_limit: int = FULL_REFERENCE_LIMIT  # above: the blockwise reference is the yardstick
    refine_limit: int = REFINE_BENCH_LIMIT  # above: no guided-exact-refined rows (each decimates again, minutes per row)
    checkpoints: str | None = None  # folder keeping the blockwise reference's finished blocks (a rerun resumes)
    methods: frozenset[str] | None = None  # run only these methods (None: every one); the yardstick always runs
    reference_stop: float | None = None  # stop the fast reference above this mean error (None: down to 4 probes)
    yardstick: str = "auto"  # "auto": fast reference up to full_reference_limit, else blockwise; "none": no reference
    leaks: str = "avoid"  # the refined rows (insertion-refined, guided-refined): "avoid" leaks where the geometry is known (the default placement), "ignore"

    def wants(self, method: str) -> bool:
        """Whether `method` is to be run (run.py's module text)."""
        return self.methods is None or method in self.methods


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
    refine_seconds: float | None
    mean_error: float
    p95_error: float
    smape_mean: float
    smape_p95: float
    reference_error: float  # the yardstick at the same probe count (budget rows) / its tolerance set
    error_ratio: float
    reference_probes: int | None = None  # tolerance rows: the yardstick's smallest count within tau
    probes_ratio: float | None = None
    yardstick: str = "fast-reference"  # or "blockwise-reference" (run.py's module text)
    # The leak-aware rows (insertion-refined, guided-refined placed leak-aware) against the leak-aware reference too
    # (run.py's module text): its plain error at the same count / its answer at tau; NaN / empty for the other rows.
    leak_reference_error: float = math.nan
    leak_error_ratio: float = math.nan
    leak_reference_probes: int | None = None
    leak_probes_ratio: float | None = None
    in_use_error: float = math.nan  # mean error at the points in use (in-use.md); NaN when the capture cannot say
    leaking: float = math.nan  # share of the points in use that leak (leaks.md); NaN without the scene's geometry
    pinned: int = 0  # of `probes`, pinned (pins.md); the benchmark places without pins, Tools~/experiments/pins-bench.py with them


@dataclass(frozen=True)
class BenchFailure:
    """A method that failed on a capture (the run goes on; the CLI reports these and exits non-zero)."""

    capture: str
    method: str
    reason: str


@dataclass
class CaptureResult:
    name: str
    points: int
    rows: list[BenchRow]
    reference_curve: np.ndarray  # the yardstick's mean error by probe count (NaN where not evaluated)
    yardstick: str = "fast-reference"
    extra: dict[str, Any] = field(default_factory=dict)
    failures: list[BenchFailure] = field(default_factory=list)


def failure_reason(error: BaseException) -> str:
    """One line for a failure report: the error's own message (our errors name the value and the fix)."""
    message = " ".join(str(error).split())
    return f"{type(error).__name__}: {message}" if message else type(error).__name__



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


def failures_csv(failures: Sequence[BenchFailure]) -> str:
    lines = ["capture,method,reason"]
    lines.extend(",".join(_cell(value) for value in (f.capture, f.method, f.reason)) for f in failures)
    return "\n".join(lines) + "\n"
