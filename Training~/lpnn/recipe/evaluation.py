"""Held-out evaluation of a recipe model (Documentation~/benchmarks.md "Default model").

For every held-out crop: ROC-AUC and PR-AUC of the scores against the reference labels, and the
benchmark of `lpnn.quality.bench.run` (every method at 1/5/10/20/30 % budgets and at a tolerance) with the
reference decimation the labelling stored (not recomputed). Aggregates over crops are geometric means
of per-crop ratios, so a crop with small errors weighs as much as one with large errors.
"""

from __future__ import annotations

import math
import statistics
from dataclasses import asdict
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

from ..core.capture_file import read_capture
from ..core.engine import Engine
from ..quality.placement.policy_rules import DEFAULT_BUDGETS, DEFAULT_TOLERANCE
from ..quality.bench.results import BenchConfig
from ..quality.bench.run import bench_capture
from ..quality.placement.methods import RECOMMENDED_REFINE
from ..quality.metric.metric import guarded_ratio
from ..train.metrics import pr_auc, roc_auc
from .labelling import stored_reference

BUDGETS = DEFAULT_BUDGETS  # the benchmark's own: every method at 1/5/10/20/30 %
METHODS = ("network", "guided", "guided-exact-refined", "network-topk", "insertion", "heuristic", "apv", "uniform", "random", "fast-reference")
# The ratios the summary reports; insertion is the best non-learned method (quality.md §5), the bar.
BASELINES = ("fast-reference", "uniform", "heuristic", "insertion")
STAGES = ("feature_seconds", "inference_seconds", "selection_seconds", "refine_seconds", "seconds")  # seconds: total


def bench_config() -> BenchConfig:
    return BenchConfig(budgets=BUDGETS, tolerance=DEFAULT_TOLERANCE, repeats=1, reference_repeats=1, workers=1,
                       refine=RECOMMENDED_REFINE)


def evaluate_crop(task: tuple[str, str]) -> dict[str, Any]:
    """One held-out crop (runs in a worker): ranking metrics and benchmark rows."""
    from ..train.onnx_scoring import OnnxScorer

    capture_path, model_path = task
    name = Path(capture_path).stem
    capture = read_capture(capture_path)
    if capture.labels is None:
        raise ValueError(f"{capture_path}: held-out crop without reference labels")
    scorer = OnnxScorer(model_path, threads=1)
    scores = scorer.score_capture(capture, name)
    result = bench_capture(name, capture, bench_config(), scorer, reference=stored_reference(capture))
    return {"name": name, "points": capture.point_count,
            "roc_auc": roc_auc(capture.labels, scores), "pr_auc": pr_auc(capture.labels, scores),
            "rows": [asdict(row) for row in result.rows],
            "failures": [asdict(failure) for failure in result.failures]}  # a method that failed: reported


def evaluate_crops(capture_paths: Sequence[Path], model_path: Path, engine: Engine,
                   progress: Callable[[Iterable, int], Iterable] = lambda items, total: items) -> list[dict[str, Any]]:
    """Every crop, sorted by name, each on a worker of `engine` (core/engine.py); stops at the first crop that fails."""
    tasks = [(str(path), str(model_path)) for path in capture_paths]
    results = [done.value() for done in progress(engine.unordered(evaluate_crop, tasks), len(tasks))]
    return sorted(results, key=lambda crop: crop["name"])


# ------------------------------------------------------------------------------------------ summary

def geometric_mean(values: Iterable[float]) -> tuple[float, int]:
    """(geometric mean of the finite positive values, how many were left out); NaN if none is usable.
    The left-out ratios are the worst cases (a reference error of 0, a failed placement): every
    report prints their count beside the mean."""
    given = [float(v) for v in values]
    usable = [v for v in given if math.isfinite(v) and v > 0]
    if not usable:
        return math.nan, len(given)
    return math.exp(sum(math.log(v) for v in usable) / len(usable)), len(given) - len(usable)


def _rows_by_key(crops: Sequence[dict[str, Any]]) -> dict[tuple[str, str, float], dict[str, dict[str, Any]]]:
    """(method, policy, parameter) -> crop name -> row."""
    table: dict[tuple[str, str, float], dict[str, dict[str, Any]]] = {}
    for crop in crops:
        for row in crop["rows"]:
            table.setdefault((row["method"], row["policy"], float(row["parameter"])), {})[crop["name"]] = row
    return table


def method_summary(method: str, policy: str, parameter: float,
                   table: dict[tuple[str, str, float], dict[str, dict[str, Any]]]) -> dict[str, Any]:
    rows = table[(method, policy, parameter)]
    summary: dict[str, Any] = {"method": method, "policy": policy, "parameter": parameter, "crops": len(rows),
                               "mean_probes": statistics.fmean(r["probes"] for r in rows.values()),
                               "mean_error": statistics.fmean(r["mean_error"] for r in rows.values())}
    for baseline in BASELINES:
        others = table.get((baseline, policy, parameter), {})
        key = "error_vs_reference" if baseline == "fast-reference" else f"error_vs_{baseline}"
        ratio, left_out = geometric_mean(guarded_ratio(rows[name]["mean_error"], others[name]["mean_error"])
                                         for name in rows if name in others)
        summary[key] = ratio
        summary[f"{key}_left_out"] = left_out  # non-finite or zero ratios: shown beside the mean, even when 0
    if policy == "tolerance":
        summary["probes_vs_reference"], summary["probes_vs_reference_left_out"] = geometric_mean(
            math.nan if r["probes_ratio"] is None else r["probes_ratio"] for r in rows.values())
        summary["within_tolerance"] = sum(r["mean_error"] <= parameter for r in rows.values())
    for stage in STAGES:
        values = [r[stage] for r in rows.values() if r[stage] is not None and math.isfinite(r[stage])]
        if values:
            summary[f"median_{stage}"] = statistics.median(values)
    return summary


def summarize(crops: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """The figures the model card and benchmarks.md report."""
    if not crops:
        raise ValueError("no held-out crops to summarise")
    table = _rows_by_key(crops)
    policies = [("budget", b) for b in BUDGETS] + [("tolerance", DEFAULT_TOLERANCE)]
    methods = [method_summary(m, p, v, table) for m in METHODS for p, v in policies if (m, p, v) in table]
    roc = [c["roc_auc"] for c in crops if math.isfinite(c["roc_auc"])]
    pr = [c["pr_auc"] for c in crops if math.isfinite(c["pr_auc"])]
    return {
        "crops": len(crops),
        "points": int(sum(c["points"] for c in crops)),
        "median_points": statistics.median(c["points"] for c in crops),
        "roc_auc": statistics.fmean(roc) if roc else math.nan,
        "pr_auc": statistics.fmean(pr) if pr else math.nan,
        "budgets": list(BUDGETS),
        "tolerance": DEFAULT_TOLERANCE,
        "refine": RECOMMENDED_REFINE,
        "methods": methods,
        "failures": [failure for crop in crops for failure in crop.get("failures", [])],
    }


def find(summary: dict[str, Any], method: str, policy: str, parameter: float) -> dict[str, Any]:
    for entry in summary["methods"]:
        if entry["method"] == method and entry["policy"] == policy and math.isclose(entry["parameter"], parameter):
            return entry
    raise KeyError(f"no {method} {policy} {parameter:g} in the evaluation")


def goal_checks(summary: dict[str, Any]) -> dict[str, bool]:
    """The issue's goals at a 20 % budget, per LPNN tier (a tier the summary lacks, e.g. in an older card, has none)."""
    checks = {}
    for method in ("network", "guided", "guided-exact-refined"):
        try:
            entry = find(summary, method, "budget", 0.2)
        except KeyError:
            continue
        checks[f"{method}: error <= 1.15x reference"] = entry["error_vs_reference"] <= 1.15
        checks[f"{method}: error <= 0.85x uniform"] = entry["error_vs_uniform"] <= 0.85
        checks[f"{method}: error < heuristic"] = entry["error_vs_heuristic"] < 1.0
        if math.isfinite(entry.get("error_vs_insertion", math.nan)):  # cards before the insertion baseline lack it
            checks[f"{method}: error <= 0.8x insertion (best non-learned)"] = entry["error_vs_insertion"] <= 0.8
    return checks


