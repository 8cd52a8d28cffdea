"""A capture from file bytes: the sections the header describes, checked against the bytes (C#:
Captures/CaptureDecoder.cs)."""

from __future__ import annotations

import struct
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from .capture import Capture
from .capture_format import DTYPES, END_MAGIC, KNOWN_HEADER_KEYS, REQUIRED_SECTIONS, TRAILER_BYTES, pad8
from .capture_header import Problems, check_header, is_int, parse_header


def expected_shape(section: str, n: int, f: int) -> tuple[int, ...] | None:
    return {"ids": (n, 3), "positions": (n, 3), "sh": (n, 27), "features": (n, f), "labels": (n,)}.get(section)


def read_sections(name: str, data: bytes, header: dict[str, Any], start: int,
                   problems: Problems) -> dict[str, np.ndarray] | None:
    n = header["point_count"]
    f = len(header["feature_names"])
    arrays: dict[str, np.ndarray] = {}
    layout: list[tuple[str, np.dtype, tuple[int, ...]]] = []
    seen: set[str] = set()
    ok = True
    for position, entry in enumerate(header["sections"]):
        where = f"{name}: header: sections[{position}]"
        if not isinstance(entry, dict) or not {"name", "dtype", "shape"} <= set(entry):
            problems.add(f"{where}: needs 'name', 'dtype' and 'shape'")
            ok = False
            continue
        section, dtype_name, shape = entry["name"], entry["dtype"], entry["shape"]
        if not isinstance(section, str) or section in seen:
            problems.add(f"{where}: name {section!r} is missing or repeated")
            ok = False
            continue
        seen.add(section)
        if dtype_name not in DTYPES:
            problems.add(f"{where} ('{section}'): dtype {dtype_name!r} is not one of {sorted(DTYPES)}")
            ok = False
            continue
        if not isinstance(shape, list) or not shape or not all(is_int(d) and d >= 0 for d in shape):
            problems.add(f"{where} ('{section}'): shape {shape!r} is not a list of non-negative integers")
            ok = False
            continue
        expected = expected_shape(section, n, f)
        expected_dtype = {"ids": "int32", "labels": "uint8"}.get(section, "float32")
        if expected is not None and (tuple(shape) != expected or dtype_name != expected_dtype):
            problems.add(f"{where} ('{section}'): is {dtype_name} {shape}, expected {expected_dtype} {list(expected)}")
            ok = False
            continue
        if expected is None and shape[0] != n:
            problems.add(f"{where} ('{section}'): first dimension {shape[0]} is not point_count {n}")
            ok = False
            continue
        layout.append((section, DTYPES[dtype_name], tuple(shape)))
    for required in REQUIRED_SECTIONS:
        if required not in seen:
            problems.add(f"{name}: header: sections: required section '{required}' is missing")
            ok = False
    if "labels" in seen and header.get("label_source") is None:
        problems.add(f"{name}: header: field 'label_source': must be set when a 'labels' section exists")
    if not ok:
        return None
    described = start
    for _, dtype, shape in layout:
        size = int(np.prod(shape)) * dtype.itemsize
        described += size + pad8(size)
    described += TRAILER_BYTES
    if described != len(data):
        problems.add(
            f"{name}: file is {len(data):,} bytes but the header describes {described:,} bytes"
            + (" (truncated?)" if len(data) < described else " (trailing bytes?)")
        )
        return None
    if data[-8:] != END_MAGIC:
        problems.add(f"{name}: byte {len(data) - 8:,}: end marker is {data[-8:]!r}, expected {END_MAGIC!r}")
        return None
    stored_crc = struct.unpack_from("<I", data, len(data) - TRAILER_BYTES)[0]
    actual_crc = zlib.crc32(memoryview(data)[: len(data) - TRAILER_BYTES]) & 0xFFFFFFFF
    if stored_crc != actual_crc:
        problems.add(f"{name}: byte {len(data) - TRAILER_BYTES:,}: CRC-32 {stored_crc:08x} does not match the content ({actual_crc:08x}): the file is corrupt")
        return None
    offset = start
    for section, dtype, shape in layout:
        count = int(np.prod(shape))
        arrays[section] = np.frombuffer(data, dtype=dtype, count=count, offset=offset).reshape(shape).copy()
        size = count * dtype.itemsize
        offset += size + pad8(size)
    return arrays


def decode(path: Path, data: bytes, problems: Problems) -> Capture | None:
    name = str(path)
    header, start = parse_header(name, data, problems)
    if header is None or not check_header(name, header, problems):
        return None
    arrays = read_sections(name, data, header, start, problems)
    if arrays is None:
        return None
    extra_sections = {k: v for k, v in arrays.items() if k not in REQUIRED_SECTIONS + ("labels",)}
    return Capture(
        ids=arrays["ids"],
        positions=arrays["positions"],
        sh=arrays["sh"],
        features=arrays["features"],
        labels=arrays.get("labels"),
        schema=header["schema"],
        feature_names=list(header["feature_names"]),
        cell_size=float(header["cell_size"]),
        units=header["units"],
        lighting_scale=float(header["lighting_scale"]),
        label_source=header["label_source"],
        source=dict(header["source"]),
        extra_sections=extra_sections,
        extra_header={k: v for k, v in header.items() if k not in KNOWN_HEADER_KEYS},
    )
