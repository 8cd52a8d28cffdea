"""`lpnn model check`: a shipped model against its contract, without the Keras model.

Checks the graph (onnx checker, allowed ops, opset, I/O names and dims), that the card matches the
graph, and runs sanity checks with onnxruntime: outputs finite and in [0, 1] for several cloud sizes,
point-permutation equivariance (a PointNet must not depend on point order) and independence of the
clouds in one batch (the global pooling must not mix clouds).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import onnx

from ..core.capture_file import read_capture
from .export import ExportError, check_io, check_ops
from .metrics import pr_auc, roc_auc
from .modelcard import INPUT_NAME, OUTPUT_NAME
from .onnx_scoring import OnnxScorer

SANITY_SIZES = (1, 7, 1000)
EQUIVALENCE_TOLERANCE = 1e-5


def _card_range_features(scorer: OnnxScorer, rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    mean = np.asarray(scorer.card.normalisation["mean"], np.float32)
    std = np.asarray(scorer.card.normalisation["std"], np.float32)
    return (mean + 3.0 * std * rng.standard_normal((*shape, scorer.feature_count))).astype(np.float32)


def check_model_file(model_path: str | os.PathLike, captures: Sequence[str | os.PathLike] = (),
                     seed: int = 0) -> dict[str, Any]:
    """Report of every check; raises ExportError (or UserError) on the first failure."""
    path = Path(model_path)
    scorer = OnnxScorer(path)
    proto = onnx.load(str(path))
    onnx.checker.check_model(proto)
    ops = check_ops(proto)
    check_io(proto, scorer.feature_count)
    if sorted(scorer.card.ops) != ops:
        raise ExportError(f"{path}: the card lists ops {sorted(scorer.card.ops)} but the graph uses {ops}")
    rng = np.random.default_rng(seed)
    report: dict[str, Any] = {"ops": ops, "opset": scorer.card.opset, "sizes": list(SANITY_SIZES)}
    for size in SANITY_SIZES:
        scores = scorer.score(_card_range_features(scorer, rng, (size,)))
        if scores.shape != (size,) or not np.all(np.isfinite(scores)) or scores.min() < 0 or scores.max() > 1:
            raise ExportError(f"{path}: {size} points gave scores of shape {scores.shape} outside [0, 1] or not finite")
    cloud = _card_range_features(scorer, rng, (SANITY_SIZES[-1],))
    permutation = rng.permutation(cloud.shape[0])
    base = scorer.score(cloud)
    permuted_difference = float(np.max(np.abs(scorer.score(cloud[permutation]) - base[permutation])))
    if permuted_difference > EQUIVALENCE_TOLERANCE:
        raise ExportError(f"{path}: shuffling the points changed their scores by {permuted_difference:.3g}")
    other = _card_range_features(scorer, rng, (cloud.shape[0],))
    batched = scorer.session.run([OUTPUT_NAME], {INPUT_NAME: np.stack([cloud, other])})[0]
    batch_difference = float(np.max(np.abs(batched[0] - base)))
    if batch_difference > EQUIVALENCE_TOLERANCE:
        raise ExportError(f"{path}: a second cloud in the batch changed the first cloud's scores by {batch_difference:.3g}")
    report.update(permutation_max_abs_diff=permuted_difference, batch_max_abs_diff=batch_difference, captures={})
    for capture_path in captures:
        capture = read_capture(capture_path)
        scores = scorer.score_capture(capture, str(capture_path))
        entry: dict[str, Any] = {"points": capture.point_count, "min": float(scores.min()), "max": float(scores.max())}
        if capture.labels is not None:
            entry.update(roc_auc=roc_auc(capture.labels, scores), pr_auc=pr_auc(capture.labels, scores))
        report["captures"][str(capture_path)] = entry
    return report
