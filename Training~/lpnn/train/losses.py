"""Class-balanced per-point losses on logits, averaged over the real (unmasked) points only."""

from __future__ import annotations

from typing import Any, Callable

import tensorflow as tf

from ..errors import UserError

LossFunction = Callable[[Any, Any, Any], Any]


def _masked_mean(per_point: Any, weights: Any) -> Any:
    return tf.reduce_sum(per_point * weights) / tf.maximum(tf.reduce_sum(weights), 1e-12)


def weighted_bce(positive_weight: float) -> LossFunction:
    """BCE where each positive counts `positive_weight` (= negatives/positives): both classes weigh the same."""
    pos = tf.constant(positive_weight, tf.float32)

    def loss(labels: Any, logits: Any, mask: Any) -> Any:
        per_point = tf.nn.sigmoid_cross_entropy_with_logits(labels=labels, logits=logits)
        weights = mask * (1.0 + (pos - 1.0) * labels)
        return _masked_mean(per_point, weights)

    return loss


def focal(positive_weight: float, gamma: float) -> LossFunction:
    """Focal loss (Lin et al. 2017) with the same class balance: easy points count less."""
    pos = tf.constant(positive_weight, tf.float32)
    gamma_t = tf.constant(gamma, tf.float32)

    def loss(labels: Any, logits: Any, mask: Any) -> Any:
        per_point = tf.nn.sigmoid_cross_entropy_with_logits(labels=labels, logits=logits)
        probability = tf.sigmoid(logits)
        p_true = labels * probability + (1.0 - labels) * (1.0 - probability)
        modulated = tf.pow(1.0 - p_true, gamma_t) * per_point
        weights = mask * (1.0 + (pos - 1.0) * labels)
        return _masked_mean(modulated, weights)

    return loss


def make_loss(name: str, positive_weight: float, focal_gamma: float) -> LossFunction:
    if name == "weighted_bce":
        return weighted_bce(positive_weight)
    if name == "focal":
        return focal(positive_weight, focal_gamma)
    raise UserError(f"unknown loss {name!r}; use 'weighted_bce' or 'focal'")
