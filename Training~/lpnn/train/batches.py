"""Training batches: many bounded clouds per step, each a random crop + subsample of ONE capture.

A batch is `features (B, P, F)`, `labels (B, P)` and `mask (B, P)` (1 = real point, 0 = padding),
padded to the largest cloud in the batch. The model's pooling, BatchNorm statistics and the loss
all read the mask, so padding never influences a result.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .config import TrainConfig
from .data import Cloud

CROP_ATTEMPTS = 8  # crops smaller than min_points are redrawn this often, then the whole capture is used
POOL_BATCHES = 8  # batches drawn together and regrouped by cloud size


@dataclass(frozen=True)
class Batch:
    features: np.ndarray  # (B, P, F) float32, zero padded
    labels: np.ndarray  # (B, P) float32
    mask: np.ndarray  # (B, P) float32, 1 for real points
    sources: tuple[str, ...]  # capture name of every cloud

    @property
    def real_points(self) -> int:
        return int(self.mask.sum())


def random_crop(ids: np.ndarray, rng: np.random.Generator, min_fraction: float) -> np.ndarray:
    """Indices of the points inside a random axis-aligned box of lattice ids.

    Each box edge covers a uniform fraction in [min_fraction, 1] of the capture's id range on that axis.
    """
    low = ids.min(axis=0)
    span = ids.max(axis=0) - low + 1
    size = np.maximum(1, np.ceil(rng.uniform(min_fraction, 1.0, size=3) * span)).astype(np.int64)
    start = low + np.floor(rng.uniform(0.0, 1.0, size=3) * (span - size + 1)).astype(np.int64)
    inside = np.all((ids >= start) & (ids < start + size), axis=1)
    return np.flatnonzero(inside)


def sample_cloud_indices(cloud: Cloud, rng: np.random.Generator, config: TrainConfig) -> np.ndarray:
    """Point indices of one training cloud: a crop (or the whole capture), then a random subsample."""
    indices = np.arange(cloud.point_count)
    if rng.uniform() < config.crop_probability:
        for _ in range(CROP_ATTEMPTS):
            crop = random_crop(cloud.ids, rng, config.crop_min_fraction)
            if crop.size >= min(config.min_points, cloud.point_count):
                indices = crop
                break
    keep_fraction = rng.uniform(config.subsample_min_fraction, 1.0)
    count = int(round(keep_fraction * indices.size))
    count = min(indices.size, config.max_points, max(count, config.min_points))
    if count < indices.size:
        indices = np.sort(rng.choice(indices, size=count, replace=False))
    return indices


def pad_clouds(parts: Sequence[tuple[np.ndarray, np.ndarray]], sources: Sequence[str]) -> Batch:
    """Stacks (features, labels) pairs of different lengths into one zero-padded, masked batch."""
    longest = max(features.shape[0] for features, _ in parts)
    feature_count = parts[0][0].shape[1]
    features = np.zeros((len(parts), longest, feature_count), dtype=np.float32)
    labels = np.zeros((len(parts), longest), dtype=np.float32)
    mask = np.zeros((len(parts), longest), dtype=np.float32)
    for row, (cloud_features, cloud_labels) in enumerate(parts):
        n = cloud_features.shape[0]
        features[row, :n] = cloud_features
        labels[row, :n] = cloud_labels
        mask[row, :n] = 1.0
    return Batch(features=features, labels=labels, mask=mask, sources=tuple(sources))


class BatchSampler:
    """Endless, seeded stream of training batches; captures are drawn uniformly (one scene = one vote).

    Clouds are drawn `POOL_BATCHES` batches at a time, sorted by size and cut into batches of similar
    sizes (then the batches are shuffled): the clouds drawn are the same, but padding shrinks from
    ~50 % to a few percent, which nearly doubles the real points per second.
    """

    def __init__(self, clouds: Sequence[Cloud], config: TrainConfig, seed: int):
        if not clouds:
            raise ValueError("BatchSampler needs at least one cloud")
        self.clouds = list(clouds)
        self.config = config
        self.rng = np.random.default_rng([seed, 0xBA7C4])
        self._ready: list[Batch] = []

    def _draw_pool(self) -> list[Batch]:
        size = self.config.batch_clouds
        chosen = self.rng.integers(0, len(self.clouds), size=size * POOL_BATCHES)
        drawn = []
        for index in chosen:
            cloud = self.clouds[int(index)]
            points = sample_cloud_indices(cloud, self.rng, self.config)
            drawn.append((cloud.name, cloud.features[points], cloud.labels[points].astype(np.float32)))
        drawn.sort(key=lambda item: item[1].shape[0])  # stable: ties keep draw order
        batches = []
        for start in range(0, len(drawn), size):
            group = drawn[start:start + size]
            batches.append(pad_clouds([(f, l) for _, f, l in group], [name for name, _, _ in group]))
        return [batches[i] for i in self.rng.permutation(len(batches))]

    def next_batch(self) -> Batch:
        if not self._ready:
            self._ready = self._draw_pool()
        return self._ready.pop()
