"""The training loop: seeded batches of cropped clouds, balanced loss, validation per epoch,
early stopping on a validation metric, best-weights checkpoints and tqdm progress."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

import keras
import tensorflow as tf

from ..errors import UserError
from .batches import Batch, BatchSampler
from .config import TrainConfig
from .data import Cloud, Normalisation, Split, normalisation_from, positive_weight
from .determinism import configure_determinism
from .losses import make_loss
from .metrics import DEFAULT_METRICS, CaptureMetric, evaluate_metrics, monitor_direction
from .model import PointNet


@dataclass
class TrainResult:
    model: PointNet
    config: TrainConfig
    split: Split
    normalisation: Normalisation
    positive_weight: float
    history: list[dict[str, Any]]
    best_epoch: int  # 1-based
    epochs_run: int
    stopped_early: bool
    validation: dict[str, Any]  # evaluate_metrics() at the best epoch
    seconds: float
    notes: list[str] = field(default_factory=list)


ImprovementCallback = Callable[[TrainResult], None]


class Trainer:
    """Model, optimiser, loss and a compiled train step; one trace serves every batch shape."""

    def __init__(self, config: TrainConfig, normalisation: Normalisation, positive_weight_value: float):
        self.config = config
        feature_count = int(normalisation.mean.shape[0])
        self.model = PointNet(config.model, normalisation.mean, normalisation.std, seed=config.seed)
        self.optimizer = keras.optimizers.Adam(learning_rate=config.learning_rate)
        self.optimizer.build(self.model.trainable_variables)
        self.loss_function = make_loss(config.loss, positive_weight_value, config.focal_gamma)
        cloud_spec = tf.TensorSpec((None, None, feature_count), tf.float32)
        point_spec = tf.TensorSpec((None, None), tf.float32)
        self._step = tf.function(self._train_step, input_signature=(cloud_spec, point_spec, point_spec))
        self._infer = tf.function(lambda features: self.model(features, training=False), input_signature=(cloud_spec,))

    def _train_step(self, features: Any, labels: Any, mask: Any) -> Any:
        with tf.GradientTape() as tape:
            logits = self.model.logits(features, mask, training=True)
            loss = self.loss_function(labels, logits, mask)
        variables = self.model.trainable_variables
        self.optimizer.apply_gradients(zip(tape.gradient(loss, variables), variables))
        return loss

    def train_step(self, batch: Batch) -> float:
        return float(self._step(batch.features, batch.labels, batch.mask))

    def predict(self, clouds: Sequence[Cloud]) -> list[np.ndarray]:
        """Importance of every point; each capture scored whole, as one cloud (as in Unity)."""
        return [self._infer(cloud.features[None]).numpy()[0] for cloud in clouds]

    def weights(self) -> list[np.ndarray]:
        return [w.numpy() for w in self.model.weights]


def _improved(value: float, best: float | None, higher_is_better: bool, min_delta: float) -> bool:
    if math.isnan(value):
        return False
    if best is None or math.isnan(best):
        return True
    return value > best + min_delta if higher_is_better else value < best - min_delta


def _summary(metrics: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in metrics.items() if k != "per_capture"}


def _stop_if_diverged(losses: Sequence[float], epoch: int, config: TrainConfig) -> None:
    """A non-finite loss means the weights are lost (NaN spreads through every later step): stop and say why."""
    if not np.all(np.isfinite(losses)):
        raise UserError(f"training diverged in epoch {epoch} (the loss became {losses[-1]}): lower the learning "
                        f"rate, now {config.learning_rate:g} (e.g. \"learning_rate\": {config.learning_rate / 10:g} "
                        "in the --config file)")


def fit(split: Split, config: TrainConfig, metrics: Sequence[CaptureMetric] = DEFAULT_METRICS,
        on_improvement: ImprovementCallback | None = None, progress: bool = True) -> TrainResult:
    """Trains on `split.train`, validates on `split.validation` every epoch, restores the best weights.

    `on_improvement(result so far)` runs whenever the monitored metric improves, while the model
    holds the new best weights (checkpointing).
    """
    from tqdm import tqdm

    config = config.validated()
    higher_is_better = monitor_direction(config.monitor, metrics)
    notes = configure_determinism(config.seed, config.threads)
    started = time.perf_counter()
    normalisation = normalisation_from(split.train)
    pos_weight = positive_weight(split.train)
    trainer = Trainer(config, normalisation, pos_weight)
    sampler = BatchSampler(split.train, config, config.seed)

    history: list[dict[str, Any]] = []

    def result(best: int, validation: dict[str, Any], stopped_early: bool) -> TrainResult:
        return TrainResult(
            model=trainer.model, config=config, split=split, normalisation=normalisation,
            positive_weight=pos_weight, history=list(history), best_epoch=best, epochs_run=len(history),
            stopped_early=stopped_early, validation=validation, seconds=time.perf_counter() - started,
            notes=notes,
        )

    best_value: float | None = None
    best_weights: list[np.ndarray] | None = None
    best_validation: dict[str, Any] = {}
    best_epoch = 0
    epochs_without_improvement = 0
    bar = tqdm(total=config.epochs * config.steps_per_epoch, unit="step", desc="train", disable=not progress,
               dynamic_ncols=True, leave=True)
    try:
        for epoch in range(1, config.epochs + 1):
            losses = []
            for _ in range(config.steps_per_epoch):
                losses.append(trainer.train_step(sampler.next_batch()))
                bar.update(1)
            _stop_if_diverged(losses, epoch, config)
            validation = evaluate_metrics(split.validation, trainer.predict(split.validation), metrics)
            value = float(validation[config.monitor])
            improved = _improved(value, best_value, higher_is_better, config.min_delta) or best_weights is None
            record = {"epoch": epoch, "loss": float(np.mean(losses)), **_summary(validation), "improved": improved}
            history.append(record)
            if improved:
                best_value, best_weights, best_validation, best_epoch = value, trainer.weights(), validation, epoch
                epochs_without_improvement = 0
                if on_improvement is not None:
                    on_improvement(result(epoch, validation, stopped_early=False))
            else:
                epochs_without_improvement += 1
            bar.set_postfix(epoch=epoch, loss=f"{record['loss']:.4f}", **{config.monitor: f"{value:.4f}"},
                            best=f"{best_value:.4f}@{best_epoch}")
            if epochs_without_improvement >= config.patience:
                break
    finally:
        bar.close()
    assert best_weights is not None  # epochs >= 1 and the first epoch always counts as an improvement
    trainer.model.set_weights(best_weights)
    return result(best_epoch, best_validation, stopped_early=len(history) < config.epochs)
