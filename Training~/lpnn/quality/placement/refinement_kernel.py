"""Compiled loops of batched refinement's rounds (batched_refinement.py, batched_state.py).

At 10^6 points the numpy versions passed over (N,) and (N, 4) arrays several times a round while a round touches a few
thousand probes: the greedy independent set ran its vectorised passes over arrays as long as the points, and finding the
points whose stencil holds a removed probe scanned every stencil with temporaries. These loops give the same results
(tests/quality/test_quality_batched_refinement.py compares both). Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ...core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit, prange  # noqa: E402  (after the cache folder is chosen)

from ..metric.metric_kernel import chunk_bounds, chunk_count, run_rows  # noqa: E402


@njit(cache=True)
def sequential_greedy(ordered, edge_from, edge_to, size):
    """The vertices `ordered` (distinct ids < size, in visiting order) the sequential greedy keeps: each one none of
    whose neighbours (edges edge_from -> edge_to, both directions listed, sorted by edge_from) it kept before."""
    blocked = np.zeros(size, dtype=np.bool_)
    kept = np.empty(ordered.shape[0], dtype=np.int64)
    count = 0
    for v in ordered:
        if blocked[v]:
            continue
        kept[count] = v
        count += 1
        for e in range(np.searchsorted(edge_from, v), np.searchsorted(edge_from, v + 1)):
            blocked[edge_to[e]] = True
    return kept[:count]


@njit(cache=True, parallel=True)
def _holding(ids, gone, hit, which):
    """hit[r]: row r is gone or holds a gone id >= 0; then which[r] = r if gone, else the first gone id it holds
    (other rows' `which` is left as it was)."""
    chunks = chunk_count(ids.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(ids.shape[0], chunks, chunk)
        for r in range(lo, hi):
            found = r if gone[r] else -1
            for k in range(ids.shape[1]):
                v = ids[r, k]
                if found < 0 and v >= 0 and gone[v]:
                    found = v
            hit[r] = found >= 0
            if found >= 0:
                which[r] = found


@njit(cache=True)
def attributed_costs(owners, attributed, is_candidate, trial_errors, state_errors, totals):
    """batched_state.trial_of's attribution: each attributed row's error change goes to the row itself when it is a
    candidate, else to the first candidate its `owners` row holds (numpy's argmax of the first hit); totals[owner] sums
    them in row order, as numpy's bincount with weights does (the same numbers, without (A, 4) temporaries)."""
    for i in range(attributed.shape[0]):
        r = attributed[i]
        owner = r
        if not is_candidate[r]:
            owner = owners[r, 0]
            for k in range(owners.shape[1]):
                v = owners[r, k]
                if v >= 0 and is_candidate[v]:
                    owner = v
                    break
        totals[owner] += trial_errors[r] - state_errors[r]


@njit(cache=True, parallel=True)
def stencil_ids(indices, vertices, weights, touched, owners):
    """touched = indices[vertices]; owners = touched where the weight is > 0, else -1 (batched_state.evaluated_at's
    rows, without (M, 4) temporaries); rows in parallel slices."""
    chunks = chunk_count(vertices.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(vertices.shape[0], chunks, chunk)
        for m in range(lo, hi):
            for k in range(vertices.shape[1]):
                v = indices[vertices[m, k]]
                touched[m, k] = v
                owners[m, k] = v if weights[m, k] > 0.0 else -1


def rows_holding_which(ids: np.ndarray, gone: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows r (ascending) where some ids[r, k] >= 0 is `gone`, or gone[r] itself (rows scanned in parallel), and for
    each the gone id it holds: the row itself when gone, else its first gone id."""
    hit = np.empty(ids.shape[0], dtype=bool)
    which = np.empty(ids.shape[0], dtype=np.int64)  # written at the hit rows only
    run_rows(_holding, ids.shape[0], ids, gone, hit, which)
    rows = np.flatnonzero(hit)
    return rows, which[rows]


@njit(cache=True)
def refill_start_rows(star, probes, refill_owner, base, out):
    """out[i] = base + the first f with refill_owner[f] == star[i] (a removed probe of the sorted state `probes`), or
    `base` when it has no refill (batched_state.refill_starts; the map from a probe to its first refill is as long as
    the probes, not as the points)."""
    first = np.full(probes.shape[0], -1, dtype=np.int64)
    for f in range(refill_owner.shape[0] - 1, -1, -1):
        at = np.searchsorted(probes, refill_owner[f])
        if at < probes.shape[0] and probes[at] == refill_owner[f]:  # an owner that is no probe has no star to start in
            first[at] = f
    last, row = -1, -1  # the points of one star come in runs: search each run's probe once
    for i in range(star.shape[0]):
        if star[i] != last:
            last = star[i]
            at = np.searchsorted(probes, last)
            row = first[at] if at < probes.shape[0] and probes[at] == last else -1
        out[i] = base + (row if row >= 0 else 0)
