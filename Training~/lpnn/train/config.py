"""Training and architecture options: defaults, JSON config files, validation of values."""

from __future__ import annotations

import dataclasses
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import UserError

LOSSES = ("weighted_bce", "focal")
POINTWISE_LAYERS = ("dense", "conv1d")


@dataclass(frozen=True)
class ModelConfig:
    """PointNet-style network. Defaults sized for <= 30 ms per 10k points in onnxruntime, 2 cores."""

    trunk: tuple[int, ...] = (32, 64, 64)  # shared per-point layers (1x1, BatchNorm, ReLU)
    head: tuple[int, ...] = (64, 32)  # per-point layers after [local, global max, global mean]
    dropout: float = 0.2
    batchnorm_momentum: float = 0.95  # EMA time constant ~20 steps: settles within one epoch
    pointwise: str = "dense"  # "dense" (MatMul) or "conv1d" (Conv): the same 1x1 map, see training.md


@dataclass(frozen=True)
class TrainConfig:
    seed: int = 0
    epochs: int = 60  # maximum; early stopping usually ends sooner
    steps_per_epoch: int = 40
    batch_clouds: int = 8  # clouds (crops of captures) per gradient step
    max_points: int = 4096  # points per cloud after subsampling (bounds batch memory)
    min_points: int = 64  # smallest crop accepted
    crop_probability: float = 0.8  # else the whole capture (still subsampled)
    crop_min_fraction: float = 0.3  # smallest crop edge, as a fraction of the capture's id range
    subsample_min_fraction: float = 0.5  # keep between this fraction and all of a crop's points
    learning_rate: float = 1e-3
    loss: str = "weighted_bce"
    focal_gamma: float = 2.0
    patience: int = 10  # epochs without improvement of `monitor` before stopping
    min_delta: float = 1e-4
    monitor: str = "pr_auc_mean"
    val_fraction: float = 0.2  # captures held out when no explicit validation list is given
    threads: int = 2  # TensorFlow intra-op threads; bit-identical reruns need the same count
    model: ModelConfig = field(default_factory=ModelConfig)

    def validated(self) -> "TrainConfig":
        """Self, after checking every value; raises UserError naming the bad option."""
        positive_ints = ("epochs", "steps_per_epoch", "batch_clouds", "max_points", "min_points", "threads")
        for name in positive_ints:
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value < 1:
                raise UserError(f"config '{name}': {value!r} must be an integer >= 1")
        if not isinstance(self.seed, int) or isinstance(self.seed, bool) or not 0 <= self.seed < 2**31:
            raise UserError(f"config 'seed': {self.seed!r} must be an integer in [0, 2^31)")
        if self.patience < 1:
            raise UserError(f"config 'patience': {self.patience!r} must be >= 1")
        if self.min_points > self.max_points:
            raise UserError(f"config 'min_points' ({self.min_points}) must not exceed 'max_points' ({self.max_points})")
        fractions = {
            "crop_probability": (0.0, 1.0), "crop_min_fraction": (1e-6, 1.0),
            "subsample_min_fraction": (1e-6, 1.0), "val_fraction": (0.0, 0.9),
        }
        for name, (low, high) in fractions.items():
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and low <= value <= high):
                raise UserError(f"config '{name}': {value!r} must be a number in [{low}, {high}]")
        for name in ("learning_rate", "focal_gamma", "min_delta"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise UserError(f"config '{name}': {value!r} must be a finite number >= 0")
        if self.learning_rate <= 0:
            raise UserError(f"config 'learning_rate': {self.learning_rate!r} must be > 0")
        if self.loss not in LOSSES:
            raise UserError(f"config 'loss': {self.loss!r} is not one of {list(LOSSES)}")
        model = self.model
        for name in ("trunk", "head"):
            widths = getattr(model, name)
            if not widths or not all(isinstance(w, int) and not isinstance(w, bool) and w >= 1 for w in widths):
                raise UserError(f"config 'model.{name}': {list(widths)!r} must be a non-empty list of integers >= 1")
        if not 0.0 <= model.dropout < 1.0:
            raise UserError(f"config 'model.dropout': {model.dropout!r} must be in [0, 1)")
        if not 0.0 <= model.batchnorm_momentum < 1.0:
            raise UserError(f"config 'model.batchnorm_momentum': {model.batchnorm_momentum!r} must be in [0, 1)")
        if model.pointwise not in POINTWISE_LAYERS:
            raise UserError(f"config 'model.pointwise': {model.pointwise!r} is not one of {list(POINTWISE_LAYERS)}")
        return self


def _replace_checked(instance: Any, values: dict[str, Any], where: str) -> Any:
    known = {f.name for f in dataclasses.fields(instance)}
    unknown = sorted(set(values) - known)
    if unknown:
        raise UserError(f"{where}: unknown option(s) {unknown}; known: {sorted(known)}")
    return dataclasses.replace(instance, **values)


def model_config_from_dict(values: dict[str, Any], where: str = "model config") -> ModelConfig:
    converted = dict(values)
    for name in ("trunk", "head"):
        if name in converted:
            if not isinstance(converted[name], (list, tuple)):
                raise UserError(f"{where}: '{name}' must be a list of layer widths, got {converted[name]!r}")
            converted[name] = tuple(converted[name])
    return _replace_checked(ModelConfig(), converted, where)


def config_from_dict(values: dict[str, Any], base: TrainConfig | None = None, where: str = "config") -> TrainConfig:
    """A TrainConfig from `base` (default: the defaults) with `values` applied; 'model' may be nested."""
    base = base or TrainConfig()
    values = dict(values)
    if "model" in values:
        model_values = values.pop("model")
        if not isinstance(model_values, dict):
            raise UserError(f"{where}: 'model' must be an object")
        merged = {**config_to_dict(base)["model"], **model_values}
        values["model"] = model_config_from_dict(merged, f"{where}: model")
    return _replace_checked(base, values, where).validated()


def load_config(path: str | os.PathLike) -> TrainConfig:
    file = Path(path)
    try:
        values = json.loads(file.read_text(encoding="utf-8"))
    except OSError as exc:
        raise UserError(f"{file}: cannot read the config: {exc.strerror or exc}") from exc
    except json.JSONDecodeError as exc:
        raise UserError(f"{file}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from exc
    if not isinstance(values, dict):
        raise UserError(f"{file}: a config must be a JSON object of options")
    return config_from_dict(values, where=str(file))


def config_to_dict(config: TrainConfig) -> dict[str, Any]:
    """JSON-ready (tuples become lists), in field order."""
    result = dataclasses.asdict(config)
    result["model"]["trunk"] = list(config.model.trunk)
    result["model"]["head"] = list(config.model.head)
    return result
