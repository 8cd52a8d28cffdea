"""Compiled loop of the spread ranking's weighted farthest-point sampling (spread.py, selection.md).

The same exact rule and arithmetic as spread.py's text (the C# core's NearestChosenDistances and
SpreadRanking follow the same plan): a static k-d tree whose nodes carry the largest current
distance D of their points, updated for each chosen point only in the nodes whose box is nearer to
it than that largest D; a lazy max-heap of w x D keyed (value descending, index ascending), whose
top is taken only when it equals the point's current key (D only shrinks, so a stored key is an
upper bound). One chosen point at a time, compiled with numba (cached on disk after the first run).
A Python loop over ~10^6 points with batched numpy updates took 15 s for 130,000 points; this
takes a fraction of that (Documentation~/benchmarks.md "Scale: whole levels").
"""

from __future__ import annotations

import numpy as np
from numba import njit

LEAF_SIZE = 8
PRUNE_MARGIN = 1e-9  # relative slack of the box test: rounding can only make it visit more nodes


@njit(cache=True)
def _build_tree(points: np.ndarray, order: np.ndarray, leaf_size: int):
    """Nodes (start, count, left, right) and boxes of a median-split k-d tree over `order` (permuted in place)."""
    n = points.shape[0]
    capacity = 2 * (n // max(1, leaf_size // 2) + 1) + 1
    span = np.empty((capacity, 4), dtype=np.int64)  # start, count, left, right
    box = np.empty((capacity, 6))  # min xyz, max xyz
    stack = np.empty((capacity, 3), dtype=np.int64)  # node, start, count
    count_nodes = 1
    top = 0
    stack[0, 0], stack[0, 1], stack[0, 2] = 0, 0, n
    while top >= 0:
        node, start, count = stack[top, 0], stack[top, 1], stack[top, 2]
        top -= 1
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        for k in range(start, start + count):
            for a in range(3):
                v = points[order[k], a]
                if v < lo[a]:
                    lo[a] = v
                if v > hi[a]:
                    hi[a] = v
        for a in range(3):
            box[node, a] = lo[a]
            box[node, 3 + a] = hi[a]
        span[node, 0], span[node, 1], span[node, 2], span[node, 3] = start, count, -1, -1
        if count > leaf_size:
            extent = hi - lo
            axis = 0 if extent[0] >= extent[1] and extent[0] >= extent[2] else (1 if extent[1] >= extent[2] else 2)
            segment = order[start:start + count]
            keys = np.empty(count)
            for k in range(count):
                keys[k] = points[segment[k], axis]
            sorted_segment = segment[np.argsort(keys, kind="mergesort")]
            order[start:start + count] = sorted_segment
            half = count // 2
            left, right = count_nodes, count_nodes + 1
            count_nodes += 2
            span[node, 2], span[node, 3] = left, right
            top += 1
            stack[top, 0], stack[top, 1], stack[top, 2] = right, start + half, count - half
            top += 1
            stack[top, 0], stack[top, 1], stack[top, 2] = left, start, half
    return span[:count_nodes], box[:count_nodes]


@njit(cache=True)
def _update(points, order, span, box, largest, distance, chosen_point, stack, finish):
    """Lower D to the distance to `chosen_point` where smaller; refresh each visited node's largest D."""
    cx, cy, cz = points[chosen_point, 0], points[chosen_point, 1], points[chosen_point, 2]
    top = 0
    stack[0] = 0
    finish[0] = False
    while top >= 0:
        node = stack[top]
        done = finish[top]
        top -= 1
        left, right = span[node, 2], span[node, 3]
        if done:
            largest[node] = max(largest[left], largest[right])
            continue
        bound = largest[node]
        if bound != np.inf:
            dx = max(0.0, max(box[node, 0] - cx, cx - box[node, 3]))
            dy = max(0.0, max(box[node, 1] - cy, cy - box[node, 4]))
            dz = max(0.0, max(box[node, 2] - cz, cz - box[node, 5]))
            if dx * dx + dy * dy + dz * dz > bound * bound * (1.0 + PRUNE_MARGIN):
                continue
        if left < 0:
            most = 0.0
            for k in range(span[node, 0], span[node, 0] + span[node, 1]):
                p = order[k]
                ex, ey, ez = points[p, 0] - cx, points[p, 1] - cy, points[p, 2] - cz
                d = np.sqrt(ex * ex + ey * ey + ez * ez)
                if d < distance[p]:
                    distance[p] = d
                if distance[p] > most:
                    most = distance[p]
            largest[node] = most
            continue
        top += 1
        stack[top] = node
        finish[top] = True
        top += 1
        stack[top] = right
        finish[top] = False
        top += 1
        stack[top] = left
        finish[top] = False


@njit(cache=True)
def _before(value_a, point_a, value_b, point_b) -> bool:
    """Heap order: larger value first, then the lower index."""
    return value_a > value_b or (value_a == value_b and point_a < point_b)


@njit(cache=True)
def _push(values, points_of, size, value, point) -> int:
    i = size
    values[i], points_of[i] = value, point
    while i > 0:
        parent = (i - 1) // 2
        if not _before(values[i], points_of[i], values[parent], points_of[parent]):
            break
        values[i], values[parent] = values[parent], values[i]
        points_of[i], points_of[parent] = points_of[parent], points_of[i]
        i = parent
    return size + 1


@njit(cache=True)
def _pop(values, points_of, size) -> int:
    size -= 1
    values[0], points_of[0] = values[size], points_of[size]
    i = 0
    while True:
        left, right, best = 2 * i + 1, 2 * i + 2, i
        if left < size and _before(values[left], points_of[left], values[best], points_of[best]):
            best = left
        if right < size and _before(values[right], points_of[right], values[best], points_of[best]):
            best = right
        if best == i:
            return size
        values[i], values[best] = values[best], values[i]
        points_of[i], points_of[best] = points_of[best], points_of[i]
        i = best


@njit(cache=True)
def start_ranking(points: np.ndarray, weights: np.ndarray, seeds: np.ndarray):
    """The state of a ranking after its seeds: (order, ranked, size, tree_order, span, box, largest,
    distance, chosen, stack, finish, heap values, heap points); extend_ranking continues it."""
    n = points.shape[0]
    order = np.empty(n, dtype=np.int64)
    tree_order = np.arange(n)
    span, box = _build_tree(points, tree_order, LEAF_SIZE)
    largest = np.full(span.shape[0], np.inf)
    distance = np.full(n, np.inf)
    chosen = np.zeros(n, dtype=np.bool_)
    stack = np.empty(2 * span.shape[0] + 8, dtype=np.int64)
    finish = np.empty(2 * span.shape[0] + 8, dtype=np.bool_)
    ranked = 0
    for s in range(seeds.shape[0]):
        seed = seeds[s]
        order[ranked] = seed
        ranked += 1
        chosen[seed] = True
        _update(points, tree_order, span, box, largest, distance, seed, stack, finish)
    values = np.empty(n)
    heap_points = np.empty(n, dtype=np.int64)
    size = 0
    for p in range(n):
        if not chosen[p]:
            size = _push(values, heap_points, size, weights[p] * distance[p], p)
    return order, ranked, size, tree_order, span, box, largest, distance, chosen, stack, finish, values, heap_points


@njit(cache=True)
def extend_ranking(points, weights, order, ranked, size, tree_order, span, box, largest, distance, chosen, stack,
                   finish, values, heap_points, limit):
    """Rank points until `limit` are ranked (or all); returns the new (ranked, size)."""
    n = points.shape[0]
    while ranked < min(limit, n):
        point, stored = heap_points[0], values[0]
        size = _pop(values, heap_points, size)
        current = weights[point] * distance[point]
        if current != stored:  # stale: D shrank since it was pushed
            size = _push(values, heap_points, size, current, point)
            continue
        order[ranked] = point
        ranked += 1
        chosen[point] = True
        _update(points, tree_order, span, box, largest, distance, point, stack, finish)
    return ranked, size


def weighted_farthest_points(points: np.ndarray, weights: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """`seeds` (distinct, in order), then repeatedly argmax weight x D, ties to the lower index: (N,) int64."""
    state = start_ranking(points, weights, seeds)
    extend_ranking(points, weights, *state, points.shape[0])
    return state[0]
