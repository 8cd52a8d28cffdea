"""Atomic file writes: a temporary file in the target folder, flushed and fsynced, then renamed.

Nothing is lost on failure: either the old file (or no file) remains, or the complete new one.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import Callable, Iterator, BinaryIO


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def _temporary_beside(target: Path) -> Iterator[tuple[BinaryIO, Path]]:
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    tmp = Path(tmp_name)
    try:
        # mkstemp creates 0600; give the file the permissions a plain open() would (0666 minus the umask).
        os.fchmod(fd, 0o666 & ~_current_umask())
        with os.fdopen(fd, "wb") as handle:
            yield handle, tmp
            handle.flush()
            os.fsync(handle.fileno())
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_bytes_atomic(path: str | os.PathLike, data: bytes) -> Path:
    """Write `data` to `path`, replacing any existing file atomically."""
    return write_atomic(path, lambda handle: handle.write(data))


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """UTF-8 text with '\\n' line ends, replacing atomically."""
    return write_bytes_atomic(path, text.encode("utf-8"))


def write_atomic(path: str | os.PathLike, writer: Callable[[BinaryIO], object]) -> Path:
    """Call writer(handle) on a temporary file, then rename it over `path`."""
    target = Path(path)
    with _temporary_beside(target) as (handle, tmp):
        writer(handle)
    os.replace(tmp, target)
    return target


def write_new_atomic(path: str | os.PathLike, writer: Callable[[BinaryIO], object]) -> bool:
    """Like write_atomic, but never replaces: returns False (and writes nothing) when `path` exists.

    The final step is a hard link, which fails atomically if the name was taken meanwhile.
    """
    target = Path(path)
    if target.exists():
        return False
    with _temporary_beside(target) as (handle, tmp):
        writer(handle)
    try:
        os.link(tmp, target)
    except FileExistsError:
        return False
    finally:
        tmp.unlink(missing_ok=True)
    return True
