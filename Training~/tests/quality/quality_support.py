"""Helpers of the quality tests (imported by the tests; fixtures live in conftest.py)."""

from __future__ import annotations

import numpy as np

from lpnn.core import sh as shmath
from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AnalyticScene, AxisBox
from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.core.grid_box import Box
from lpnn.core.grid_builder import build_grid
from lpnn.quality.metric.metric import ReferenceField

SMALL_ROOM = (1.5, 1.25, 1.25)  # 48 grid points at cell 0.5: the faithful decimation takes ~2 s
MEDIUM_ROOM = (4.0, 2.5, 3.0)  # ~600 points at cell 0.4
# two_rooms' lattice x = -4, -3.5, ..., 4 (cell 0.5): the wall lies between x = 0 and x = 0.5, so no point is inside it.
WALL_FROM, WALL_TO = 0.1, 0.4
WALLED = AnalyticBoxRaycaster(obstacles=(AxisBox(min=[WALL_FROM, -10.0, -10.0], max=[WALL_TO, 10.0, 10.0]),))
OPEN = AnalyticBoxRaycaster()


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


def two_rooms() -> tuple[ReferenceField, EvaluationGrid]:
    """A warm room (x < the wall WALLED) and a cool one half as bright, each varying smoothly (612 points): a
    tetrahedron across the wall blends the two, so a leak is an error, yet one small enough that today's default keeps
    some leaks at tau = 0.05."""
    grid = build_grid((Box.axis_aligned(np.array([-4.0, 0.0, 0.0]), np.array([4.0, 2.5, 2.5])),), 0.5, 100_000)
    positions = grid.positions.astype(np.float64)
    lit = positions[:, 0] < WALL_FROM
    x, z = positions[:, 0], positions[:, 2]
    bright = shmath.ambient(np.array([1.0, 0.9, 0.7]))[None, :] * (1.0 + 0.3 * np.sin(x) * np.cos(z))[:, None]
    dim = shmath.ambient(np.array([0.35, 0.4, 0.5]))[None, :] * (1.0 + 0.2 * np.cos(x) * np.sin(z))[:, None]
    sh = np.where(lit[:, None], bright, dim)
    return ReferenceField.from_sh(positions, sh), grid
