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

Exact and fast (N up to ~10^6): an exact lazy max-heap over the keys (distances only shrink, so a
stored key is an upper bound; an entry is taken only when it equals the point's current key) and a
static k-d hierarchy over the points (scipy's cKDTree leaves, grouped upwards) carrying the largest
current distance of each node. Choosing points updates distances only in the nodes that can change
(the node's box is nearer to a new point than the node's largest distance) — exact for any weights,
unlike a ball of radius "largest distance", which contains (w_max / w_min)^3 times too many points.
Points are chosen in batches: each heap candidate is first brought up to date against the batch
chosen so far (so it is the exact next point), and the batch's distance updates are applied at once.
"""

from __future__ import annotations

import heapq
import math

import numpy as np
from scipy.spatial import cKDTree

from .features import D14

SCORE_FLOOR = 1e-6  # scores are clipped to [SCORE_FLOOR, 1] (NaN -> SCORE_FLOOR)
DEFAULT_EXPONENT = 0.5
LEAF_SIZE = 16  # k-d leaf size of the distance hierarchy
FAN_OUT = 8  # children per node above the leaves
BATCH_LIMIT = 64  # points chosen before their distance updates are applied together
PRUNE_SLACK = 1e-6  # relative slack of the box test: rounding can only make it visit more nodes
FILTER_SLACK = 1e-9  # math.dist is within an ulp of the true distance: keep candidates below (1 + this) x D


class SpreadError(ValueError):
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


def _distances(points: np.ndarray, a: np.ndarray, b: np.ndarray | int) -> np.ndarray:
    """sqrt(dx*dx + dy*dy + dz*dz) between points[a] and points[b] (rows), summed left to right."""
    d = points[a] - points[b]
    return np.sqrt(d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1] + d[..., 2] * d[..., 2])


# ------------------------------------------------------------------------------ the ranking itself

def spread_ranking(positions: np.ndarray, scores: np.ndarray, exponent: float = DEFAULT_EXPONENT) -> np.ndarray:
    """The spread ranking of selection.md: (N,) int64, every point once, most important first."""
    points = _checked_points(positions)
    weights = spread_weights(scores, exponent)
    if weights.shape[0] != points.shape[0]:
        raise SpreadError(f"{weights.shape[0]:,} scores for {points.shape[0]:,} positions: give one score per point")
    return farthest_point_ranking(points, weights, extreme_seeds(points))


def farthest_point_ranking(positions: np.ndarray, weights: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """`seeds` in order (repeats dropped; none: point 0), then repeatedly the point maximising
    weight x distance to the chosen set, ties to the lower index. (N,) int64.

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
    order = np.empty(n, dtype=np.int64)
    order[:start.shape[0]] = start
    if start.shape[0] == n:
        return order
    distance = np.full(n + 1, np.inf)  # one sentinel slot (distance 0) pads the hierarchy's tables
    for seed in start.tolist():
        np.minimum(distance[:n], _distances(points, slice(None), seed), out=distance[:n])
    distance[start] = 0.0
    distance[n] = 0.0
    chosen = np.zeros(n, dtype=bool)
    chosen[start] = True
    _Sampler(points, w, distance, chosen).run(order, start.shape[0])
    return order


def _nearest(here: list[float], members: list[list[float]], limit: float) -> float | None:
    """The exact distance (the formula above) from `here` to the nearest of `members` when it is below
    `limit`, else None. math.dist (within an ulp of the true distance) discards the far ones first."""
    bound = limit * (1.0 + FILTER_SLACK)
    near = [m for m in members if math.dist(m, here) < bound]
    if not near:
        return None
    x, y, z = here
    best = min((m[0] - x) * (m[0] - x) + (m[1] - y) * (m[1] - y) + (m[2] - z) * (m[2] - z) for m in near)
    nearest = math.sqrt(best)  # sqrt is monotonic: the sqrt of the smallest sum is the smallest distance
    return nearest if nearest < limit else None


class _Hierarchy:
    """Static k-d leaves of the points, grouped FAN_OUT at a time upwards, each node with its box and
    the largest current distance of its points. Row `count` of every level is an empty sentinel."""

    def __init__(self, points: np.ndarray, distance: np.ndarray):
        n = points.shape[0]
        tree = cKDTree(points, leafsize=LEAF_SIZE, balanced_tree=False, compact_nodes=False)
        leaves, stack = [], [tree.tree]
        while stack:  # depth first, lesser side first: consecutive leaves are neighbours in space
            node = stack.pop()
            if node.lesser is None:
                leaves.append((node.start_idx, node.end_idx))
            else:
                stack.extend((node.greater, node.lesser))
        members = np.full((len(leaves), max(e - s for s, e in leaves)), n, dtype=np.int64)  # pad: sentinel n
        for row, (s, e) in enumerate(leaves):
            members[row, :e - s] = tree.indices[s:e]
        self.members = members
        self.leaf_of = np.empty(n + 1, dtype=np.int64)
        self.leaf_of[members.reshape(-1)] = np.repeat(np.arange(members.shape[0]), members.shape[1])
        padded = np.concatenate([points, np.full((1, 3), np.nan)])
        inside = (members < n)[..., None]
        lo = np.where(inside, padded[members], np.inf).min(axis=1)
        hi = np.where(inside, padded[members], -np.inf).max(axis=1)
        self.lo, self.hi, self.children = [self._pad(lo, np.inf)], [self._pad(hi, -np.inf)], [members]
        self.maxd = [np.append(distance[members].max(axis=1), 0.0)]
        while self.lo[-1].shape[0] - 1 > FAN_OUT:  # levels up to a root of <= FAN_OUT nodes
            count = self.lo[-1].shape[0] - 1
            parents = -(-count // FAN_OUT)
            children = np.arange(parents * FAN_OUT).reshape(parents, FAN_OUT)
            children[children >= count] = count  # the level's sentinel
            self.children.append(children)
            self.lo.append(self._pad(self.lo[-1][children].min(axis=1), np.inf))
            self.hi.append(self._pad(self.hi[-1][children].max(axis=1), -np.inf))
            self.maxd.append(np.append(self.maxd[-1][children].max(axis=1), 0.0))

    @staticmethod
    def _pad(box: np.ndarray, value: float) -> np.ndarray:
        return np.concatenate([box, np.full((1, 3), value)])

    def candidates(self, points: np.ndarray, centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(centre row, point) pairs whose point may be nearer to that centre than its distance."""
        top = len(self.lo) - 1
        pair_centre = np.repeat(np.arange(centres.shape[0]), self.lo[top].shape[0] - 1)
        node = np.tile(np.arange(self.lo[top].shape[0] - 1), centres.shape[0])
        for level in range(top, -1, -1):
            c = points[centres[pair_centre]]
            gap = np.maximum(self.lo[level][node] - c, 0.0) + np.maximum(c - self.hi[level][node], 0.0)
            near2 = gap[:, 0] * gap[:, 0] + gap[:, 1] * gap[:, 1] + gap[:, 2] * gap[:, 2]
            reach = self.maxd[level][node]
            keep = near2 < reach * reach * (1.0 + PRUNE_SLACK)
            pair_centre, node = pair_centre[keep], node[keep]
            width = self.children[level].shape[1]
            pair_centre = np.repeat(pair_centre, width)
            node = self.children[level][node].reshape(-1)
        return pair_centre, node

    def refresh(self, distance: np.ndarray, points: np.ndarray) -> None:
        """Recompute the largest distance of the leaves holding `points`, and of their ancestors."""
        nodes = np.unique(self.leaf_of[points])
        for level in range(len(self.maxd)):
            self.maxd[level][nodes] = (distance[self.children[level][nodes]] if level == 0
                                       else self.maxd[level - 1][self.children[level][nodes]]).max(axis=1)
            nodes = np.unique(nodes // FAN_OUT)


class _Sampler:
    """Weighted farthest-point sampling after the seeds: lazy max-heap + batched exact updates."""

    def __init__(self, points: np.ndarray, weights: np.ndarray, distance: np.ndarray, chosen: np.ndarray):
        n = points.shape[0]
        self.points = np.concatenate([points, np.zeros((1, 3))])  # sentinel row n
        self.weights = np.append(weights, 0.0)
        self.distance = distance  # (n + 1,), sentinel 0
        self.key = self.weights * distance
        self.chosen = chosen
        self.hierarchy = _Hierarchy(self.points[:n], distance)
        open_points = np.flatnonzero(~chosen)
        self.heap = list(zip((-self.key[open_points]).tolist(), open_points.tolist()))
        heapq.heapify(self.heap)

    def run(self, order: np.ndarray, position: int) -> None:
        heap, key, distance, chosen, points = self.heap, self.key, self.distance, self.chosen, self.points
        weights = self.weights
        n = order.shape[0]
        while position < n:
            # Early on every new point moves the distances of ~N/position others: smaller batches bound memory.
            limit = min(BATCH_LIMIT, max(1, position // 4))
            batch: list[int] = []
            members: list[list[float]] = []  # the batch's positions
            checked: dict[int, int] = {}  # point -> how many batch members its distance already accounts for
            lowered: list[int] = []
            while heap and len(batch) < limit:
                stored, p = heap[0]
                if chosen[p]:
                    heapq.heappop(heap)
                    continue
                current = float(key[p])
                if -stored != current:  # stale upper bound: re-file it at the point's current key
                    heapq.heapreplace(heap, (-current, p))
                    continue
                upto = checked.get(p, 0)
                here = points[p].tolist()
                if upto < len(batch):  # bring D(p) up to date with this batch's new points
                    checked[p] = len(batch)
                    nearest = _nearest(here, members[upto:], float(distance[p]))
                    if nearest is not None:
                        distance[p] = nearest
                        key[p] = weights[p] * nearest
                        lowered.append(p)
                        heapq.heapreplace(heap, (-float(key[p]), p))
                        continue
                heapq.heappop(heap)  # an exact key at the top: the next point
                batch.append(p)
                members.append(here)
                chosen[p] = True
                distance[p] = key[p] = 0.0
            order[position:position + len(batch)] = batch
            position += len(batch)
            self._apply(np.asarray(batch, dtype=np.int64), lowered)

    def _apply(self, batch: np.ndarray, lowered: list[int]) -> None:
        """Distances after choosing `batch`: min over the new points, where the hierarchy allows a change."""
        if batch.shape[0] == 0:
            return
        pair_centre, point = self.hierarchy.candidates(self.points, batch)
        gap = _distances(self.points, point, batch[pair_centre])
        hit = gap < self.distance[point]
        point, gap = point[hit], gap[hit]
        np.minimum.at(self.distance, point, gap)
        changed = np.unique(point)
        self.key[changed] = self.weights[changed] * self.distance[changed]
        self.hierarchy.refresh(self.distance, np.concatenate([changed, batch, np.asarray(lowered, dtype=np.int64)]))
