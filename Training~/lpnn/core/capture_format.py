"""The capture file's constants (Documentation~/file-formats.md; C#: Captures/CaptureFormat.cs)."""

from __future__ import annotations

import numpy as np

MAGIC = b"LPNNCAP\x00"
END_MAGIC = b"LPNNEND\x00"
FORMAT_NAME = "lpnn.capture"
FORMAT_VERSION = 1
SH_CONVENTION = "unity.SphericalHarmonicsL2"
EXTENSION = ".lpnncap"
PREAMBLE_BYTES = 16
TRAILER_BYTES = 16

DTYPES: dict[str, np.dtype] = {
    "int32": np.dtype("<i4"),
    "float32": np.dtype("<f4"),
    "uint8": np.dtype("u1"),
}
REQUIRED_SECTIONS = ("ids", "positions", "sh", "features")
KNOWN_HEADER_KEYS = (
    "format", "version", "point_count", "schema", "feature_names", "cell_size", "units",
    "lighting_scale", "sh_convention", "label_source", "source", "sections",
)
SH_CHANNELS = "rgb"


def pad8(n: int) -> int:
    return (-n) % 8
