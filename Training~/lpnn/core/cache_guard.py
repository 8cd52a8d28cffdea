"""numba's disk cache shared by several processes at once: each entry saved whole, or not at all.

numba (0.68) saves a kernel's cache entry in two renames — the index naming the data file, then the data file — after
reading the index, and loads it by reading the index, then the data file it names. Two processes compiling the same
kernel at once (the warm-up and its partner, quality/placement/warmup_partner.py; the benchmark's worker processes)
can then lose one's index update, or pair an index with another's data file (numba issue 10128); and a process
stopped between the two renames leaves an index naming a data file of the sources before an edit, which a later run
loads as if it were current. Here every save and flush holds an exclusive lock on a file in the cache folder, and
every load a shared one, so a reader sees either no entry or a whole one; SIGINT and SIGTERM that arrive during a save
(in the main thread, where numba compiles here) act when it is done. POSIX only (fcntl): elsewhere nothing changes,
and the warm-up starts no partner.
"""

from __future__ import annotations

import os
import signal
import threading
from contextlib import contextmanager
from typing import Any, Callable, Iterator

try:
    import fcntl
except ImportError:  # not POSIX
    fcntl = None  # type: ignore[assignment]

LOCK_NAME = ".lpnn-cache.lock"
DEFERRED_SIGNALS = (signal.SIGINT, signal.SIGTERM)
GUARDED = "_lpnn_guarded"  # set on numba's IndexDataCacheFile once its methods are wrapped


def can_guard() -> bool:
    """Whether this platform can lock files (fcntl): where it cannot, processes must not share a cache at once."""
    return fcntl is not None


@contextmanager
def locked(folder: str, exclusive: bool) -> Iterator[None]:
    """An exclusive (writer) or shared (reader) lock on `folder`'s lock file, held for the block; released by the
    system too if the process dies."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, LOCK_NAME), "a+b") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


@contextmanager
def signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM received during the block are recorded and raised again when it ends (then the handlers
    before it act: a KeyboardInterrupt, the process's end), so a save is never cut in half. Python's handlers run in
    the main thread whichever thread the signal reached, so a handler, not a thread's signal mask, holds them back.
    Only the main thread can set handlers: elsewhere (a worker thread's save) the block runs as it is; and a signal
    whose handler was not set from Python (getsignal None: a library's own, which could not be put back) is left alone."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = {number: signal.signal(number, lambda caught, frame: received.append(caught))
                for number in DEFERRED_SIGNALS if signal.getsignal(number) is not None}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        for number in received:
            signal.raise_signal(number)


def _writer(method: Callable[..., Any]) -> Callable[..., Any]:
    def guarded(self: Any, *arguments: Any) -> Any:
        with signals_deferred(), locked(self._cache_path, exclusive=True):
            return method(self, *arguments)
    return guarded


def _reader(method: Callable[..., Any]) -> Callable[..., Any]:
    def guarded(self: Any, *arguments: Any) -> Any:
        with locked(self._cache_path, exclusive=False):
            return method(self, *arguments)
    return guarded


def guard_numba_cache_files() -> bool:
    """Wraps numba's IndexDataCacheFile.save, .flush (writers) and .load (reader) as the module text says, once per
    process; False where the platform cannot lock files. Raises if numba's class no longer has those methods (a numba
    upgrade to check against the module text)."""
    if not can_guard():
        return False
    from numba.core.caching import IndexDataCacheFile

    if getattr(IndexDataCacheFile, GUARDED, False):
        return True
    for name in ("save", "flush", "load"):
        if not callable(getattr(IndexDataCacheFile, name, None)):
            raise RuntimeError(f"numba's IndexDataCacheFile has no method {name!r}: check lpnn/core/cache_guard.py "
                               "against this numba version")
    IndexDataCacheFile.save = _writer(IndexDataCacheFile.save)
    IndexDataCacheFile.flush = _writer(IndexDataCacheFile.flush)
    IndexDataCacheFile.load = _reader(IndexDataCacheFile.load)
    setattr(IndexDataCacheFile, GUARDED, True)
    return True
