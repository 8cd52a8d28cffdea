"""Non-learned placements the network has to beat (quality.md §5).

- uniform: a lattice subsample (every s-th point per axis, from the grid's lowest id), the stride s
  whose count is closest to K (ties: the smaller stride), then trimmed or filled to exactly K by
  taking points evenly spaced in grid order: trimming keeps lattice points at positions
  floor((i + 1/2) M / K), filling adds non-lattice points at positions floor((i + 1/2) R / (K - M)).
- random: a seeded permutation (numpy default_rng(seed)).
- heuristic (spread probes out, denser where the light bends): the grid's convex-hull corners
  first (a tetrahedralisation needs its hull), then importance-weighted farthest-point sampling:
  repeatedly the point maximising d(p) * w(p), d = distance to the nearest chosen point,
  w = (c(p)/median(c) + 0.3)^0.25 with c the largest local interpolation error (max over
  k in {1, 2, 4} of features.md's curvature_k: the relative error of linearly interpolating a point
  from its two neighbours k cells away; computed fresh from the SH with the metric's directions).
  Ties go to the lower index. The sampling loop is lpnn.core.spread.farthest_point_ranking, the one
  behind the spread ranking of LPNN scores (same rule, hull corners instead of D14 extremes as seeds,
  curvature instead of scores as weights). The constants were chosen on synthetic rooms (seeds 3-7, 10-30 %
  budgets): ranking by curvature alone clusters the probes and is worse than random; the weighted
  sampling is ~25 % better than the uniform lattice, about as good as pure farthest-point sampling.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ...core.features import NEIGHBOUR_SCALES, lighting_features
from ...core.grid import EvaluationGrid
from ...core.selection import ensure_tetrahedron
from ...core.spread import farthest_point_ranking

CURVATURE_COLUMNS = (12, 13, 14)  # curvature_1, curvature_2, curvature_4 in lighting_features
DEFAULT_SEED = 0
HEURISTIC_FLOOR = 0.3  # weight floor, in units of the median curvature
HEURISTIC_EXPONENT = 0.25  # how strongly curvature pulls probes together


def _evenly_spaced(count: int, available: int) -> np.ndarray:
    """`count` positions in [0, available), evenly spread, deterministic."""
    return np.floor((np.arange(count) + 0.5) * available / count).astype(np.int64)


def lattice_mask(ids: np.ndarray, stride: int) -> np.ndarray:
    """Points whose id is a multiple of `stride` away from the grid's lowest id on every axis."""
    offset = ids.astype(np.int64) - ids.astype(np.int64).min(axis=0)
    return np.all(offset % stride == 0, axis=1)


def uniform_selection(ids: np.ndarray, count: int) -> np.ndarray:
    """Exactly `count` point indices (sorted) of a near-uniform lattice subsample."""
    n = ids.shape[0]
    if not 1 <= count <= n:
        raise ValueError(f"uniform subsample: count {count} must be in [1, {n}]")
    span = int(np.max(np.ptp(ids.astype(np.int64), axis=0))) + 1
    best_mask, best_gap = None, None
    for stride in range(1, span + 1):  # a handful of strides: their counts fall like 1/s^3
        mask = lattice_mask(ids, stride)
        gap = abs(int(mask.sum()) - count)
        if best_gap is None or gap < best_gap:
            best_mask, best_gap = mask, gap
        if mask.sum() < count:
            break
    assert best_mask is not None
    lattice = np.flatnonzero(best_mask)
    if lattice.shape[0] >= count:
        return lattice[_evenly_spaced(count, lattice.shape[0])]
    rest = np.flatnonzero(~best_mask)
    return np.sort(np.concatenate([lattice, rest[_evenly_spaced(count - lattice.shape[0], rest.shape[0])]]))


def uniform_selector(grid: EvaluationGrid):
    """count -> the uniform subsample with the tetrahedron guarantee (grid order completes a flat one)."""
    grid_order = np.arange(grid.point_count, dtype=np.int64)

    def select(count: int) -> np.ndarray:
        return ensure_tetrahedron(grid, grid_order, uniform_selection(grid.ids, count))[0]

    return select


def random_ranking(point_count: int, seed: int = DEFAULT_SEED) -> np.ndarray:
    return np.random.default_rng(seed).permutation(point_count).astype(np.int64)


def hull_corners(positions: np.ndarray) -> np.ndarray:
    """Indices of the grid's convex-hull vertices (none for a flat grid)."""
    try:
        return np.sort(ConvexHull(np.asarray(positions, dtype=np.float64)).vertices).astype(np.int64)
    except (QhullError, ValueError):
        return np.zeros(0, dtype=np.int64)


def curvature_scores(grid: EvaluationGrid, sh: np.ndarray, scale: float) -> np.ndarray:
    """Largest multi-scale interpolation error per point (curvature_1, _2, _4 of features.md)."""
    assert len(NEIGHBOUR_SCALES) == len(CURVATURE_COLUMNS)
    return lighting_features(grid, sh, scale)[:, list(CURVATURE_COLUMNS)].max(axis=1)


def heuristic_ranking(grid: EvaluationGrid, sh: np.ndarray, scale: float) -> np.ndarray:
    """Hull corners, then curvature-weighted farthest-point sampling (see the module text)."""
    curvature = curvature_scores(grid, sh, scale)
    positive = curvature[curvature > 0.0]
    typical = float(np.median(positive)) if positive.shape[0] else 1.0
    weights = (curvature / typical + HEURISTIC_FLOOR) ** HEURISTIC_EXPONENT
    return farthest_point_ranking(grid.positions, weights, hull_corners(grid.positions))
