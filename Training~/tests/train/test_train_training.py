"""Training respects the data: held-out captures are learned, runs are reproducible per seed,
the best weights are what is checkpointed, BatchNorm statistics settle, losses ignore padding."""

from __future__ import annotations

import json

import numpy as np
import pytest
import tensorflow as tf

from lpnn.train.checkpoint import load_checkpoint
from lpnn.train.config import config_from_dict
from lpnn.train.data import load_split
from lpnn.train.diagnostics import batchnorm_report, is_settled
from lpnn.train.losses import focal, weighted_bce
from lpnn.train.metrics import roc_auc
from lpnn.train.onnx_scoring import OnnxScorer
from lpnn.train.trainer import fit
from lpnn.core.capture_file import read_capture

from train_support import TINY_CONFIG, TrainedModel


def test_held_out_captures_are_learned(trained: TrainedModel) -> None:
    card = json.loads(trained.card.read_text(encoding="utf-8"))
    held_out = card["training"]["held_out"]
    assert held_out and not set(held_out) & set(card["training"]["captures"])
    assert card["metrics"]["validation"]["roc_auc"] > 0.9
    scorer = OnnxScorer(trained.model)
    for name in held_out:  # independent of the trainer's own bookkeeping: rescore the exported model
        capture = read_capture(trained.dataset / name)
        assert roc_auc(capture.labels, scorer.score(capture.features)) > 0.9, name


def test_best_epoch_is_the_checkpointed_one(trained: TrainedModel) -> None:
    card = json.loads(trained.card.read_text(encoding="utf-8"))
    history = card["training"]["history"]
    monitor = card["metrics"]["validation"]["monitor"]
    best = max(history, key=lambda record: record[monitor])
    assert card["training"]["best_epoch"] == best["epoch"]
    assert card["metrics"]["validation"][monitor] == best[monitor]
    model, meta = load_checkpoint(trained.checkpoint)
    assert meta["training"]["best_epoch"] == best["epoch"]
    capture = read_capture(trained.dataset / card["training"]["held_out"][0])
    np.testing.assert_allclose(np.asarray(model(capture.features[None]))[0],
                               OnnxScorer(trained.model).score(capture.features), atol=1e-5)


def test_batchnorm_running_statistics_settle(trained: TrainedModel) -> None:
    model, meta = load_checkpoint(trained.checkpoint)
    split = load_split([trained.dataset], [], seed=meta["seed"], val_fraction=0.2)
    report = batchnorm_report(model, split.train)
    assert report["max_mean_shift"] < 0.5  # in units of the true standard deviation
    assert report["max_abs_log_variance_ratio"] < 0.5
    assert is_settled(report)
    assert report["max_mean_shift"] == pytest.approx(meta["training"]["batchnorm_check"]["max_mean_shift"], rel=1e-4)
    # The check can fail: the untouched initial statistics (0, 1) are far from the data's.
    for norm in model.trunk_norm:
        norm.moving_mean.assign(np.zeros(norm.moving_mean.shape, np.float32))
        norm.moving_variance.assign(np.ones(norm.moving_variance.shape, np.float32))
    unsettled = batchnorm_report(model, split.train)
    assert max(unsettled["max_mean_shift"], unsettled["max_abs_log_variance_ratio"]) > 1.0
    assert not is_settled(unsettled)


def test_same_seed_same_run_and_different_seed_different_weights(dataset_dir) -> None:
    def run(seed: int):
        config = config_from_dict({**TINY_CONFIG, "epochs": 2, "steps_per_epoch": 5, "seed": seed})
        split = load_split([dataset_dir], [], seed=0, val_fraction=0.2)  # same split: isolate the training seed
        result = fit(split, config, progress=False)
        return result.history, [w.numpy() for w in result.model.weights]

    history_a, weights_a = run(11)
    history_b, weights_b = run(11)
    _, weights_c = run(12)
    assert history_a == history_b  # losses and every validation metric, exactly
    assert all(np.array_equal(a, b) for a, b in zip(weights_a, weights_b))
    trainable_differs = [not np.array_equal(a, c) for a, c in zip(weights_a, weights_c) if a.ndim == 2]
    assert all(trainable_differs)


def test_losses_ignore_padding_and_balance_classes() -> None:
    labels = tf.constant([[1.0, 0.0, 0.0, 1.0]])
    logits = tf.constant([[2.0, -1.0, 0.5, 9.0]])
    mask = tf.constant([[1.0, 1.0, 1.0, 0.0]])  # the last point is padding
    bce = tf.nn.sigmoid_cross_entropy_with_logits(labels=labels, logits=logits).numpy()[0]
    weight = 2.0
    expected = (weight * bce[0] + bce[1] + bce[2]) / (weight + 2.0)
    assert float(weighted_bce(weight)(labels, logits, mask)) == pytest.approx(expected, rel=1e-6)
    assert float(focal(weight, 0.0)(labels, logits, mask)) == pytest.approx(expected, rel=1e-6)
    assert float(focal(weight, 2.0)(labels, logits, mask)) < expected  # easy points are discounted


def test_a_diverging_run_stops_and_says_to_lower_the_learning_rate(dataset_dir) -> None:
    from lpnn.cli.errors import UserError

    config = config_from_dict({**TINY_CONFIG, "epochs": 2, "steps_per_epoch": 5, "learning_rate": 1e30})
    split = load_split([dataset_dir], [], seed=0, val_fraction=0.2)
    with pytest.raises(UserError, match=r"training diverged in epoch 1 .*lower the learning rate, now 1e\+30"):
        fit(split, config, progress=False)
