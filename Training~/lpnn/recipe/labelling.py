"""Ground truth for training: the fast error-driven reference placement (Documentation~/quality.md §3).

Each capture gets
- `labels`: 1 for the points the reference keeps at `label_budget` of the points;
- `reference_rank` (int32 [N]): every point's position in the reference's importance ordering
  (0 = most important), so the labels of any other budget follow without rerunning it;
- `reference_error` (float32 [N]): the reference's mean error with 1..N probes (NaN below the floor of 4).
"""

from __future__ import annotations

import time

import numpy as np

from ..core.capture import Capture
from ..quality.placement.decimation.decimation import MINIMUM_PROBES, Decimation
from ..quality.metric.metric import PRIMARY_METRIC, ReferenceField
from ..quality.placement.policies import budget_count, reference_label_source
from ..quality.placement.decimation.reference_fast import fast_decimation

RANK_SECTION = "reference_rank"
ERROR_SECTION = "reference_error"


def label_source(budget: float) -> str:
    return reference_label_source("fast", budget, None)


def labelled(capture: Capture, budget: float) -> tuple[Capture, float]:
    """The capture with reference labels and the two reference sections; and the reference's seconds."""
    start = time.perf_counter()
    decimation = fast_decimation(ReferenceField.from_capture(capture), workers=1)
    seconds = time.perf_counter() - start
    n = capture.point_count
    rank = np.empty(n, dtype=np.int32)
    rank[decimation.ordering] = np.arange(n, dtype=np.int32)
    labels = (rank < budget_count(budget, n)).astype(np.uint8)
    extra = dict(capture.extra_sections)
    extra[RANK_SECTION] = rank
    extra[ERROR_SECTION] = decimation.error_curve[1:].astype(np.float32)
    result = capture.with_labels(labels, label_source(budget))
    result.extra_sections = extra
    return result, seconds


def reference_ordering(capture: Capture) -> np.ndarray:
    """The reference's importance ordering stored by `labelled` (most important first)."""
    if RANK_SECTION not in capture.extra_sections:
        raise ValueError(f"capture has no '{RANK_SECTION}' section: label it with the recipe first")
    return np.argsort(capture.extra_sections[RANK_SECTION], kind="stable").astype(np.int64)


def stored_reference(capture: Capture) -> Decimation:
    """The reference decimation `labelled` stored, rebuilt without rerunning it: its ordering lists the
    survivors, then the removals last-removed first, so the removal order is the tail reversed."""
    ordering = reference_ordering(capture)
    if ERROR_SECTION not in capture.extra_sections:
        raise ValueError(f"capture has no '{ERROR_SECTION}' section: label it with the recipe first")
    errors = np.asarray(capture.extra_sections[ERROR_SECTION], dtype=np.float64)
    n = capture.point_count
    if errors.shape != (n,):
        raise ValueError(f"'{ERROR_SECTION}' holds {errors.shape[0]:,} values for {n:,} points")
    curve = np.concatenate([[np.nan], errors])
    reached = np.flatnonzero(np.isfinite(curve))
    smallest = int(reached[0]) if reached.shape[0] else n
    if smallest < MINIMUM_PROBES:
        raise ValueError(f"'{ERROR_SECTION}' has an error for {smallest} probe(s); a decimation stops at {MINIMUM_PROBES}")
    return Decimation(method="fast-greedy", metric=PRIMARY_METRIC, removed=ordering[smallest:][::-1].copy(),
                      error_curve=curve, stop_reason="stored by the recipe's labelling", seconds=float("nan"))
