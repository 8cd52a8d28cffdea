"""The network: masked pooling and BatchNorm ignore padding, point-order equivariance, the
normalisation inside the graph, output shape, and the multiply-add count."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.train.config import ModelConfig
from lpnn.train.model import PointNet, multiply_adds_per_point

F = 5
SMALL_MODEL = ModelConfig(trunk=(8, 16), head=(8,), dropout=0.0)  # frozen: safe as a default


def make_model(config: ModelConfig = SMALL_MODEL,
               mean: np.ndarray | None = None, std: np.ndarray | None = None) -> PointNet:
    mean = np.zeros(F, np.float32) if mean is None else mean
    std = np.ones(F, np.float32) if std is None else std
    return PointNet(config, mean, std, seed=7)


def test_output_is_one_probability_per_point() -> None:
    model = make_model()
    features = np.random.default_rng(0).normal(size=(3, 11, F)).astype(np.float32)
    scores = np.asarray(model(features))
    assert scores.shape == (3, 11)
    assert np.all((scores > 0) & (scores < 1))


def test_padding_never_reaches_pooling_or_batchnorm() -> None:
    model = make_model()
    rng = np.random.default_rng(1)
    short = rng.normal(size=(1, 6, F)).astype(np.float32)
    long = rng.normal(size=(1, 10, F)).astype(np.float32)
    padded = np.zeros((2, 10, F), np.float32)
    padded[0, :6] = short[0]
    padded[0, 6:] = 1e3  # garbage in the padding must not matter
    padded[1] = long[0]
    mask = np.zeros((2, 10), np.float32)
    mask[0, :6] = 1
    mask[1] = 1
    # Inference: each cloud scored alone equals its row of the padded, masked batch.
    batched = np.asarray(model.logits(padded, mask, training=False))
    np.testing.assert_allclose(batched[0, :6], np.asarray(model.logits(short))[0], atol=1e-5)
    np.testing.assert_allclose(batched[1], np.asarray(model.logits(long))[0], atol=1e-5)
    # Training mode: BatchNorm batch statistics come from the real points only.
    together = np.concatenate([short[0], long[0]])[None]
    np.testing.assert_allclose(
        np.asarray(model.trunk_activations(padded, mask, training=True)[-1])[mask > 0],
        np.asarray(model.trunk_activations(together, None, training=True)[-1])[0], atol=1e-4)


def test_scores_follow_the_points_when_shuffled() -> None:
    model = make_model()
    features = np.random.default_rng(2).normal(size=(1, 50, F)).astype(np.float32)
    order = np.random.default_rng(3).permutation(50)
    np.testing.assert_allclose(np.asarray(model(features[:, order]))[0], np.asarray(model(features))[0][order], atol=1e-6)


def test_normalisation_is_part_of_the_graph() -> None:
    mean = np.array([1.0, -2.0, 0.5, 3.0, 0.0], np.float32)
    std = np.array([2.0, 0.5, 1.0, 4.0, 1.0], np.float32)
    raw = make_model(mean=mean, std=std)
    plain = make_model()
    trainable = [w for w in raw.weights if not w.path.startswith("standardize")]
    for target, source in zip([w for w in plain.weights if not w.path.startswith("standardize")], trainable):
        target.assign(source.numpy())
    features = np.random.default_rng(4).normal(size=(1, 20, F)).astype(np.float32) * std + mean
    np.testing.assert_allclose(np.asarray(raw(features)), np.asarray(plain((features - mean) / std)), atol=1e-5)


def test_bad_normalisation_is_refused() -> None:
    with pytest.raises(ValueError, match="std"):
        make_model(std=np.array([1, 0, 1, 1, 1], np.float32))


def test_multiply_adds_of_the_default_network() -> None:
    # normalisation 19; trunk 19*32+32, 32*64+64, 64*64+64; head (3*64)*64, 64*32; output 32
    expected = 19 + (608 + 32) + (2048 + 64) + (4096 + 64) + 192 * 64 + 64 * 32 + 32
    assert multiply_adds_per_point(ModelConfig(), 19) == expected == 21_299


def test_conv1d_and_dense_pointwise_layers_compute_the_same_function() -> None:
    dense = make_model()
    conv = make_model(ModelConfig(trunk=(8, 16), head=(8,), dropout=0.0, pointwise="conv1d"))
    for target, source in zip(conv.weights, dense.weights):
        target.assign(source.numpy().reshape(tuple(target.shape)))
    features = np.random.default_rng(5).normal(size=(2, 9, F)).astype(np.float32)
    np.testing.assert_allclose(np.asarray(conv(features)), np.asarray(dense(features)), atol=1e-6)
