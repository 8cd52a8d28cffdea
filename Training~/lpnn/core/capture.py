"""Capture files (*.lpnncap, Documentation~/file-formats.md): read, validate, write, append.

A capture is one evaluation grid of one scene: ids, positions, SH, features, optional labels and
metadata. The C# core reads and writes the same bytes (Lpnn.Probes.Core.Captures).
"""

from __future__ import annotations

import json
import os
import struct
import zlib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Iterable

import numpy as np

from ..errors import InvalidInputError
from .atomic import write_atomic, write_new_atomic
from .schema import schema_by_id

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


# ----------------------------------------------------------------------------------------- writing

def _pad8(n: int) -> int:
    return (-n) % 8


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
    problems = _content_problems(capture, "<capture being written>", stop_at_first=True)
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
    header_bytes += b" " * _pad8(PREAMBLE_BYTES + len(header_bytes))
    parts = [MAGIC, struct.pack("<II", FORMAT_VERSION, len(header_bytes)), header_bytes]
    for _, array in sections:
        raw = array.tobytes(order="C")
        parts.append(raw)
        parts.append(b"\x00" * _pad8(len(raw)))
    body = b"".join(parts)
    crc = zlib.crc32(body) & 0xFFFFFFFF
    return body + struct.pack("<II", crc, 0) + END_MAGIC


def write_capture(path: str | os.PathLike, capture: Capture) -> Path:
    """Save: write (or atomically replace) one capture file."""
    data = encode_capture(capture)
    return write_atomic(path, lambda handle: handle.write(data))


def safe_file_stem(stem: str) -> str:
    """A file name stem from free text (e.g. a scene name): letters, digits, '-', '_', '.' kept, others '_'."""
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem) or "capture"


def append_capture(folder: str | os.PathLike, capture: Capture, stem: str) -> Path:
    """Append to a dataset folder: a new file `<stem>.lpnncap` (or `-2`, `-3`...), never replacing."""
    data = encode_capture(capture)
    base = Path(folder)
    safe_stem = safe_file_stem(stem)
    for number in range(1, 1_000_000):
        name = f"{safe_stem}{EXTENSION}" if number == 1 else f"{safe_stem}-{number}{EXTENSION}"
        if write_new_atomic(base / name, lambda handle: handle.write(data)):
            return base / name
    raise CaptureError(f"{base}: no free capture name for stem '{safe_stem}'")


# ----------------------------------------------------------------------------------------- reading

class _Problems:
    """Collects problems; raises on the first one unless collecting all (validate mode)."""

    def __init__(self, collect_all: bool):
        self.collect_all = collect_all
        self.items: list[str] = []

    def add(self, message: str) -> None:
        if not self.collect_all:
            raise CaptureError(message)
        self.items.append(message)


def _parse_header(name: str, data: bytes, problems: _Problems) -> tuple[dict[str, Any] | None, int]:
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


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: Any) -> bool:
    return (isinstance(value, (int, float)) and not isinstance(value, bool)) and np.isfinite(value)


def _check_header(name: str, header: dict[str, Any], problems: _Problems) -> bool:
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
    if not _is_int(header["point_count"]) or header["point_count"] < 1:
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
    if not _is_number(header["cell_size"]) or header["cell_size"] <= 0:
        bad("cell_size", f"{header['cell_size']!r} is not a finite number > 0")
    if not isinstance(header["units"], str):
        bad("units", "must be a string")
    if not _is_number(header["lighting_scale"]) or header["lighting_scale"] <= 0:
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


def _expected_shape(section: str, n: int, f: int) -> tuple[int, ...] | None:
    return {"ids": (n, 3), "positions": (n, 3), "sh": (n, 27), "features": (n, f), "labels": (n,)}.get(section)


def _read_sections(name: str, data: bytes, header: dict[str, Any], start: int,
                   problems: _Problems) -> dict[str, np.ndarray] | None:
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
        if not isinstance(shape, list) or not shape or not all(_is_int(d) and d >= 0 for d in shape):
            problems.add(f"{where} ('{section}'): shape {shape!r} is not a list of non-negative integers")
            ok = False
            continue
        expected = _expected_shape(section, n, f)
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
        described += size + _pad8(size)
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
        offset += size + _pad8(size)
    return arrays


def _record(name: str, index: int, ids: np.ndarray) -> str:
    i, j, k = (int(v) for v in ids[index])
    return f"{name}: record {index} (id {i},{j},{k})"


def _content_problems(capture: Capture, name: str, stop_at_first: bool) -> list[str]:
    """Value-level checks shared by reading, validating and writing."""
    problems: list[str] = []

    def add(message: str) -> bool:
        problems.append(message)
        return stop_at_first

    n = capture.ids.shape[0] if capture.ids.ndim == 2 else 0
    f = len(capture.feature_names)
    shapes = {
        "ids": (capture.ids, (n, 3)),
        "positions": (capture.positions, (n, 3)),
        "sh": (capture.sh, (n, 27)),
        "features": (capture.features, (n, f)),
    }
    if n < 1:
        add(f"{name}: capture has no points")
        return problems
    for key, (array, shape) in shapes.items():
        if array.shape != shape:
            add(f"{name}: section '{key}' has shape {list(array.shape)}, expected {list(shape)}")
            return problems
    if capture.labels is not None and capture.labels.shape != (n,):
        add(f"{name}: section 'labels' has shape {list(capture.labels.shape)}, expected [{n}]")
        return problems
    if not (np.isfinite(capture.cell_size) and capture.cell_size > 0):
        add(f"{name}: header: field 'cell_size': {capture.cell_size!r} is not a finite number > 0")
        return problems
    if not (np.isfinite(capture.lighting_scale) and capture.lighting_scale > 0):
        if add(f"{name}: header: field 'lighting_scale': {capture.lighting_scale!r} is not a finite number > 0"):
            return problems
    if len(set(capture.feature_names)) != f or f == 0:
        if add(f"{name}: header: field 'feature_names': must be unique and non-empty"):
            return problems
    known = schema_by_id(capture.schema)
    if known is not None and tuple(capture.feature_names) != known.names:
        if add(f"{name}: header: field 'feature_names': do not match schema {known.id!r}"):
            return problems
    if capture.labels is not None and capture.label_source is None:
        if add(f"{name}: header: field 'label_source': must be set when labels are present"):
            return problems

    ids = np.asarray(capture.ids, dtype=np.int64)
    if n > 1:
        diffs = ids[1:] - ids[:-1]
        # strictly increasing in (k, j, i) order
        later = (diffs[:, 2] > 0) | ((diffs[:, 2] == 0) & ((diffs[:, 1] > 0) | ((diffs[:, 1] == 0) & (diffs[:, 0] > 0))))
        bad = np.flatnonzero(~later)
        for index in bad[: 1 if stop_at_first else 20]:
            what = "repeats" if not diffs[index].any() else "is out of grid order after"
            if add(f"{_record(name, int(index) + 1, ids)}: field 'ids': {what} record {int(index)}"):
                return problems

    def check_finite(key: str, array: np.ndarray, column_name) -> bool:
        bad_rows, bad_cols = np.nonzero(~np.isfinite(array))
        for row, col in list(zip(bad_rows, bad_cols))[: 1 if stop_at_first else 20]:
            value = float(array[row, col])  # plain float: numpy 2 would print 'np.float32(nan)'
            text = "NaN" if np.isnan(value) else repr(value)
            if add(f"{_record(name, int(row), ids)}: field '{column_name(int(col))}': {text} is not finite"):
                return True
        return False

    if check_finite("positions", capture.positions, lambda c: f"positions[{'xyz'[c]}]"):
        return problems
    if check_finite("sh", capture.sh, lambda c: f"sh[{SH_CHANNELS[c // 9]},{c % 9}]"):
        return problems
    if check_finite("features", capture.features, lambda c: f"features[{capture.feature_names[c]}]"):
        return problems

    h = float(capture.cell_size)
    expected = ids.astype(np.float64) * h
    positions = capture.positions.astype(np.float64)
    tolerance = 1e-4 * h + 4.0 * np.spacing(np.abs(expected).astype(np.float32)).astype(np.float64)
    off_rows = np.flatnonzero(np.any(np.abs(positions - expected) > tolerance, axis=1))
    for row in off_rows[: 1 if stop_at_first else 20]:
        if add(f"{_record(name, int(row), ids)}: field 'positions': {positions[row].tolist()} is not cell_size*id = {expected[row].tolist()}"):
            return problems

    if capture.labels is not None:
        bad_labels = np.flatnonzero(capture.labels > 1)
        for row in bad_labels[: 1 if stop_at_first else 20]:
            if add(f"{_record(name, int(row), ids)}: field 'labels': {int(capture.labels[row])} is not 0 or 1"):
                return problems
    return problems


def _decode(path: Path, data: bytes, problems: _Problems) -> Capture | None:
    name = str(path)
    header, start = _parse_header(name, data, problems)
    if header is None or not _check_header(name, header, problems):
        return None
    arrays = _read_sections(name, data, header, start, problems)
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


def read_capture(path: str | os.PathLike) -> Capture:
    """Read and fully validate one capture; raises CaptureError naming file, record and field."""
    file = Path(path)
    try:
        data = file.read_bytes()
    except OSError as exc:
        raise CaptureError(f"{file}: cannot read: {exc.strerror or exc}") from exc
    capture = _decode(file, data, _Problems(collect_all=False))
    assert capture is not None
    problems = _content_problems(capture, str(file), stop_at_first=True)
    if problems:
        raise CaptureError(problems[0])
    return capture


def validate_capture(path: str | os.PathLike) -> list[str]:
    """Every problem found in one capture (empty list = valid)."""
    file = Path(path)
    try:
        data = file.read_bytes()
    except OSError as exc:
        return [f"{file}: cannot read: {exc.strerror or exc}"]
    problems = _Problems(collect_all=True)
    capture = _decode(file, data, problems)
    if capture is not None:
        problems.items.extend(_content_problems(capture, str(file), stop_at_first=False))
    return problems.items


def dataset_files(paths: str | os.PathLike | Iterable[str | os.PathLike]) -> list[Path]:
    """Capture files of a dataset: folders are searched recursively; result sorted by path."""
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    found: list[Path] = []
    for entry in paths:
        p = Path(entry)
        if p.is_dir():
            found.extend(sorted(q for q in p.rglob(f"*{EXTENSION}") if q.is_file()))
        elif p.is_file():
            found.append(p)
        else:
            raise CaptureError(f"{p}: no such capture file or dataset folder")
    return sorted(dict.fromkeys(found))
