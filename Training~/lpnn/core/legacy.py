"""The thesis' `features.txt` / `comparisons.txt` (Documentation~/file-formats.md, "Legacy thesis files").

features.txt: the first non-blank line starts with the integer F (values per point); then one block
per point, blocks separated by blank lines, numbers separated by whitespace, decimal separator '.' or
',' (the thesis wrote the machine's locale: `0,0226`, `2,338238E-05`). comparisons.txt: one
True/False per line. Converted captures use schema `lpnn.thesis30`.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InvalidInputError
from .capture import Capture
from .schema import THESIS30

# One decimal number, '.' or ',' as the decimal separator, optional exponent; no thousands separators,
# no NaN/Infinity (a feature must be finite), no '_' digit grouping (which float() would accept).
_NUMBER = re.compile(r"[+-]?(?:\d+(?:[.,]\d*)?|[.,]\d+)(?:[eE][+-]?\d+)?")
_COUNT = re.compile(r"\+?\d+")
_LABELS = {"true": 1, "false": 0}


class LegacyFormatError(InvalidInputError):
    """A legacy file does not follow the thesis layout; the message names file, line and value."""


@dataclass(frozen=True)
class LegacyFeatures:
    values: np.ndarray  # (M, F) float64
    first_lines: np.ndarray  # (M,) int64: 1-based line where each point's block starts


def _lines(path: Path) -> list[str]:
    try:
        return path.read_text(encoding="utf-8-sig").splitlines()
    except UnicodeDecodeError as exc:
        raise LegacyFormatError(f"{path}: byte {exc.start}: not UTF-8 text") from exc
    except OSError as exc:
        raise LegacyFormatError(f"{path}: cannot read: {exc.strerror or exc}") from exc


def _parse_number(token: str, path: Path, line: int) -> float:
    if not _NUMBER.fullmatch(token):
        raise LegacyFormatError(f"{path}: line {line}: {token!r} is not a finite decimal number")
    value = float(token.replace(",", "."))
    if not np.isfinite(np.float32(value)):
        raise LegacyFormatError(f"{path}: line {line}: {token!r} is too large for a float32 feature")
    return value


def read_legacy_features(path: str | os.PathLike) -> LegacyFeatures:
    """All feature blocks of a thesis features.txt; errors name the file, the line and the count found."""
    file = Path(path)
    lines = _lines(file)
    header = next((number for number, text in enumerate(lines) if text.strip()), None)
    if header is None:
        raise LegacyFormatError(f"{file}: the file is empty; expected the feature count F on the first line")
    tokens = lines[header].split()
    if not _COUNT.fullmatch(tokens[0]) or int(tokens[0]) < 1:
        raise LegacyFormatError(f"{file}: line {header + 1}: {tokens[0]!r} is not the feature count F (an integer >= 1)")
    count = int(tokens[0])
    blocks: list[list[float]] = []
    first_lines: list[int] = []
    current: list[float] = []
    start = 0

    def close_block() -> None:
        if len(current) != count:
            raise LegacyFormatError(f"{file}: line {start}: the block starting here has {len(current)} values, "
                                    f"expected F = {count}")
        blocks.append(list(current))
        first_lines.append(start)

    # Anything after F on its line is ignored, as the thesis' own reader did (file-formats.md).
    rest = [(number + 1, text.split()) for number, text in enumerate(lines) if number > header]
    for line, words in rest:
        if not words:
            if current:
                close_block()
                current = []
            continue
        if not current:
            start = line
        current.extend(_parse_number(word, file, line) for word in words)
    if current:
        close_block()
    if not blocks:
        raise LegacyFormatError(f"{file}: no feature blocks after the feature count F = {count} on line {header + 1}")
    return LegacyFeatures(values=np.asarray(blocks, dtype=np.float64), first_lines=np.asarray(first_lines, np.int64))


def read_legacy_labels(path: str | os.PathLike) -> np.ndarray:
    """comparisons.txt: one True/False per line (case-insensitive, blank lines ignored) -> (M,) uint8."""
    file = Path(path)
    labels: list[int] = []
    for number, text in enumerate(_lines(file), start=1):
        word = text.strip()
        if not word:
            continue
        if word.lower() not in _LABELS:
            raise LegacyFormatError(f"{file}: line {number}: {word!r} is not True or False")
        labels.append(_LABELS[word.lower()])
    return np.asarray(labels, dtype=np.uint8)


def legacy_to_capture(features_path: str | os.PathLike, labels_path: str | os.PathLike | None,
                      scene_name: str) -> Capture:
    """A `lpnn.thesis30` capture: ids (index, 0, 0), positions (index, 0, 0), SH zero, cell size 1,
    lighting scale 1, source.legacy = true."""
    features_file = Path(features_path)
    legacy = read_legacy_features(features_file)
    points, count = legacy.values.shape
    if count != THESIS30.feature_count:
        raise LegacyFormatError(f"{features_file}: line {int(legacy.first_lines[0])}: F = {count} values per point, "
                                f"but the thesis layout {THESIS30.id!r} has {THESIS30.feature_count}")
    labels = None
    label_source = None
    # Same keys, same order as the C# converter, so both write the same bytes.
    source: dict[str, str | bool] = {"legacy": True, "scene": scene_name, "features_file": features_file.name}
    if labels_path is not None:
        labels_file = Path(labels_path)
        labels = read_legacy_labels(labels_file)
        if labels.shape[0] != points:
            raise LegacyFormatError(f"{labels_file}: {labels.shape[0]:,} labels, but {features_file} has {points:,} "
                                    "feature blocks; the two files must describe the same points")
        label_source = f"legacy:{labels_file.name}"
    index = np.arange(points, dtype=np.int64)
    ids = np.zeros((points, 3), dtype=np.int32)
    ids[:, 0] = index
    positions = np.zeros((points, 3), dtype=np.float32)
    positions[:, 0] = index
    return Capture(ids=ids, positions=positions, sh=np.zeros((points, 27), dtype=np.float32),
                   features=legacy.values.astype(np.float32), schema=THESIS30.id, feature_names=list(THESIS30.names),
                   cell_size=1.0, lighting_scale=1.0, labels=labels, label_source=label_source, source=source)
