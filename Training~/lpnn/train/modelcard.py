"""The model card (`<model>.card.json` beside `<model>.onnx`, Documentation~/model-contract.md).

Read by Unity and by `OnnxScorer` before scoring; this module stays free of TensorFlow.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from ..errors import UserError
from ..core.atomic import write_text_atomic

CARD_FORMAT = "lpnn.modelcard"
CARD_VERSION = 1
CARD_SUFFIX = ".card.json"
INPUT_NAME = "features"
OUTPUT_NAME = "importance"
OPSET = 15


def card_path(model_path: str | os.PathLike) -> Path:
    """`dir/name.onnx` -> `dir/name.card.json`."""
    return Path(model_path).with_suffix(CARD_SUFFIX)


def json_ready(value: Any) -> Any:
    """NaN/inf -> null (JSON has no NaN), tuples -> lists, numpy scalars -> Python numbers."""
    if isinstance(value, dict):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(v) for v in value]
    if hasattr(value, "item") and callable(value.item) and getattr(value, "ndim", None) == 0:
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


@dataclass(frozen=True)
class ModelCard:
    """Field order = key order of the JSON file (model-contract.md)."""

    format: str
    version: int
    model_file: str
    schema: str
    feature_names: list[str]
    feature_count: int
    input: dict[str, Any]
    output: dict[str, Any]
    opset: int
    ops: list[str]
    normalisation: dict[str, Any]
    architecture: dict[str, Any]
    training: dict[str, Any]
    metrics: dict[str, Any]
    versions: dict[str, Any]
    parity: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        return json_ready(dataclasses.asdict(self))

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2, ensure_ascii=False, allow_nan=False) + "\n"

    def write(self, path: str | os.PathLike) -> Path:
        return write_text_atomic(path, self.to_json())

    @classmethod
    def from_dict(cls, values: Any, where: str) -> "ModelCard":
        if not isinstance(values, dict):
            raise UserError(f"{where}: a model card must be a JSON object")
        names = [f.name for f in dataclasses.fields(cls)]
        missing = [n for n in names if n not in values]
        if missing:
            raise UserError(f"{where}: model card is missing {missing}")
        if values["format"] != CARD_FORMAT or values["version"] != CARD_VERSION:
            raise UserError(f"{where}: format {values['format']!r} version {values['version']!r} is not "
                            f"{CARD_FORMAT!r} version {CARD_VERSION}")
        card = cls(**{n: values[n] for n in names})
        feature_names = card.feature_names
        if not isinstance(feature_names, list) or not all(isinstance(n, str) for n in feature_names):
            raise UserError(f"{where}: 'feature_names' must be a list of strings")
        if card.feature_count != len(feature_names):
            raise UserError(f"{where}: 'feature_count' {card.feature_count} differs from the "
                            f"{len(feature_names)} feature names")
        return card

    @classmethod
    def read(cls, path: str | os.PathLike) -> "ModelCard":
        file = Path(path)
        try:
            values = json.loads(file.read_text(encoding="utf-8"))
        except FileNotFoundError as exc:
            raise UserError(f"{file}: model card not found; a model needs its card beside it "
                            "(written by `lpnn train` / `lpnn export`)") from exc
        except OSError as exc:
            raise UserError(f"{file}: cannot read the model card: {exc.strerror or exc}") from exc
        except json.JSONDecodeError as exc:
            raise UserError(f"{file}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from exc
        return cls.from_dict(values, str(file))


def schema_mismatch(reference: str, reference_schema: str, reference_names: Sequence[str],
                    other: str, other_schema: str, other_names: Sequence[str]) -> str | None:
    """Why the features of `other` cannot stand in for those of `reference`, naming both; None if they can."""
    expected, names = list(reference_names), list(other_names)
    if reference_schema != other_schema or len(expected) != len(names):
        return (f"{other} has schema '{other_schema}' ({len(names)} features) but {reference} has schema "
                f"'{reference_schema}' ({len(expected)} features)")
    if names != expected:
        index = next(i for i, (a, b) in enumerate(zip(expected, names)) if a != b)
        return (f"{other} and {reference} both use schema '{other_schema}', but feature {index} is "
                f"'{names[index]}' in {other} and '{expected[index]}' in {reference}")
    return None


def check_features(model_schema: str, model_feature_names: Sequence[str], model_name: str,
                   schema: str, feature_names: Sequence[str], source: str) -> None:
    """Features of `schema` must be what the model reads (its card or checkpoint); the error names both."""
    problem = schema_mismatch(f"the model '{model_name}'", model_schema, model_feature_names,
                              source, schema, feature_names)
    if problem:
        raise UserError(f"{problem}; score with a model trained on '{schema}', or extract '{model_schema}' features")
