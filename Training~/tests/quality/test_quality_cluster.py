"""Same labels everywhere: `lpnn label` in this process, on 2 local workers, and on a two-process Dask cluster started
the way a user starts a real one (`dask scheduler`, `dask worker ADDRESS`; here on 127.0.0.1 only)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Iterator

import pytest

from lpnn.cli.main import main

TRAINING = Path(__file__).resolve().parents[2]  # holds lpnn/: what the workers must be able to import
START_SECONDS = 60  # bound on the scheduler and its workers coming up


def _dask(*arguments: str, log: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(TRAINING), os.environ.get("PYTHONPATH")])))
    with open(log, "wb") as handle:
        return subprocess.Popen([sys.executable, "-m", "dask", *arguments], env=env,
                                stdout=handle, stderr=subprocess.STDOUT)


@pytest.fixture
def loopback_cluster(tmp_path: Path) -> Iterator[str]:
    """A scheduler and a worker (2 processes of 1 thread), separate processes on 127.0.0.1; yields the address."""
    from distributed import Client

    scheduler_file = tmp_path / "scheduler.json"
    started = [_dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                     "--scheduler-file", str(scheduler_file), log=tmp_path / "scheduler.log")]
    try:
        deadline = time.monotonic() + START_SECONDS
        while not scheduler_file.exists():
            assert time.monotonic() < deadline, (tmp_path / "scheduler.log").read_text(errors="replace")
            assert started[0].poll() is None, (tmp_path / "scheduler.log").read_text(errors="replace")
            time.sleep(0.2)
        address = json.loads(scheduler_file.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        started.append(_dask("worker", address, "--host", "127.0.0.1", "--nworkers", "2", "--nthreads", "1",
                             "--no-dashboard", log=tmp_path / "worker.log"))
        with Client(address, timeout=f"{START_SECONDS}s") as client:
            client.wait_for_workers(2, timeout=START_SECONDS)
        yield address
    finally:
        for process in reversed(started):
            process.terminate()
        for process in reversed(started):
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


def _labelled(captures: list[Path], out: Path, *engine: str) -> dict[str, bytes]:
    assert main(["label", *map(str, captures), "--budget", "0.2", "--out-dir", str(out), "--quiet", *engine]) == 0
    return {path.name: path.read_bytes() for path in sorted(out.iterdir())}


def test_labels_are_identical_in_process_on_local_workers_and_on_a_cluster(
        capture_files: list[Path], tmp_path: Path, loopback_cluster: str) -> None:
    alone = _labelled(capture_files, tmp_path / "one", "--workers", "1")
    assert sorted(alone) == sorted(path.name for path in capture_files)
    assert _labelled(capture_files, tmp_path / "two", "--workers", "2") == alone
    assert _labelled(capture_files, tmp_path / "cluster", "--scheduler", loopback_cluster) == alone
