"""The placement error as a training validation metric (`lpnn train --metric`).

    lpnn train DATASET --out model.onnx --metric lpnn.train.placement_metric:PLACEMENT_ERROR_20

reports, per held-out capture, the mean placement error of the model's 20 % placement (budget
policy on the spread ranking of its scores, the way LPNN scores become probes: quality.md §4,
selection.md) — the same number `lpnn bench` reports for `lpnn`. PLACEMENT_ERROR_TOPK_20 measures
the raw top 20 % instead (`network-topk`). Lower is better.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.grid import EvaluationGrid
from ..core.selection import rank
from ..core.spread import spread_ranking
from ..quality.metric.metric import ReferenceField, placement_error
from ..quality.placement.policies import budget_count, prefix_selection
from .metrics import CaptureMetric


def placement_error_at(fraction: float, topk: bool = False) -> CaptureMetric:
    """CaptureMetric: mean placement error of the first `fraction` of the points in the spread ranking
    of the scores (topk: in score order)."""

    def per_capture(cloud: Any, scores: np.ndarray) -> float:
        capture = cloud.capture
        if capture is None or np.asarray(scores).shape[0] != capture.point_count:
            return float("nan")  # a crop, not the whole capture: the metric needs every point
        values = np.asarray(scores, dtype=np.float64)
        grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
        select = prefix_selection(grid, rank(values) if topk else spread_ranking(capture.positions, values))
        field = ReferenceField.from_capture(capture)
        return placement_error(field, select(budget_count(fraction, capture.point_count))).mean

    return CaptureMetric(f"placement_error{'_topk' if topk else ''}_{round(fraction * 100)}", False, per_capture)


PLACEMENT_ERROR_10 = placement_error_at(0.1)
PLACEMENT_ERROR_20 = placement_error_at(0.2)
PLACEMENT_ERROR_30 = placement_error_at(0.3)
PLACEMENT_ERROR_TOPK_20 = placement_error_at(0.2, topk=True)
