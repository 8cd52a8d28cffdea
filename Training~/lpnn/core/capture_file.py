"""Capture files: read, validate, write (atomically), append to a dataset folder, list a dataset (C#:
Captures/CaptureFile.cs). The C# core reads and writes the same bytes."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable

from .atomic import write_atomic, write_new_atomic
from .capture import Capture, CaptureError
from .capture_content import content_problems
from .capture_decoder import decode
from .capture_encoder import encode_capture
from .capture_format import EXTENSION
from .capture_header import Problems


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


def read_capture(path: str | os.PathLike) -> Capture:
    """Read and fully validate one capture; raises CaptureError naming file, record and field."""
    file = Path(path)
    try:
        data = file.read_bytes()
    except OSError as exc:
        raise CaptureError(f"{file}: cannot read: {exc.strerror or exc}") from exc
    capture = decode(file, data, Problems(collect_all=False))
    assert capture is not None
    problems = content_problems(capture, str(file), stop_at_first=True)
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
    problems = Problems(collect_all=True)
    capture = decode(file, data, problems)
    if capture is not None:
        problems.items.extend(content_problems(capture, str(file), stop_at_first=False))
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
