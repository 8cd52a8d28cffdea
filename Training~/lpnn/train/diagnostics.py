"""BatchNorm check: do the running statistics match the statistics of the data they normalise?

For each trunk BatchNorm layer, the true mean and variance of its input over the training clouds
(inference mode, every capture weighted equally as the batch sampler draws them) are compared with
the layer's moving averages. A settled layer has mean shifts well below one standard deviation and
variance ratios near 1; the thesis' model (50 steps, momentum 0.99) kept ~60 % of its initial (0, 1).
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from .data import Cloud

VARIANCE_FLOOR = 1e-3  # the BatchNormalization epsilon: variances below it are noise
SETTLED_LIMIT = 0.5  # mean shift (in std) and |log variance ratio| of a settled layer stay below this


def is_settled(report: dict[str, Any]) -> bool:
    return report["max_mean_shift"] < SETTLED_LIMIT and report["max_abs_log_variance_ratio"] < SETTLED_LIMIT


def batchnorm_report(model: Any, clouds: Sequence[Cloud]) -> dict[str, Any]:
    """{"layers": [{layer, max_mean_shift, max_abs_log_variance_ratio}], and the maxima over layers}."""
    layer_count = len(model.trunk_norm)
    means = [[] for _ in range(layer_count)]
    squares = [[] for _ in range(layer_count)]
    for cloud in clouds:
        activations = model.trunk_activations(cloud.features[None], None, training=False)[:-1]
        for index, values in enumerate(activations):
            flat = np.asarray(values, dtype=np.float64).reshape(-1, values.shape[-1])
            means[index].append(flat.mean(axis=0))
            squares[index].append((flat ** 2).mean(axis=0))
    layers = []
    for index, norm in enumerate(model.trunk_norm):
        true_mean = np.mean(means[index], axis=0)
        true_variance = np.maximum(np.mean(squares[index], axis=0) - true_mean ** 2, 0.0)
        moving_mean = norm.moving_mean.numpy().astype(np.float64)
        moving_variance = norm.moving_variance.numpy().astype(np.float64)
        scale = np.sqrt(true_variance + VARIANCE_FLOOR)
        mean_shift = np.abs(moving_mean - true_mean) / scale
        log_ratio = np.abs(np.log((moving_variance + VARIANCE_FLOOR) / (true_variance + VARIANCE_FLOOR)))
        layers.append({
            "layer": norm.name,
            "max_mean_shift": float(mean_shift.max()),
            "max_abs_log_variance_ratio": float(log_ratio.max()),
        })
    return {
        "layers": layers,
        "max_mean_shift": max((l["max_mean_shift"] for l in layers), default=math.nan),
        "max_abs_log_variance_ratio": max((l["max_abs_log_variance_ratio"] for l in layers), default=math.nan),
    }
