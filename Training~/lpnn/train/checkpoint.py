"""Checkpoints (`*.ckpt.npz`): every weight of the model (incl. BatchNorm running statistics and
the normalisation constants) plus the JSON metadata needed to rebuild and export it."""

from __future__ import annotations

import io
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import UserError
from ..core.atomic import write_bytes_atomic
from .config import model_config_from_dict
from .model import MODEL_NAME, PointNet
from .modelcard import json_ready
from .summary import CHECKPOINT_FORMAT, CHECKPOINT_VERSION

META_KEY = "meta_json"
CHECKPOINT_SUFFIX = ".ckpt.npz"


def default_checkpoint_path(model_path: str | os.PathLike) -> Path:
    """`dir/name.onnx` -> `dir/name.ckpt.npz`."""
    return Path(model_path).with_suffix(CHECKPOINT_SUFFIX)


def _weight_key(index: int) -> str:
    return f"w{index:03d}"


def _relative_path(variable: Any) -> str:
    """Variable path without the model's own prefix, so any PointNet instance matches."""
    return variable.path.removeprefix(f"{MODEL_NAME}/")


def save_checkpoint(path: str | os.PathLike, model: PointNet, meta: dict[str, Any]) -> Path:
    meta = {**meta, "weights": [_relative_path(w) for w in model.weights]}
    text = json.dumps(json_ready(meta), ensure_ascii=False, allow_nan=False)
    arrays = {META_KEY: np.frombuffer(text.encode("utf-8"), dtype=np.uint8)}
    arrays.update({_weight_key(i): w.numpy() for i, w in enumerate(model.weights)})
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return write_bytes_atomic(path, buffer.getvalue())


def load_checkpoint(path: str | os.PathLike) -> tuple[PointNet, dict[str, Any]]:
    """Rebuilds the model from a checkpoint; UserError when the file is not one or does not fit."""
    file = Path(path)
    try:
        with np.load(file, allow_pickle=False) as archive:
            arrays = {key: archive[key] for key in archive.files}
    except FileNotFoundError as exc:
        raise UserError(f"{file}: checkpoint not found") from exc
    except (OSError, ValueError) as exc:
        raise UserError(f"{file}: not a checkpoint (.ckpt.npz written by `lpnn train`): {exc}") from exc
    if META_KEY not in arrays:
        raise UserError(f"{file}: not a checkpoint: no '{META_KEY}' entry")
    meta = json.loads(arrays[META_KEY].tobytes().decode("utf-8"))
    if meta.get("format") != CHECKPOINT_FORMAT or meta.get("version") != CHECKPOINT_VERSION:
        raise UserError(f"{file}: format {meta.get('format')!r} version {meta.get('version')!r} is not "
                        f"{CHECKPOINT_FORMAT!r} version {CHECKPOINT_VERSION}")
    config = model_config_from_dict(meta["model"], f"{file}: model")
    normalisation = meta["normalisation"]
    model = PointNet(config, np.asarray(normalisation["mean"], np.float32), np.asarray(normalisation["std"], np.float32),
                     seed=int(meta["seed"]))
    expected = [_relative_path(w) for w in model.weights]
    if meta["weights"] != expected:
        raise UserError(f"{file}: weights {meta['weights']} do not match the architecture's {expected}")
    values = [arrays[_weight_key(i)] for i in range(len(expected))]
    shapes = [tuple(w.shape) for w in model.weights]
    if [v.shape for v in values] != shapes:
        raise UserError(f"{file}: weight shapes {[v.shape for v in values]} differ from the architecture's {shapes}")
    model.set_weights(values)
    return model, meta
