"""The trainer's yardsticks: the best single feature and a logistic regression, fitted on training captures."""

from __future__ import annotations

import numpy as np

from lpnn.cli.train_cmd import _yardsticks
from lpnn.train.baselines import baselines
from lpnn.train.data import Cloud

NAMES = ("a", "b", "c")


def _cloud(name: str, features: np.ndarray, labels: np.ndarray) -> Cloud:
    return Cloud(name=name, ids=np.zeros((labels.size, 3), dtype=np.int32), features=features.astype(np.float32),
                 labels=labels.astype(np.uint8), schema="test", feature_names=NAMES, label_source="test")


def _data(rng: np.random.Generator, count: int, rule) -> Cloud:
    features = rng.normal(size=(count, 3))
    return _cloud("c", features, rule(features))


def test_a_single_decisive_feature_is_found_with_its_sign() -> None:
    rng = np.random.default_rng(1)
    rule = lambda x: x[:, 1] < -0.5  # noqa: E731  lower b = needs a probe
    result = baselines([_data(rng, 4000, rule)], [_data(rng, 2000, rule)])
    assert (result.feature, result.feature_sign) == ("b", -1)
    assert result.feature_roc_auc > 0.99 and result.logistic_roc_auc > 0.99


def test_logistic_regression_beats_any_single_feature_on_a_combined_rule() -> None:
    rng = np.random.default_rng(2)
    rule = lambda x: x[:, 0] + x[:, 2] > 0.3  # noqa: E731
    result = baselines([_data(rng, 4000, rule)], [_data(rng, 2000, rule)])
    assert result.logistic_roc_auc > 0.99
    assert 0.6 < result.feature_roc_auc < 0.85


def test_noise_gives_chance_level_yardsticks_and_the_report_says_the_network_does_not_beat_them() -> None:
    rng = np.random.default_rng(3)
    rule = lambda x: rng.random(x.shape[0]) < 0.3  # noqa: E731
    result = baselines([_data(rng, 4000, rule)], [_data(rng, 4000, rule)])
    assert abs(result.feature_roc_auc - 0.5) < 0.05 and abs(result.logistic_roc_auc - 0.5) < 0.05
    line = _yardsticks(result.logistic_roc_auc + 0.005, result)  # no better than the regression, within the margin
    assert f"network {result.logistic_roc_auc + 0.005:.4f}" in line and "does not beat these simple rules" in line
    assert "does not beat" not in _yardsticks(0.9, result)
