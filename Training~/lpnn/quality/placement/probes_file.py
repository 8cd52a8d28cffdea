"""`*.probes.json` (Documentation~/file-formats.md): world-space probe positions the editor imports."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from ...core.atomic import write_text_atomic

FORMAT_NAME = "lpnn.probes"
FORMAT_VERSION = 1


def _shortest(value: np.float32) -> float:
    """The shortest decimal that reads back as the same float32 (numpy's float32 repr)."""
    return float(str(np.float32(value)))


def probes_json(positions: np.ndarray, units: str, source: dict[str, Any]) -> str:
    points = np.asarray(positions, dtype=np.float32).reshape(-1, 3)
    if not np.all(np.isfinite(points)):
        raise ValueError("probe positions must be finite")
    document = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "units": units,
        "space": "world",
        "count": int(points.shape[0]),
        "positions": [[_shortest(c) for c in row] for row in points],
        "source": source,
    }
    return json.dumps(document, ensure_ascii=False, allow_nan=False) + "\n"


def write_probes_json(path: str | os.PathLike, positions: np.ndarray, units: str, source: dict[str, Any]) -> Path:
    """Atomic, culture-invariant ('.' decimals, no separators) UTF-8 JSON."""
    return write_text_atomic(path, probes_json(positions, units, source))
