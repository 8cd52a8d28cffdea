"""Atomic file writes: a temporary file in the target folder, flushed and fsynced, then renamed.

Nothing is lost on failure: either the old file (or no file) remains, or the complete new one, and no
temporary file is left behind. A target that cannot be written (a folder, a path under a regular file,
no permission, a full disk) raises `OutputPathError`, whose message names the path and what to do.
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from pathlib import Path
from typing import Callable, Iterator, BinaryIO

from ..errors import LpnnError

# Failures of the write itself (not of the path): the disk or the user's quota is full, or the file is
# larger than the file system allows.
_SPACE_ERRNOS = frozenset(getattr(errno, name) for name in ("ENOSPC", "EDQUOT", "EFBIG") if hasattr(errno, name))
# os.link where the file system has no hard links (FAT/exFAT, some network shares).
_NO_HARD_LINK_ERRNOS = frozenset(getattr(errno, name) for name in ("EPERM", "ENOTSUP", "EOPNOTSUPP", "EXDEV", "ENOSYS")
                                 if hasattr(errno, name))


class OutputPathError(LpnnError):
    """An output path that cannot be written; the message names the path and what to do."""


def _explain(target: Path, exc: OSError, *, folder: bool = False) -> OutputPathError:
    """One message per cause a user can act on (`target` is a file path, or a folder when `folder`)."""
    blocker = _file_among_parents(target if not folder else target / "_")
    if target.is_dir() and not folder:
        advice = f"{target} is a folder: give a file path inside it instead"
    elif blocker is not None:
        advice = f"cannot create {target}: {blocker} is a file, not a folder; choose another output path"
    elif isinstance(exc, PermissionError):
        place = target if folder else target.parent
        advice = f"no permission to write in {place}: choose a folder you can write to, or change its permissions"
    elif exc.errno in _SPACE_ERRNOS:
        advice = f"could not write {target}: {exc.strerror}; free some space or choose another disk"
    else:
        advice = f"could not write {target}: {exc.strerror or exc}; check the path and try again"
    return OutputPathError(advice)


def _file_among_parents(target: Path) -> Path | None:
    for parent in target.parents:
        if parent.exists():
            return parent if not parent.is_dir() else None
    return None


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def ensure_folder(folder: str | os.PathLike) -> Path:
    """Create `folder` (and its parents) for outputs, or raise OutputPathError saying why it cannot be."""
    path = Path(folder)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _explain(path, exc, folder=True) from exc
    return path


@contextlib.contextmanager
def _temporary_beside(target: Path) -> Iterator[tuple[BinaryIO, Path]]:
    """A temporary file in the target's folder; removed on any failure (or by the caller after use)."""
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except OSError as exc:
        raise _explain(target, exc) from exc
    tmp = Path(tmp_name)
    try:
        # mkstemp creates 0600; give the file the permissions a plain open() would (0666 minus the umask).
        # By path, not os.fchmod: that one is missing on Windows before Python 3.13.
        os.chmod(tmp, 0o666 & ~_current_umask())
        with os.fdopen(fd, "wb") as handle:
            try:
                yield handle, tmp
                handle.flush()
                os.fsync(handle.fileno())
            except OSError as exc:
                if exc.errno in _SPACE_ERRNOS:
                    raise _explain(target, exc) from exc
                raise
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
    try:
        os.replace(tmp, target)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise _explain(target, exc) from exc
    return target


def write_new_atomic(path: str | os.PathLike, writer: Callable[[BinaryIO], object]) -> bool:
    """Like write_atomic, but never replaces: returns False (and writes nothing) when `path` exists.

    The final step is a hard link, which fails atomically if the name was taken meanwhile. Where the file
    system has no hard links, the name is reserved by an exclusive create and the temporary file renamed
    over it: still never replacing another file, though a reader may briefly see it empty.
    """
    target = Path(path)
    if target.exists():
        return False
    with _temporary_beside(target) as (handle, tmp):
        writer(handle)
    try:
        return _publish_new(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)


def _publish_new(tmp: Path, target: Path) -> bool:
    try:
        os.link(tmp, target)
        return True
    except FileExistsError:
        return False
    except OSError as exc:
        if exc.errno not in _NO_HARD_LINK_ERRNOS:
            raise _explain(target, exc) from exc
    try:
        os.close(os.open(target, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
    except FileExistsError:
        return False
    except OSError as exc:
        raise _explain(target, exc) from exc
    try:
        os.replace(tmp, target)
    except OSError as exc:
        target.unlink(missing_ok=True)
        raise _explain(target, exc) from exc
    return True
