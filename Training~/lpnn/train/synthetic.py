"""Synthetic labelled captures with a learnable rule, for tests, examples and the benchmark.

Every capture is its own scene: a box of lattice points whose `lpnn.features.v1` features are
random, shifted and scaled per scene, with label = (f3 + 0.5 f7 > threshold) on the raw values.
Feature 8 (`boundary`) is constant, to exercise the std = 0 guard of the input normalisation.
"""

from __future__ import annotations

import numpy as np

from ..core.capture import Capture
from ..core.schema import LPNN_V1

RULE_THRESHOLD = 1.4
CONSTANT_FEATURE = 8


def synthetic_capture(seed: int, shape: tuple[int, int, int] = (16, 12, 8), cell_size: float = 0.5,
                      label_source: str = "synthetic:f3+0.5*f7>1.4") -> Capture:
    """A labelled capture of prod(shape) points in grid order (k slowest, then j, then i)."""
    rng = np.random.default_rng([seed, 0x5C3E])
    nx, ny, nz = shape
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    ids = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.int32)
    count = ids.shape[0]
    feature_count = LPNN_V1.feature_count
    scene_shift = rng.normal(0.0, 0.3, size=feature_count)
    scene_scale = rng.uniform(0.8, 1.25, size=feature_count)
    features = (rng.normal(size=(count, feature_count)) * scene_scale + scene_shift).astype(np.float32)
    features[:, CONSTANT_FEATURE] = 0.0
    labels = (features[:, 3] + 0.5 * features[:, 7] > RULE_THRESHOLD).astype(np.uint8)
    return Capture(
        ids=ids,
        positions=(ids.astype(np.float32) * np.float32(cell_size)),
        sh=np.zeros((count, 27), dtype=np.float32),
        features=features,
        schema=LPNN_V1.id,
        feature_names=list(LPNN_V1.names),
        cell_size=cell_size,
        lighting_scale=1.0,
        labels=labels,
        label_source=label_source,
        source={"synthetic": True, "seed": seed},
    )
