"""Ranking metrics per validation capture and pooled, plus a pluggable list of capture metrics.

ROC-AUC is the Mann-Whitney statistic on average ranks (ties count one half). PR-AUC is average
precision over distinct score thresholds (tied scores enter together, so ties are never ordered
arbitrarily). Both return NaN when a capture lacks one of the classes.

Other metrics (e.g. placement error at a fixed probe budget from `lpnn.quality`) plug in as
`CaptureMetric`s: a name, a direction and a function of (capture cloud, scores).
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import UserError

RankingFunction = Callable[[np.ndarray, np.ndarray], float]


def average_ranks(values: np.ndarray) -> np.ndarray:
    """1-based ranks; tied values share the mean of their ranks."""
    order = np.argsort(values, kind="stable")
    sorted_values = values[order]
    starts = np.flatnonzero(np.r_[True, sorted_values[1:] != sorted_values[:-1]])
    ends = np.r_[starts[1:], sorted_values.size]
    mean_rank = (starts + ends + 1) / 2.0  # mean of ranks starts+1 .. ends
    ranks = np.empty(values.size, dtype=np.float64)
    ranks[order] = np.repeat(mean_rank, ends - starts)
    return ranks


def _binary(labels: np.ndarray, scores: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    labels = np.asarray(labels).reshape(-1).astype(bool)
    scores = np.asarray(scores, dtype=np.float64).reshape(-1)
    if labels.shape != scores.shape:
        raise ValueError(f"labels ({labels.size}) and scores ({scores.size}) differ in length")
    if not np.all(np.isfinite(scores)):
        raise ValueError("scores must be finite")
    return labels, scores


def roc_auc(labels: np.ndarray, scores: np.ndarray) -> float:
    """P(score of a random positive > score of a random negative), ties counted 1/2; NaN if one class."""
    labels, scores = _binary(labels, scores)
    positives = int(labels.sum())
    negatives = labels.size - positives
    if positives == 0 or negatives == 0:
        return math.nan
    rank_sum = float(average_ranks(scores)[labels].sum())
    return (rank_sum - positives * (positives + 1) / 2.0) / (positives * negatives)


def pr_auc(labels: np.ndarray, scores: np.ndarray) -> float:
    """Average precision: sum over distinct thresholds of (recall gain) x precision; NaN if no positive."""
    labels, scores = _binary(labels, scores)
    positives = int(labels.sum())
    if positives == 0 or positives == labels.size:
        return math.nan
    order = np.argsort(-scores, kind="stable")
    sorted_scores = scores[order]
    true_cumulative = np.cumsum(labels[order])
    # The last index of every group of tied scores: one threshold per distinct score.
    last_of_group = np.r_[np.flatnonzero(sorted_scores[1:] != sorted_scores[:-1]), labels.size - 1]
    true_positives = true_cumulative[last_of_group].astype(np.float64)
    precision = true_positives / (last_of_group + 1)
    recall_gain = np.diff(np.r_[0.0, true_positives]) / positives
    return float(np.sum(recall_gain * precision))


@dataclass(frozen=True)
class CaptureMetric:
    """A validation metric computed per capture. `pooled` (labels, scores) -> value, if it pools."""

    name: str
    higher_is_better: bool
    # (data.Cloud, scores (N,)) -> value or NaN; `cloud.capture` is the full Capture (positions, SH).
    per_capture: Callable[[Any, np.ndarray], float]
    pooled: RankingFunction | None = None


def _ranking_metric(name: str, function: RankingFunction) -> CaptureMetric:
    return CaptureMetric(name, True, lambda cloud, scores: function(cloud.labels, scores), function)


ROC_AUC = _ranking_metric("roc_auc", roc_auc)
PR_AUC = _ranking_metric("pr_auc", pr_auc)
DEFAULT_METRICS: tuple[CaptureMetric, ...] = (ROC_AUC, PR_AUC)


def _nan_mean(values: Sequence[float]) -> float:
    finite = [v for v in values if not math.isnan(v)]
    return float(np.mean(finite)) if finite else math.nan


def evaluate_metrics(clouds: Sequence[Any], scores: Sequence[np.ndarray],
                     metrics: Sequence[CaptureMetric] = DEFAULT_METRICS) -> dict[str, Any]:
    """{"per_capture": {name: {metric: value, points, positives}}, "<m>": pooled, "<m>_mean": mean}.

    `<m>_mean` averages the captures where the metric is defined (NaN values are skipped).
    """
    per_capture: dict[str, dict[str, float]] = {}
    for cloud, cloud_scores in zip(clouds, scores):
        values = {m.name: float(m.per_capture(cloud, cloud_scores)) for m in metrics}
        per_capture[cloud.name] = {**values, "points": cloud.point_count, "positives": cloud.positives}
    summary: dict[str, Any] = {}
    if clouds:
        all_labels = np.concatenate([c.labels for c in clouds])
        all_scores = np.concatenate([np.asarray(s).reshape(-1) for s in scores])
    for metric in metrics:
        if metric.pooled is not None and clouds:
            summary[metric.name] = float(metric.pooled(all_labels, all_scores))
        summary[f"{metric.name}_mean"] = _nan_mean([v[metric.name] for v in per_capture.values()])
    summary["per_capture"] = per_capture
    return summary


def monitor_direction(monitor: str, metrics: Sequence[CaptureMetric]) -> bool:
    """True when higher values of `monitor` are better; UserError for a key no metric produces."""
    for metric in metrics:
        keys = ([metric.name] if metric.pooled is not None else []) + [f"{metric.name}_mean"]
        if monitor in keys:
            return metric.higher_is_better
    known = sorted(k for m in metrics for k in ([m.name] if m.pooled is not None else []) + [f"{m.name}_mean"])
    raise UserError(f"monitor {monitor!r} is not a validation metric; choose one of {known}")


EXAMPLE_METRIC = "lpnn.train.placement_metric:PLACEMENT_ERROR_20"  # named in error messages: must load


def load_metric_plugins(specs: Sequence[str]) -> list[CaptureMetric]:
    """`module:attribute` specs naming a CaptureMetric, a list of them, or a no-argument factory of either."""
    loaded: list[CaptureMetric] = []
    for spec in specs:
        module_name, _, attribute = spec.partition(":")
        if not module_name or not attribute:
            raise UserError(f"metric {spec!r}: expected 'module:attribute', e.g. '{EXAMPLE_METRIC}'")
        try:
            target = getattr(importlib.import_module(module_name), attribute)
        except (ImportError, AttributeError) as exc:
            raise UserError(f"metric {spec!r}: cannot load: {exc}") from exc
        if callable(target) and not isinstance(target, CaptureMetric):
            target = target()
        items = [target] if isinstance(target, CaptureMetric) else list(target)
        for item in items:
            if not isinstance(item, CaptureMetric):
                raise UserError(f"metric {spec!r}: {item!r} is not a lpnn.train.metrics.CaptureMetric")
            loaded.append(item)
    return loaded
