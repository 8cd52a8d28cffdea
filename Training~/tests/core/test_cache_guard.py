"""numba's disk cache shared by processes at once (lpnn/core/cache_guard.py): its entries' files are written and read
under a lock, and a stop that arrives during a save acts when the save is done."""

from __future__ import annotations

import fcntl
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from lpnn.core import cache_guard
from lpnn.core.cache import use_project_cache_for_numba
from lpnn.core.cache_guard import LOCK_NAME, locked, signals_deferred

TRAINING = Path(__file__).resolve().parents[2]

HOLDER = """
import sys
from lpnn.core.cache_guard import locked
with locked(sys.argv[1], exclusive=True):
    print("held", flush=True)
    sys.stdin.readline()
"""


def test_numbas_cache_files_are_read_and_written_under_the_lock() -> None:
    use_project_cache_for_numba()
    from numba.core.caching import IndexDataCacheFile

    assert getattr(IndexDataCacheFile, cache_guard.GUARDED) is True
    assert all(getattr(IndexDataCacheFile, name).__name__ == "guarded" for name in ("save", "flush", "load"))
    assert cache_guard.guard_numba_cache_files() is True  # once: not wrapped twice
    assert IndexDataCacheFile.save.__closure__[0].cell_contents.__name__ == "save"


def test_a_writer_in_another_process_keeps_readers_out_until_it_is_done(tmp_path: Path) -> None:
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, str(tmp_path)], stdin=subprocess.PIPE,
                              stdout=subprocess.PIPE, text=True, env=dict(os.environ, PYTHONPATH=str(TRAINING)))
    try:
        assert holder.stdout.readline().strip() == "held"
        with open(tmp_path / LOCK_NAME, "a+b") as handle:
            with pytest.raises(BlockingIOError):
                fcntl.flock(handle, fcntl.LOCK_SH | fcntl.LOCK_NB)
            holder.stdin.write("done\n")
            holder.stdin.flush()
            assert holder.wait(timeout=60) == 0
            fcntl.flock(handle, fcntl.LOCK_SH | fcntl.LOCK_NB)  # released: taken at once
            fcntl.flock(handle, fcntl.LOCK_UN)
    finally:
        if holder.poll() is None:
            holder.kill()
    with locked(str(tmp_path), exclusive=False):
        pass


def test_a_stop_during_a_save_acts_when_the_save_is_done() -> None:
    """The handler in place before the block (here a recorder: another test may have changed SIGINT's) runs once the
    block is done, not when the signal arrives, and is in place again afterwards."""
    finished: list[bool] = []
    caught: list[list[bool]] = []
    recorder = lambda number, frame: caught.append(list(finished))  # noqa: E731 - what had finished when it ran
    previous = signal.signal(signal.SIGINT, recorder)
    try:
        with signals_deferred():
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):  # bytecodes enough for Python to run a handler, which only records the signal here
                pass
            assert caught == []
            finished.append(True)
        for _ in range(1000):
            pass
        assert caught == [[True]]
        assert signal.getsignal(signal.SIGINT) is recorder
    finally:
        signal.signal(signal.SIGINT, previous)


def test_a_handler_python_did_not_set_is_left_alone(monkeypatch: pytest.MonkeyPatch) -> None:
    """getsignal None (a library's handler installed outside Python) cannot be put back, so it is not replaced."""
    replaced = []
    real = signal.signal
    monkeypatch.setattr(cache_guard.signal, "getsignal", lambda number: None)
    monkeypatch.setattr(cache_guard.signal, "signal", lambda number, handler: replaced.append(number) or real(number, handler))
    with signals_deferred():
        pass
    assert replaced == []
