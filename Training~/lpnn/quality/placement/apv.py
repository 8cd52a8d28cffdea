"""APV-style geometry-driven density: what Unity's Adaptive Probe Volumes do, as a ranking (quality.md §5).

    apv_ranking(grid, features, feature_names) -> (N,) int64 point indices, most important first

Unity's Adaptive Probe Volumes (HDRP/URP, `com.unity.render-pipelines.core`) place probes at the
corners of bricks whose size is the minimum probe spacing times a power of 3, and subdivide bricks
only where geometry is near: dense next to surfaces, sparse in open space, no lighting involved
(Unity manual, "Probe Volume settings and properties", Min/Max Distance Between Probes,
https://docs.unity3d.com/Packages/com.unity.render-pipelines.high-definition@14.0/manual/probevolumes-settings.html;
the subdivision loop: Unity-Technologies/Graphics, com.unity.render-pipelines.core/Editor/Lighting/
ProbeVolume/ProbePlacement.cs, SubdivideSubCell).

On our lattice: a point's level l(p) is the largest s <= APV_LEVELS with every id offset from the
grid's lowest id a multiple of 3^s (a corner of the bricks of size 3^s cells). A volume whose bricks
may shrink to 3^s cells within distance rho x 3^s cells of geometry holds p iff d(p) <= rho x 3^l(p),
d(p) the distance to the nearest surface in cells; so p enters as rho grows past d(p) / 3^l(p), and
every rho gives one nested set. The ranking: the grid's convex-hull corners first (APV's bricks
cover the whole volume; a tetrahedralisation needs its hull), then by that entry key, ties to the
coarser level, then the lower index. Points of level APV_LEVELS (the coarsest bricks) enter at once.

d(p) comes from the capture's `nearest_surface` feature (features.md: min hit distance / R over 26
rays, R = 4 cells; 1 when nothing is hit): d = 4 x nearest_surface cells, and "nothing within 4
cells" counts as the coarsest brick's distance, 3^APV_LEVELS cells.
"""

from __future__ import annotations

import numpy as np

from ...errors import InvalidInputError
from ...core.grid import EvaluationGrid
from .baselines import hull_corners

APV_LEVELS = 3  # brick sizes 1, 3, 9, 27 cells: APV's four subdivision levels between min and max spacing
RAY_REACH_CELLS = 4.0  # features.md: R = 4h
NEAREST_SURFACE = "nearest_surface"


class ApvError(InvalidInputError):
    """The APV-style baseline cannot run on this capture; the message says why and what to do."""


def brick_levels(ids: np.ndarray, levels: int = APV_LEVELS) -> np.ndarray:
    """(N,) the largest s <= levels with every id offset a multiple of 3^s."""
    offset = ids.astype(np.int64) - ids.astype(np.int64).min(axis=0)
    level = np.zeros(offset.shape[0], dtype=np.int64)
    for s in range(1, levels + 1):
        level[np.all(offset % (3 ** s) == 0, axis=1)] = s
    return level


def surface_distance_cells(features: np.ndarray, feature_names: list[str]) -> np.ndarray:
    """Distance to the nearest surface in cells (3^APV_LEVELS where no ray hit within R)."""
    if NEAREST_SURFACE not in feature_names:
        raise ApvError(f"the capture has no '{NEAREST_SURFACE}' feature (features: {', '.join(feature_names)}): "
                       "re-import it with the current schema to benchmark the APV-style baseline")
    nearest = np.asarray(features[:, feature_names.index(NEAREST_SURFACE)], dtype=np.float64)
    nearest = np.where(np.isfinite(nearest), nearest, 1.0)
    return np.where(nearest >= 1.0, float(3 ** APV_LEVELS), RAY_REACH_CELLS * np.clip(nearest, 0.0, 1.0))


def apv_ranking(grid: EvaluationGrid, features: np.ndarray, feature_names: list[str]) -> np.ndarray:
    """Hull corners, then the APV entry key d(p) / 3^l(p) (module text). (N,) int64."""
    level = brick_levels(grid.ids)
    key = surface_distance_cells(features, feature_names) / (3.0 ** level)
    key[level >= APV_LEVELS] = 0.0
    n = grid.point_count
    order = np.lexsort((np.arange(n), -level, key))
    corners = hull_corners(grid.positions)
    is_corner = np.zeros(n, dtype=bool)
    is_corner[corners] = True
    return np.concatenate([corners, order[~is_corner[order]]]).astype(np.int64)
