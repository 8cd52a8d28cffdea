"""A capture's exact file bytes (C#: Captures/CaptureEncoder.cs)."""

from __future__ import annotations

import json
import struct
import zlib
from typing import Any

import numpy as np

from .capture import Capture, CaptureError
from .capture_content import content_problems
from .capture_format import DTYPES, END_MAGIC, FORMAT_NAME, FORMAT_VERSION, MAGIC, PREAMBLE_BYTES, SH_CONVENTION, pad8


def _sections(capture: Capture) -> list[tuple[str, np.ndarray]]:
    sections: list[tuple[str, np.ndarray]] = [
        ("ids", np.ascontiguousarray(capture.ids, dtype="<i4")),
        ("positions", np.ascontiguousarray(capture.positions, dtype="<f4")),
        ("sh", np.ascontiguousarray(capture.sh, dtype="<f4")),
        ("features", np.ascontiguousarray(capture.features, dtype="<f4")),
    ]
    if capture.labels is not None:
        sections.append(("labels", np.ascontiguousarray(capture.labels, dtype="u1")))
    for name, array in capture.extra_sections.items():
        sections.append((name, np.ascontiguousarray(array)))
    return sections


def _dtype_name(array: np.ndarray) -> str:
    for name, dtype in DTYPES.items():
        if array.dtype == dtype or array.dtype == dtype.newbyteorder("="):
            return name
    raise CaptureError(f"section dtype {array.dtype} is not one of int32, float32, uint8")


def encode_capture(capture: Capture) -> bytes:
    """The exact bytes of a capture file. Validates the content first (nothing invalid is written)."""
    problems = content_problems(capture, "<capture being written>", stop_at_first=True)
    if problems:
        raise CaptureError(problems[0])
    sections = _sections(capture)
    header: dict[str, Any] = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "point_count": capture.point_count,
        "schema": capture.schema,
        "feature_names": list(capture.feature_names),
        "cell_size": float(capture.cell_size),
        "units": capture.units,
        "lighting_scale": float(capture.lighting_scale),
        "sh_convention": SH_CONVENTION,
        "label_source": capture.label_source,
        "source": dict(capture.source),
        "sections": [
            {"name": name, "dtype": _dtype_name(array), "shape": list(array.shape)} for name, array in sections
        ],
    }
    for key, value in capture.extra_header.items():
        if key not in header:
            header[key] = value
    try:
        header_text = json.dumps(header, ensure_ascii=False, allow_nan=False, separators=(", ", ": "))
    except ValueError as exc:
        raise CaptureError(f"<capture being written>: header: {exc}") from exc
    header_bytes = header_text.encode("utf-8")
    header_bytes += b" " * pad8(PREAMBLE_BYTES + len(header_bytes))
    parts = [MAGIC, struct.pack("<II", FORMAT_VERSION, len(header_bytes)), header_bytes]
    for _, array in sections:
        raw = array.tobytes(order="C")
        parts.append(raw)
        parts.append(b"\x00" * pad8(len(raw)))
    body = b"".join(parts)
    crc = zlib.crc32(body) & 0xFFFFFFFF
    return body + struct.pack("<II", crc, 0) + END_MAGIC
