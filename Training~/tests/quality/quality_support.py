"""Helpers of the quality tests (imported by the tests; fixtures live in conftest.py)."""

from __future__ import annotations

import numpy as np

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture import Capture

SMALL_ROOM = (1.5, 1.25, 1.25)  # 48 grid points at cell 0.5: the faithful decimation takes ~2 s
MEDIUM_ROOM = (4.0, 2.5, 3.0)  # ~600 points at cell 0.4


def room_capture(seed: int, room: tuple[float, float, float] = SMALL_ROOM, cell_size: float = 0.5) -> Capture:
    return AnalyticScene.random(seed, cell_size=cell_size, room_size=room).capture(name=f"room{seed}")


def box_grid(nx: int, ny: int, nz: int, spacing: float = 1.0) -> np.ndarray:
    """Lattice positions (N, 3) in grid order (x fastest)."""
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    return np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.float64) * spacing


def linear_sh(positions: np.ndarray, seed: int = 0) -> np.ndarray:
    """SH (N, 27) that are an affine function of position (exactly reproduced by tetrahedral blending)."""
    rng = np.random.default_rng(seed)
    base = rng.uniform(0.5, 1.0, 27)
    gradient = rng.normal(0.0, 0.1, (3, 27))
    return base + np.asarray(positions, dtype=np.float64) @ gradient
