"""Compiled loops of the lighting features' neighbour comparisons (features.py, `_RelativeDifference`).

At 10^6 points the numpy passes gather (chunk, 42) rows for every neighbour offset and scale (nine
passes each for change_k and curvature_k): about half of the feature step. These loops compute the
same numbers pair by pair in numpy's order of operations, so the features are bit-identical
(tests/core/test_core_features_kernel.py): a row sum of 42 values is numpy's pairwise sum, and
max() is exact in any order. Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from .cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit  # noqa: E402  (after the cache folder is chosen)


@njit(cache=True, inline="always")
def pairwise_sum(a, n):
    """numpy's pairwise_sum (numpy/_core/src/umath/loops_utils.h.src) for n <= 128 values of a (1-D):
    below 8 values a running sum from 0; else 8 partial sums over the multiple of 8, combined
    ((r0+r1)+(r2+r3))+((r4+r5)+(r6+r7)), then the rest in order."""
    if n < 8:
        total = 0.0
        for i in range(n):
            total += a[i]
        return total
    r0, r1, r2, r3, r4, r5, r6, r7 = a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]
    i = 8
    while i < n - (n % 8):
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    total = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        total += a[i]
        i += 1
    return total


@njit(cache=True)
def raise_change(light, abs_sum, floor, plus, change):
    """change[p] and change[q] = max(., rel(E(q), E(p))) for every pair q = plus[p] >= 0, with
    rel = sum|E(q) - E(p)| / ((sum|E(q)| + sum|E(p)|) + floor)."""
    width = light.shape[1]
    difference = np.empty(width)
    for p in range(plus.shape[0]):
        q = plus[p]
        if q < 0:
            continue
        for c in range(width):
            difference[c] = abs(light[q, c] - light[p, c])
        rel = pairwise_sum(difference, width) / (abs_sum[q] + abs_sum[p] + floor)
        if rel > change[p]:
            change[p] = rel
        if rel > change[q]:
            change[q] = rel


@njit(cache=True)
def raise_curvature(light, abs_sum, floor, plus, minus, curvature):
    """curvature[p] = max(., rel(E(p), (E(p+) + E(p-)) * 0.5)) where both neighbours exist, with
    rel = sum|M - E(p)| / ((sum|E(p)| + sum|M|) + floor)."""
    width = light.shape[1]
    midpoint = np.empty(width)
    difference = np.empty(width)
    for p in range(plus.shape[0]):
        a, b = plus[p], minus[p]
        if a < 0 or b < 0:
            continue
        for c in range(width):
            m = (light[a, c] + light[b, c]) * 0.5
            midpoint[c] = abs(m)
            difference[c] = abs(m - light[p, c])
        rel = pairwise_sum(difference, width) / (abs_sum[p] + pairwise_sum(midpoint, width) + floor)
        if rel > curvature[p]:
            curvature[p] = rel
