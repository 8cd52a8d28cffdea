"""The capture (*.lpnncap, Documentation~/file-formats.md): one evaluation grid of one scene — ids, positions, SH,
features, optional labels and metadata — and its error. The file format is split as the C# core's
(Lpnn.Probes.Core.Captures): capture_format (constants), capture_header (the JSON header), capture_content (value
checks), capture_encoder / capture_decoder (bytes), capture_file (read, validate, write, append, datasets).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import InvalidInputError


class CaptureError(InvalidInputError):
    """A capture could not be read or written; the message names file, record/field and problem."""


@dataclass
class Capture:
    ids: np.ndarray  # (N, 3) int32 lattice ids, grid order
    positions: np.ndarray  # (N, 3) float32
    sh: np.ndarray  # (N, 27) float32
    features: np.ndarray  # (N, F) float32
    schema: str
    feature_names: list[str]
    cell_size: float
    lighting_scale: float
    units: str = "m"
    labels: np.ndarray | None = None  # (N,) uint8 in {0, 1}
    label_source: str | None = None
    source: dict[str, Any] = field(default_factory=dict)
    extra_sections: dict[str, np.ndarray] = field(default_factory=dict)
    extra_header: dict[str, Any] = field(default_factory=dict)

    @property
    def point_count(self) -> int:
        return int(self.ids.shape[0])

    @property
    def feature_count(self) -> int:
        return int(self.features.shape[1])

    def with_labels(self, labels: np.ndarray, label_source: str) -> "Capture":
        return replace(self, labels=np.asarray(labels, dtype=np.uint8), label_source=label_source)
