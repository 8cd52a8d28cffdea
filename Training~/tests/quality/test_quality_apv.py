"""APV-style geometry-driven density (quality/placement/apv.py)."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.apv import APV_LEVELS, ApvError, apv_ranking, brick_levels, surface_distance_cells
from lpnn.quality.placement.baselines import hull_corners

from quality_support import box_grid


def test_brick_levels_are_the_coarsest_brick_corner_each_point_is() -> None:
    ids = np.array([[5, 5, 5], [6, 5, 5], [8, 5, 5], [14, 14, 14], [32, 5, 5], [86, 5, 5], [8, 8, 5]])
    np.testing.assert_array_equal(brick_levels(ids), [3, 0, 1, 2, 3, 3, 1])  # offsets from (5, 5, 5)


def test_surface_distance_in_cells_and_the_far_value() -> None:
    names = ["a", "nearest_surface"]
    features = np.array([[0.0, 0.25], [0.0, 1.0], [0.0, np.nan], [0.0, 0.0]], dtype=np.float32)
    np.testing.assert_allclose(surface_distance_cells(features, names), [1.0, 27.0, 27.0, 0.0])
    with pytest.raises(ApvError, match="nearest_surface"):
        surface_distance_cells(features, ["a", "b"])


def test_apv_ranking_is_hull_first_then_coarse_bricks_then_finer_near_geometry() -> None:
    ids = box_grid(10, 10, 4).astype(np.int32)
    grid = EvaluationGrid(cell_size=1.0, ids=ids)
    n = grid.point_count
    nearest = np.ones(n, dtype=np.float32)  # nothing within 4 cells ...
    near_wall = ids[:, 0] <= 1
    nearest[near_wall] = 0.1  # ... except next to the wall x = 0
    features = np.stack([np.zeros(n, dtype=np.float32), nearest], axis=1)
    ranking = apv_ranking(grid, features, ["x", "nearest_surface"])
    np.testing.assert_array_equal(np.sort(ranking), np.arange(n))
    corners = hull_corners(grid.positions)
    np.testing.assert_array_equal(ranking[:corners.shape[0]], corners)
    position = np.empty(n, dtype=np.int64)
    position[ranking] = np.arange(n)
    level = brick_levels(ids)
    rest = ~np.isin(np.arange(n), corners)
    # Far from geometry a finer brick corner never comes before a coarser one.
    far = rest & ~near_wall
    for coarse in range(1, APV_LEVELS + 1):
        if np.any(far & (level == coarse)) and np.any(far & (level < coarse)):
            assert position[far & (level == coarse)].max() < position[far & (level < coarse)].min()
    # Near the wall even the finest points come before the far fine ones.
    assert position[rest & near_wall & (level == 0)].max() < position[far & (level == 0)].min()
