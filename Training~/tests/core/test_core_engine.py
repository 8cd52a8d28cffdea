"""The engine (lpnn.core.engine): in-process and local-cluster fan-out, a dying worker, an unreachable scheduler,
and that no module starts worker processes its own way."""

from __future__ import annotations

import os
import re
import socket
from pathlib import Path

import pytest

from lpnn.core import engine as engine_module
from lpnn.core.engine import Engine
from lpnn.errors import UserError

LPNN = Path(__file__).resolve().parents[2] / "lpnn"
# Anything that picks a start method or builds a pool/process by itself instead of through the engine.
OWN_START = re.compile(r"get_context\(|set_start_method\(|multiprocessing\.(Pool|Process)\(|ProcessPoolExecutor\(")
# The fast reference's lockstep replica (one process over a pipe, not a fan-out of items): its own spawn context.
REPLICA = "quality/placement/decimation/removal_costs.py"


def square_unless_three(value: int) -> int:
    if value == 3:
        raise ValueError("three is refused")
    return value * value


def thread_limit(_: int) -> str | None:
    return os.environ.get("OMP_NUM_THREADS")


def die_once(task: tuple[str, int]) -> tuple[int, int]:
    """Kills its worker process the first time it runs (a marker file remembers), then answers."""
    marker, value = task
    if value == 2 and not os.path.exists(marker):
        Path(marker).write_text("died once\n")
        os._exit(1)
    return value, os.getpid()


def test_one_worker_runs_in_this_process_and_reports_each_error() -> None:
    with Engine(1) as engine:
        assert engine.in_process
        done = list(engine.unordered(square_unless_three, [1, 2, 3, 4]))
    assert [d.task for d in done] == [1, 2, 3, 4]
    assert [d.result for d in done if d.error is None] == [1, 4, 16]
    with pytest.raises(ValueError, match="three is refused"):
        done[2].value()


def test_local_workers_give_every_result_once_and_one_thread_each() -> None:
    with Engine(2) as engine:
        assert not engine.in_process
        done = list(engine.unordered(square_unless_three, list(range(8))))
        assert list(engine.ordered(square_unless_three, iter([5, 1, 4]))) == [25, 1, 16]
        assert {d.result for d in engine.unordered(thread_limit, [0, 1, 2, 3])} == {"1"}
    assert sorted(d.task for d in done) == list(range(8))
    assert {d.task: d.result for d in done if d.error is None} == {v: v * v for v in range(8) if v != 3}
    assert [type(d.error) for d in done if d.error is not None] == [ValueError]


def test_a_killed_worker_loses_only_its_task_which_runs_again(tmp_path: Path) -> None:
    marker = str(tmp_path / "died")
    with Engine(2) as engine:
        done = list(engine.unordered(die_once, [(marker, v) for v in range(5)]))
    assert Path(marker).exists()  # a worker did die
    assert all(d.error is None for d in done)
    assert sorted(d.result[0] for d in done) == [0, 1, 2, 3, 4]


def test_an_unreachable_scheduler_is_named_with_what_to_do(monkeypatch: pytest.MonkeyPatch) -> None:
    with socket.socket() as probe:  # a loopback port nobody listens on
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    monkeypatch.setattr(engine_module, "CONNECT_SECONDS", 2)
    address = f"tcp://127.0.0.1:{port}"
    with pytest.raises(UserError, match=rf"cannot reach the Dask scheduler at '{address}'.*dask scheduler"):
        with Engine(scheduler=address):
            pass


def test_a_worker_count_below_one_is_refused() -> None:
    with pytest.raises(UserError, match="--workers 0 must be at least 1"):
        Engine(0)


def test_no_module_starts_processes_its_own_way() -> None:
    offenders = [f"{path.relative_to(LPNN)}:{number}" for path in sorted(LPNN.rglob("*.py"))
                 if path.relative_to(LPNN).as_posix() != REPLICA
                 for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
                 if OWN_START.search(line)]
    assert offenders == []
