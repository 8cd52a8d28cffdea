"""LumiProbes' greedy decimation, faithfully (quality.md §3.1) — the slow ground truth, for small sets.

Start from all candidates (or a given initial set); each iteration tries removing every remaining probe, recomputes the
placement error from scratch against the original dense reference (re-tetrahedralise, re-locate,
re-evaluate: O(n^2 (n log n + N)) per run, as LumiProbes did), and removes the probe with the
smallest error (ties: lowest index). A removal that leaves no valid tetrahedralisation is skipped.
Stopping rules as LumiProbes: an error threshold (stop *without* removing when the best next error
exceeds it) and/or a minimum count, with a floor of 4.

Kept from LumiProbes: the loop, the cumulative error against the original reference, the stopping
rules and the tie-break. Fixed: B1/B2/B5 (the metric and interpolation of metric/metric.py), B3 (no
`cost > 0` filter: zero-impact removals are the best ones), B4 (no extra /3), B8 (one clock per run),
B10 (an invalid configuration is skipped, never evaluated as black).
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np

from .decimation import MINIMUM_PROBES, Decimation, error_curve_from, initial_mask, tie_key
from ...metric.metric import PRIMARY_METRIC, ReferenceField, checked_metric, point_errors
from ...metric.triangulation import GeometryError

FAITHFUL_MAX_CANDIDATES = 200


def faithful_decimation(field: ReferenceField, metric: str = PRIMARY_METRIC, max_error: float | None = None,
                        min_count: int = MINIMUM_PROBES, max_candidates: int = FAITHFUL_MAX_CANDIDATES,
                        progress: Callable[[int, int], None] | None = None,
                        initial: np.ndarray | None = None) -> Decimation:
    """Greedy decimation by exhaustive re-evaluation. `max_error` is a mean error (None = off).
    initial: the starting probe set (boolean mask or point indices; None = every point)."""
    checked_metric(metric)
    n = field.point_count
    if n > max_candidates:
        raise ValueError(f"the faithful decimation costs O(n^3 N); {n:,} candidates exceed its limit of "
                         f"{max_candidates:,}: use the fast reference (reference_fast) instead")
    if max_error is not None and not (np.isfinite(max_error) and max_error >= 0.0):
        raise ValueError(f"max_error {max_error!r} must be a finite number >= 0 (or None to disable it)")
    floor = max(int(min_count), MINIMUM_PROBES)
    start = time.perf_counter()
    mask = initial_mask(initial, n)
    alive = np.ones(n, dtype=bool) if mask is None else mask.copy()
    start_count = int(np.count_nonzero(alive))
    start_error = 0.0 if mask is None else float(point_errors(field, np.flatnonzero(alive), metric).mean())
    removed: list[int] = []
    errors: list[float] = []
    stop_reason = "minimum count"
    while np.count_nonzero(alive) > floor:
        best_key, best_index, best_mean = float("inf"), -1, float("nan")
        for candidate in np.flatnonzero(alive):
            alive[candidate] = False
            try:
                total = float(point_errors(field, np.flatnonzero(alive), metric).sum())
            except GeometryError:  # e.g. the rest is coplanar: LumiProbes rejects and reinserts
                total = float("inf")
            alive[candidate] = True
            key = tie_key(total)
            if key < best_key:  # strict: ties keep the lowest index
                best_key, best_index, best_mean = key, int(candidate), total / n
        if best_index < 0:
            stop_reason = "no removable probe"
            break
        if max_error is not None and best_mean > max_error:
            stop_reason = "max error"
            break
        alive[best_index] = False
        removed.append(best_index)
        errors.append(best_mean)
        if progress is not None:
            progress(len(removed), start_count - floor)
    return Decimation(method="faithful-greedy", metric=metric, removed=np.asarray(removed, dtype=np.int64),
                      error_curve=error_curve_from(errors, n, start_count, start_error), stop_reason=stop_reason,
                      seconds=time.perf_counter() - start, initial=mask)
