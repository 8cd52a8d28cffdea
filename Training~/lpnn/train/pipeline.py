"""The two jobs behind the CLI: train (captures -> checkpoint -> model + card) and export a checkpoint."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from .checkpoint import load_checkpoint, save_checkpoint
from .config import TrainConfig
from ..core.capture_file import read_capture
from .data import capture_files, display_names, load_split
from .diagnostics import batchnorm_report
from .export import export_model, onnx_path
from .metrics import DEFAULT_METRICS, CaptureMetric
from .modelcard import ModelCard, check_features
from .summary import checkpoint_meta
from .trainer import TrainResult, fit


@dataclass(frozen=True)
class TrainingRun:
    result: TrainResult
    card: ModelCard
    model_path: Path
    checkpoint_path: Path


def train_and_export(dataset_paths: Sequence[str | os.PathLike], out_path: str | os.PathLike, config: TrainConfig,
                     checkpoint_path: str | os.PathLike, validation_paths: Sequence[str | os.PathLike] = (),
                     extra_metrics: Sequence[CaptureMetric] = (), progress: bool = True) -> TrainingRun:
    """Loads and splits the captures, trains (checkpointing the best weights), exports model + card."""
    out = onnx_path(out_path)  # before training: a bad name fails fast
    checkpoint = Path(checkpoint_path)
    config = config.validated()  # before loading data: a bad option fails fast
    split = load_split(dataset_paths, validation_paths, config.seed, config.val_fraction)
    metrics = (*DEFAULT_METRICS, *extra_metrics)
    result = fit(split, config, metrics,
                 on_improvement=lambda so_far: save_checkpoint(checkpoint, so_far.model, checkpoint_meta(so_far)),
                 progress=progress)
    meta = checkpoint_meta(result, batchnorm_report(result.model, split.train))
    save_checkpoint(checkpoint, result.model, meta)
    card = export_model(result.model, meta, out, [(c.name, c.features) for c in split.validation])
    return TrainingRun(result=result, card=card, model_path=out, checkpoint_path=checkpoint)


def export_checkpoint(checkpoint_path: str | os.PathLike, out_path: str | os.PathLike,
                      parity_data: Sequence[str | os.PathLike] = ()) -> ModelCard:
    """Re-exports a checkpoint; captures in `parity_data` add real inputs to the parity check."""
    model, meta = load_checkpoint(checkpoint_path)
    real_inputs = []
    files = capture_files(parity_data) if parity_data else []
    for path, name in zip(files, display_names(files)):
        capture = read_capture(path)
        check_features(meta["schema"], meta["feature_names"], Path(checkpoint_path).name,
                       capture.schema, capture.feature_names, name)
        real_inputs.append((name, capture.features))
    return export_model(model, meta, out_path, real_inputs)
