"""What a trained model records about itself: the checkpoint metadata, which becomes the card's
`normalisation`, `architecture`, `training` and `metrics` sections at export."""

from __future__ import annotations

from typing import Any

from .config import config_to_dict
from .model import architecture_summary
from .trainer import TrainResult

CHECKPOINT_FORMAT = "lpnn.checkpoint"
CHECKPOINT_VERSION = 1


def training_section(result: TrainResult, batchnorm: dict[str, Any] | None) -> dict[str, Any]:
    train, validation = result.split.train, result.split.validation
    sources = sorted({c.label_source for c in train + validation})
    config = result.config
    return {
        "captures": [c.name for c in train],
        "held_out": [c.name for c in validation],
        "label_source": "; ".join(sources),
        "label_sources": sources,
        "seed": config.seed,
        "epochs": result.epochs_run,
        "best_epoch": result.best_epoch,
        "max_epochs": config.epochs,
        "stopped_early": result.stopped_early,
        "steps_per_epoch": config.steps_per_epoch,
        "points": sum(c.point_count for c in train),
        "positives": sum(c.positives for c in train),
        "validation_points": sum(c.point_count for c in validation),
        "validation_positives": sum(c.positives for c in validation),
        "loss": config.loss,
        "positive_weight": result.positive_weight,
        "constant_features": list(result.normalisation.constant_features),
        "batchnorm_check": batchnorm,
        "config": config_to_dict(config),
        "history": result.history,
    }


def checkpoint_meta(result: TrainResult, batchnorm: dict[str, Any] | None = None) -> dict[str, Any]:
    """Everything export needs besides the weights; JSON-ready."""
    first = result.split.train[0]
    return {
        "format": CHECKPOINT_FORMAT,
        "version": CHECKPOINT_VERSION,
        "schema": first.schema,
        "feature_names": list(first.feature_names),
        "model": config_to_dict(result.config)["model"],
        "seed": result.config.seed,
        "normalisation": {
            "mean": result.normalisation.mean.tolist(),
            "std": result.normalisation.std.tolist(),
        },
        "architecture": architecture_summary(result.model),
        "training": training_section(result, batchnorm),
        "metrics": {
            "validation": {
                **{k: v for k, v in result.validation.items() if k != "per_capture"},
                "monitor": result.config.monitor,
                "best_epoch": result.best_epoch,
                "per_capture": result.validation.get("per_capture", {}),
            }
        },
    }
