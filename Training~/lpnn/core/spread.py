"""The spread ranking (selection.md "Spread ranking"): importance-weighted farthest-point sampling.

    spread_ranking(positions, scores) -> (N,) int64 point indices, most important first

1. Weights: s = score clipped to [1e-6, 1] (NaN -> 1e-6), m = median of s (mean of the two middle
   values for an even count), w = (s / m)^exponent (exponent 0.5: sqrt).
2. Seeds: for each D14 direction d (features.md order) the point maximising d.p, ties to the lower
   index; repeats dropped, first occurrence kept.
3. Then repeatedly the point maximising w(p) * D(p), D = distance to the nearest chosen point; ties
   to the lower index.

Arithmetic, fixed so that the C# port reproduces every tie (Tests/Data/spread_golden.json): positions
are the given float32 values widened to double; d.p = x*dx + y*dy + z*dz, left to right;
D = sqrt(dx*dx + dy*dy + dz*dz) of the double differences, left to right; the key is w * D.

Exact and fast (10^6 points in ~24 s on one core here): an exact lazy max-heap over the keys
(distances only shrink, so a stored key is an upper bound; an entry is taken only when it equals the
point's current key) and a static k-d tree carrying the largest current distance of each node.
Choosing a point updates distances only in the nodes that can change (the node's box is nearer to
the new point than the node's largest distance) — exact for any weights, unlike a ball of radius
"largest distance", which contains (w_max / w_min)^3 times too many points. The loop is compiled
(spread_kernel.py), the plan of the C# core's NearestChosenDistances.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InvalidInputError
from .features import D14
from .spread_kernel import extend_ranking, start_ranking, weighted_farthest_points

SCORE_FLOOR = 1e-6  # scores are clipped to [SCORE_FLOOR, 1] (NaN -> SCORE_FLOOR)
DEFAULT_EXPONENT = 0.5


class SpreadError(InvalidInputError):
    """The spread ranking's inputs are invalid; the message names the value and what to do."""


# ------------------------------------------------------------------------------------------ inputs

def _checked_points(positions: np.ndarray) -> np.ndarray:
    points = np.asarray(positions)
    if points.ndim != 2 or points.shape[1] != 3 or not np.issubdtype(points.dtype, np.floating):
        raise SpreadError(f"positions must be an (N, 3) float array (float32 grid positions), "
                          f"got {points.dtype} {list(points.shape)}")
    points = points.astype(np.float64)
    bad = np.flatnonzero(~np.all(np.isfinite(points), axis=1))
    if bad.shape[0]:
        raise SpreadError(f"position {int(bad[0])} = {points[bad[0]].tolist()} is not finite "
                          f"({bad.shape[0]:,} such rows): every coordinate must be a finite number")
    return np.ascontiguousarray(points)


def spread_weights(scores: np.ndarray, exponent: float = DEFAULT_EXPONENT) -> np.ndarray:
    """(N,) float64 weights w = (clip(s, 1e-6, 1) / median)^exponent; NaN scores count as 1e-6."""
    values = np.asarray(scores)
    if values.ndim != 1 or not (np.issubdtype(values.dtype, np.floating) or np.issubdtype(values.dtype, np.integer)):
        raise SpreadError(f"scores must be one number per point (shape (N,)), got {values.dtype} {list(values.shape)}")
    power = float(exponent)
    if not (math.isfinite(power) and power >= 0.0):
        raise SpreadError(f"exponent {exponent!r} must be a finite number >= 0 (0.5 by default; 0 = plain "
                          "farthest-point sampling)")
    clipped = values.astype(np.float64)
    clipped = np.where(np.isnan(clipped), SCORE_FLOOR, np.clip(clipped, SCORE_FLOOR, 1.0))
    if clipped.shape[0] == 0:
        return clipped
    middle = clipped.shape[0] // 2
    ordered = np.partition(clipped, [middle - 1, middle] if clipped.shape[0] % 2 == 0 else [middle])
    median = float(ordered[middle]) if clipped.shape[0] % 2 else (float(ordered[middle - 1]) + float(ordered[middle])) / 2.0
    ratio = clipped / median
    return np.sqrt(ratio) if power == 0.5 else ratio**power


def extreme_seeds(positions: np.ndarray) -> np.ndarray:
    """For each D14 direction, the point maximising d.p (ties: lower index); repeats dropped."""
    points = _checked_points(positions)
    if points.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    seeds = [int(np.argmax(x * d[0] + y * d[1] + z * d[2])) for d in D14]  # argmax: the lowest index of equals
    return np.asarray(list(dict.fromkeys(seeds)), dtype=np.int64)


# ------------------------------------------------------------------------------ the ranking itself

def spread_ranking(positions: np.ndarray, scores: np.ndarray, exponent: float = DEFAULT_EXPONENT) -> np.ndarray:
    """The spread ranking of selection.md: (N,) int64, every point once, most important first."""
    points = _checked_points(positions)
    weights = spread_weights(scores, exponent)
    if weights.shape[0] != points.shape[0]:
        raise SpreadError(f"{weights.shape[0]:,} scores for {points.shape[0]:,} positions: give one score per point")
    return farthest_point_ranking(points, weights, extreme_seeds(points))


class SpreadPrefix:
    """The spread ranking computed only as far as it is read: prefix(K) is spread_ranking(...)[:K],
    exactly (the same loop, paused and resumed). A budget or a tolerance at 10^6 points reads a few
    per cent of the ranking, and the first K of a farthest-point ranking cost far less than all N
    (each chosen point updates the distances only around it, in an ever smaller neighbourhood)."""

    def __init__(self, positions: np.ndarray, scores: np.ndarray, exponent: float = DEFAULT_EXPONENT):
        self._points = _checked_points(positions)
        self._weights = spread_weights(scores, exponent)
        if self._weights.shape[0] != self._points.shape[0]:
            raise SpreadError(f"{self._weights.shape[0]:,} scores for {self._points.shape[0]:,} positions: "
                              "give one score per point")
        self.point_count = int(self._points.shape[0])
        self._state = list(start_ranking(self._points, self._weights, extreme_seeds(self._points)))

    @property
    def computed(self) -> int:
        """How many leading points are ranked so far."""
        return int(self._state[1])

    def prefix(self, count: int) -> np.ndarray:
        """The first min(count, N) points of the ranking (a view: do not modify)."""
        wanted = min(max(int(count), 0), self.point_count)
        if wanted > self.computed:
            # Grow at least geometrically: a search that asks for K, 2K, 4K, ... resumes few times.
            limit = min(self.point_count, max(wanted, 2 * self.computed))
            ranked, size = extend_ranking(self._points, self._weights, *self._state, limit)
            self._state[1], self._state[2] = ranked, size
        return self._state[0][:wanted]

    def provisional_order(self) -> np.ndarray:
        """(N,): the points ranked so far, then the others by index (their true order is not known yet)."""
        ranked = self.computed
        return np.concatenate([self._state[0][:ranked], np.flatnonzero(~self._state[8])])


def farthest_point_ranking(positions: np.ndarray, weights: np.ndarray, seeds: np.ndarray,
                           limit: int | None = None) -> np.ndarray:
    """`seeds` in order (repeats dropped; none: point 0), then repeatedly the point maximising
    weight x distance to the chosen set, ties to the lower index. (N,) int64; with `limit`, only the first
    min(limit, N) of that ranking (at least the seeds), at the cost of ranking those.

    weights: (N,) finite, >= 0. Exact: equals the O(N^2) argmax loop (tests/core/test_core_spread.py).
    """
    points = _checked_points(positions)
    n = points.shape[0]
    w = np.asarray(weights, dtype=np.float64)
    if w.shape != (n,):
        raise SpreadError(f"weights must have shape ({n},) (one per position), got {list(w.shape)}")
    if not np.all(np.isfinite(w) & (w >= 0.0)):
        bad = int(np.flatnonzero(~(np.isfinite(w) & (w >= 0.0)))[0])
        raise SpreadError(f"weight {bad} = {w[bad]!r} must be a finite number >= 0")
    start = np.asarray(seeds).reshape(-1)
    if start.shape[0] and not np.issubdtype(start.dtype, np.integer):
        raise SpreadError(f"seeds must be point indices (integers), got {start.dtype}")
    start = start.astype(np.int64)
    if start.shape[0] and (start.min() < 0 or start.max() >= n):
        raise SpreadError(f"seed index {int(start[(start < 0) | (start >= n)][0])} is outside the {n:,} points")
    start = np.asarray(list(dict.fromkeys(start.tolist())) or ([0] if n else []), dtype=np.int64)
    if limit is None:
        return weighted_farthest_points(points, w, start)
    state = start_ranking(points, w, start)
    ranked, _ = extend_ranking(points, w, *state, int(limit))
    return state[0][:ranked]
