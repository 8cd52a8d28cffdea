"""The capture file's JSON header: parsed and checked field by field (C#: Captures/CaptureHeader.cs)."""

from __future__ import annotations

import json
import struct
from typing import Any

import numpy as np

from .capture import CaptureError
from .capture_format import (
    FORMAT_NAME,
    FORMAT_VERSION,
    KNOWN_HEADER_KEYS,
    MAGIC,
    PREAMBLE_BYTES,
    SH_CONVENTION,
    TRAILER_BYTES,
)
from .schema import schema_by_id


class Problems:
    """Collects problems; raises on the first one unless collecting all (validate mode)."""

    def __init__(self, collect_all: bool):
        self.collect_all = collect_all
        self.items: list[str] = []

    def add(self, message: str) -> None:
        if not self.collect_all:
            raise CaptureError(message)
        self.items.append(message)


def parse_header(name: str, data: bytes, problems: Problems) -> tuple[dict[str, Any] | None, int]:
    if len(data) < PREAMBLE_BYTES + TRAILER_BYTES:
        problems.add(f"{name}: file is {len(data):,} bytes, too short for a capture (truncated?)")
        return None, 0
    if data[:8] != MAGIC:
        problems.add(f"{name}: byte 0: not a capture (magic is {data[:8]!r}, expected {MAGIC!r})")
        return None, 0
    version, header_length = struct.unpack_from("<II", data, 8)
    if version != FORMAT_VERSION:
        problems.add(f"{name}: byte 8: format version {version} is not supported (this reader knows {FORMAT_VERSION})")
        return None, 0
    if PREAMBLE_BYTES + header_length > len(data) - TRAILER_BYTES:
        problems.add(f"{name}: byte 12: header length {header_length:,} runs past the end of the {len(data):,}-byte file (truncated?)")
        return None, 0
    raw = data[PREAMBLE_BYTES:PREAMBLE_BYTES + header_length]
    try:
        text = raw.decode("utf-8")
        header = json.loads(text)
    except UnicodeDecodeError as exc:
        problems.add(f"{name}: header byte {exc.start}: not UTF-8")
        return None, 0
    except json.JSONDecodeError as exc:
        problems.add(f"{name}: header line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}")
        return None, 0
    if not isinstance(header, dict):
        problems.add(f"{name}: header: expected a JSON object")
        return None, 0
    return header, PREAMBLE_BYTES + header_length


def is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def is_number(value: Any) -> bool:
    return (isinstance(value, (int, float)) and not isinstance(value, bool)) and np.isfinite(value)


def check_header(name: str, header: dict[str, Any], problems: Problems) -> bool:
    ok = True

    def bad(key: str, message: str) -> None:
        nonlocal ok
        ok = False
        problems.add(f"{name}: header: field '{key}': {message}")

    for key in KNOWN_HEADER_KEYS:
        if key not in header:
            bad(key, "missing")
    if not ok:
        return False
    if header["format"] != FORMAT_NAME:
        bad("format", f"{header['format']!r} is not {FORMAT_NAME!r}")
    if header["version"] != FORMAT_VERSION:
        bad("version", f"{header['version']!r} does not match the binary version {FORMAT_VERSION}")
    if not is_int(header["point_count"]) or header["point_count"] < 1:
        bad("point_count", f"{header['point_count']!r} is not an integer >= 1")
    if not isinstance(header["schema"], str) or not header["schema"]:
        bad("schema", "must be a non-empty string")
    names = header["feature_names"]
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        bad("feature_names", "must be a non-empty list of non-empty strings")
    elif len(set(names)) != len(names):
        duplicates = sorted({n for n in names if names.count(n) > 1})
        bad("feature_names", f"duplicate names {duplicates}")
    elif isinstance(header["schema"], str):
        known = schema_by_id(header["schema"])
        if known is not None and tuple(names) != known.names:
            bad("feature_names", f"do not match schema {known.id!r} ({known.feature_count} names)")
    if not is_number(header["cell_size"]) or header["cell_size"] <= 0:
        bad("cell_size", f"{header['cell_size']!r} is not a finite number > 0")
    if not isinstance(header["units"], str):
        bad("units", "must be a string")
    if not is_number(header["lighting_scale"]) or header["lighting_scale"] <= 0:
        bad("lighting_scale", f"{header['lighting_scale']!r} is not a finite number > 0")
    if header["sh_convention"] != SH_CONVENTION:
        bad("sh_convention", f"{header['sh_convention']!r} is not {SH_CONVENTION!r}")
    if header["label_source"] is not None and not isinstance(header["label_source"], str):
        bad("label_source", "must be a string or null")
    if not isinstance(header["source"], dict):
        bad("source", "must be an object")
    sections = header["sections"]
    if not isinstance(sections, list):
        bad("sections", "must be a list")
        return False
    return ok
