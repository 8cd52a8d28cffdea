"""ROC-AUC and PR-AUC against brute-force definitions, ties included; per-capture vs pooled; plugins."""

from __future__ import annotations

import math
import sys
import types

import numpy as np
import pytest

from lpnn.cli.errors import UserError
from lpnn.train.data import Cloud
from lpnn.train.metrics import (
    CaptureMetric, average_ranks, evaluate_metrics, load_metric_plugins, monitor_direction, pr_auc, roc_auc,
)


def brute_force_roc(labels: np.ndarray, scores: np.ndarray) -> float:
    positives = scores[labels == 1]
    negatives = scores[labels == 0]
    wins = (positives[:, None] > negatives[None, :]).sum() + 0.5 * (positives[:, None] == negatives[None, :]).sum()
    return wins / (positives.size * negatives.size)


def brute_force_ap(labels: np.ndarray, scores: np.ndarray) -> float:
    """Precision at each distinct threshold (score >= t), weighted by the recall it adds."""
    total, previous_recall = 0.0, 0.0
    for threshold in sorted(set(scores.tolist()), reverse=True):
        selected = scores >= threshold
        true_positives = labels[selected].sum()
        recall = true_positives / labels.sum()
        total += (recall - previous_recall) * true_positives / selected.sum()
        previous_recall = recall
    return total


def make_cloud(name: str, labels: np.ndarray) -> Cloud:
    n = labels.size
    return Cloud(name=name, ids=np.zeros((n, 3), np.int32), features=np.zeros((n, 1), np.float32),
                 labels=labels.astype(np.uint8), schema="s", feature_names=("f",), label_source="test")


@pytest.mark.parametrize("seed", range(6))
def test_roc_and_pr_match_brute_force_with_many_ties(seed: int) -> None:
    rng = np.random.default_rng(seed)
    labels = (rng.uniform(size=60) < 0.3).astype(np.uint8)
    labels[:2] = [0, 1]
    scores = rng.integers(0, 5, size=60).astype(np.float32)  # 5 distinct values: ties everywhere
    assert roc_auc(labels, scores) == pytest.approx(brute_force_roc(labels, scores), abs=1e-12)
    assert pr_auc(labels, scores) == pytest.approx(brute_force_ap(labels, scores), abs=1e-12)


def test_known_values() -> None:
    labels = np.array([1, 0, 1, 0])
    scores = np.array([0.9, 0.8, 0.7, 0.1])
    assert roc_auc(labels, scores) == pytest.approx(0.75)
    assert pr_auc(labels, scores) == pytest.approx(0.5 * 1.0 + 0.5 * 2.0 / 3.0)
    assert roc_auc(labels, -scores) == pytest.approx(0.25)
    assert roc_auc([0, 0, 1, 1], [0.1, 0.2, 0.3, 0.4]) == 1.0
    assert pr_auc([0, 0, 1, 1], [0.1, 0.2, 0.3, 0.4]) == 1.0


def test_all_tied_scores_are_chance_level() -> None:
    labels = np.array([1, 0, 0, 0, 1, 0, 0, 0])
    scores = np.full(8, 0.5)
    assert roc_auc(labels, scores) == 0.5
    assert pr_auc(labels, scores) == pytest.approx(0.25)  # precision of taking everything


def test_single_class_is_nan() -> None:
    assert math.isnan(roc_auc([0, 0, 0], [0.1, 0.2, 0.3]))
    assert math.isnan(roc_auc([1, 1], [0.1, 0.2]))
    assert math.isnan(pr_auc([0, 0, 0], [0.1, 0.2, 0.3]))


def test_average_ranks_share_ties() -> None:
    assert average_ranks(np.array([3.0, 1.0, 3.0, 2.0])).tolist() == [3.5, 1.0, 3.5, 2.0]


def test_pooled_differs_from_per_capture_when_scenes_are_offset() -> None:
    labels = np.array([0, 0, 1, 1])
    first, second = make_cloud("a", labels), make_cloud("b", labels)
    # Perfect ranking inside each capture, but capture b's scores are all higher than capture a's.
    result = evaluate_metrics([first, second], [np.array([0.1, 0.2, 0.3, 0.4]), np.array([0.5, 0.6, 0.7, 0.8])])
    assert result["per_capture"]["a"]["roc_auc"] == 1.0
    assert result["per_capture"]["b"]["roc_auc"] == 1.0
    assert result["roc_auc_mean"] == 1.0
    assert result["roc_auc"] < 1.0
    assert result["per_capture"]["b"]["positives"] == 2


def test_mean_skips_captures_without_both_classes() -> None:
    result = evaluate_metrics(
        [make_cloud("a", np.array([0, 1])), make_cloud("b", np.array([0, 0]))],
        [np.array([0.2, 0.9]), np.array([0.3, 0.4])],
    )
    assert math.isnan(result["per_capture"]["b"]["roc_auc"])
    assert result["roc_auc_mean"] == 1.0


def test_plugged_metric_is_reported_and_can_be_monitored(monkeypatch: pytest.MonkeyPatch) -> None:
    placement = CaptureMetric("placement_error_10pct", higher_is_better=False,
                              per_capture=lambda cloud, scores: float(np.mean(scores)))
    module = types.ModuleType("fake_quality_metrics")
    module.metrics = lambda: [placement]
    monkeypatch.setitem(sys.modules, "fake_quality_metrics", module)
    loaded = load_metric_plugins(["fake_quality_metrics:metrics"])
    assert loaded == [placement]
    result = evaluate_metrics([make_cloud("a", np.array([0, 1]))], [np.array([0.2, 0.6])], loaded)
    assert result["placement_error_10pct_mean"] == pytest.approx(0.4)
    assert "placement_error_10pct" not in result  # no pooled form
    assert monitor_direction("placement_error_10pct_mean", loaded) is False


def test_bad_monitor_and_plugin_specs_are_user_errors() -> None:
    with pytest.raises(UserError, match="roc_auc_mean"):
        monitor_direction("accuracy", [CaptureMetric("roc_auc", True, lambda c, s: 0.0, roc_auc)])
    with pytest.raises(UserError, match="module:attribute"):
        load_metric_plugins(["no_colon_here"])
    with pytest.raises(UserError, match="cannot load"):
        load_metric_plugins(["lpnn_no_such_module_xyz:metric"])


def test_the_example_in_the_spec_error_loads() -> None:
    with pytest.raises(UserError) as refused:
        load_metric_plugins(["no-colon"])
    example = str(refused.value).split("e.g. '")[1].rstrip("'")
    assert [metric.name for metric in load_metric_plugins([example])] == ["placement_error_20"]
