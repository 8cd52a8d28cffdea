"""The PointNet-style importance network (Keras 3, TensorFlow backend).

raw features -> (x - mean) * (1/std)                       constants in the graph (model contract)
  -> trunk: per point [1x1 linear (no bias) -> BatchNorm -> ReLU] x len(trunk)
  -> global context: max and mean over the cloud's points (masked: padding is never pooled)
  -> per point concat [local, tile(global max), tile(global mean)]
  -> head: per point [1x1 linear -> ReLU -> Dropout] x len(head)
  -> 1x1 linear -> sigmoid -> squeeze: importance (batch, points)

A "1x1 linear" applied to (batch, points, channels) with weights shared over the points is a 1x1
Conv1D; `pointwise="dense"` builds it as a Dense layer (exports as MatMul, no layout transposes),
`pointwise="conv1d"` as a Conv1D (exports as Conv). Both compute the same function.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import keras
from keras import ops

from .config import ModelConfig

POOLED_STATISTICS = 2  # global max and global mean
MODEL_NAME = "pointnet"
SEEDS_PER_MODEL = 1000  # layer k of a model seeded s draws from seed s*1000 + k: no stream is shared
PADDING_FLOOR = -3.0e38  # below any activation: padded points never win the max


class Standardize(keras.layers.Layer):
    """(x - mean) * inv_std with frozen per-feature constants (exported as Sub and Mul nodes)."""

    def __init__(self, mean: np.ndarray, std: np.ndarray, **kwargs: Any):
        super().__init__(**kwargs)
        mean = np.asarray(mean, dtype=np.float32)
        std = np.asarray(std, dtype=np.float32)
        if mean.shape != std.shape or mean.ndim != 1:
            raise ValueError(f"mean {mean.shape} and std {std.shape} must be equal 1-D shapes")
        if not (np.all(np.isfinite(mean)) and np.all(np.isfinite(std)) and np.all(std > 0)):
            raise ValueError("normalisation mean must be finite and std finite and > 0")
        self.mean = self.add_weight(shape=mean.shape, initializer=keras.initializers.Constant(mean),
                                    trainable=False, name="mean")
        self.inv_std = self.add_weight(shape=std.shape, initializer=keras.initializers.Constant(1.0 / std),
                                       trainable=False, name="inv_std")

    def call(self, inputs):
        return (inputs - self.mean) * self.inv_std


def layer_seed(model_seed: int, layer: int) -> int:
    return model_seed * SEEDS_PER_MODEL + layer


def _pointwise(kind: str, width: int, seed: int, **kwargs: Any) -> keras.layers.Layer:
    initializer = keras.initializers.GlorotUniform(seed=seed)
    if kind == "conv1d":
        return keras.layers.Conv1D(width, 1, kernel_initializer=initializer, **kwargs)
    return keras.layers.Dense(width, kernel_initializer=initializer, **kwargs)


def global_context(local: Any, mask: Any | None) -> Any:
    """(B, 1, 2C): max and mean over the points; with a mask, over the real points only."""
    if mask is None:
        return ops.concatenate([ops.max(local, axis=1, keepdims=True), ops.mean(local, axis=1, keepdims=True)], axis=-1)
    weights = ops.expand_dims(mask, -1)
    highest = ops.max(ops.where(weights > 0, local, PADDING_FLOOR), axis=1, keepdims=True)
    count = ops.maximum(ops.sum(weights, axis=1, keepdims=True), 1.0)  # guard: an all-padding row
    average = ops.sum(local * weights, axis=1, keepdims=True) / count
    return ops.concatenate([highest, average], axis=-1)


class PointNet(keras.Model):
    """Scores every point of each cloud in a batch; `call` is the exported (mask-free) graph."""

    def __init__(self, config: ModelConfig, mean: np.ndarray, std: np.ndarray, seed: int):
        super().__init__(name=MODEL_NAME)
        self.config = config
        self.feature_count = int(np.asarray(mean).shape[0])
        self.standardize = Standardize(mean, std, name="standardize")
        self.trunk_linear = [
            _pointwise(config.pointwise, width, layer_seed(seed, index), use_bias=False, name=f"trunk_{index}")
            for index, width in enumerate(config.trunk)
        ]
        self.trunk_norm = [
            keras.layers.BatchNormalization(momentum=config.batchnorm_momentum, name=f"trunk_{index}_bn")
            for index in range(len(config.trunk))
        ]
        offset = len(config.trunk)
        self.head_linear = [
            _pointwise(config.pointwise, width, layer_seed(seed, offset + index), activation="relu", name=f"head_{index}")
            for index, width in enumerate(config.head)
        ]
        self.head_dropout = [
            keras.layers.Dropout(config.dropout, seed=layer_seed(seed, offset + len(config.head) + 1 + index),
                                 name=f"head_{index}_dropout")
            for index in range(len(config.head))
        ]
        self.output_linear = _pointwise(config.pointwise, 1, layer_seed(seed, offset + len(config.head)), name="importance")
        self(np.zeros((1, 2, self.feature_count), dtype=np.float32))  # create every weight now, in a fixed order

    def trunk_activations(self, features: Any, mask: Any | None = None, training: bool = False) -> list[Any]:
        """Pre-BatchNorm activations of every trunk layer, then the trunk output (last item)."""
        x = self.standardize(features)
        pre_norm = []
        for linear, norm in zip(self.trunk_linear, self.trunk_norm):
            x = linear(x)
            pre_norm.append(x)
            x = ops.relu(norm(x, training=training, mask=mask))
        return pre_norm + [x]

    def logits(self, features: Any, mask: Any | None = None, training: bool = False) -> Any:
        """(B, P) pre-sigmoid scores. `mask` (B, P): 1 = real point, 0 = padding (training batches)."""
        local = self.trunk_activations(features, mask, training)[-1]
        pooled = global_context(local, mask)
        tiled = ops.tile(pooled, [1, ops.shape(local)[1], 1])
        x = ops.concatenate([local, tiled], axis=-1)
        for linear, dropout in zip(self.head_linear, self.head_dropout):
            x = dropout(linear(x), training=training)
        return ops.squeeze(self.output_linear(x), axis=-1)

    def call(self, features: Any, training: bool = False) -> Any:
        return ops.sigmoid(self.logits(features, None, training))


def multiply_adds_per_point(config: ModelConfig, feature_count: int) -> int:
    """Multiply-adds per point of the per-point layers (pooling and tiling add no multiplications)."""
    total = feature_count  # normalisation
    width = feature_count
    for out in config.trunk:
        total += width * out + out  # linear + folded BatchNorm scale
        width = out
    width = width * (1 + POOLED_STATISTICS)
    for out in config.head:
        total += width * out
        width = out
    return total + width


def architecture_summary(model: PointNet) -> dict[str, Any]:
    config = model.config
    return {
        "type": "pointnet",
        "pointwise": config.pointwise,
        "trunk": list(config.trunk),
        "head": list(config.head),
        "pooling": ["max", "mean"],
        "global_context": "tiled and concatenated per point",
        "dropout": config.dropout,
        "batchnorm_momentum": config.batchnorm_momentum,
        "activation": "relu",
        "output": "sigmoid",
        "parameters": int(sum(int(np.prod(w.shape)) for w in model.trainable_weights)),
        "multiply_adds_per_point": multiply_adds_per_point(config, model.feature_count),
    }
