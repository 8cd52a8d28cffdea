"""One process-pool policy: every worker process of the trainer starts through lpnn.core.processes (spawn)."""

from __future__ import annotations

import os
import re
from pathlib import Path

from lpnn.core.processes import worker_pool

LPNN = Path(__file__).resolve().parents[2] / "lpnn"
# Anything that picks a start method or builds a pool/process by itself instead of through the policy.
OWN_START = re.compile(r"get_context\(|set_start_method\(|multiprocessing\.(Pool|Process)\(|ProcessPoolExecutor\(")


def _thread_limit(_: int) -> str | None:
    return os.environ.get("OMP_NUM_THREADS")


def test_workers_are_spawned_with_one_thread_each() -> None:
    with worker_pool(2) as pool:
        assert pool._ctx.get_start_method() == "spawn"  # type: ignore[attr-defined]
        assert pool.map(_thread_limit, range(2)) == ["1", "1"]


def test_no_module_starts_processes_its_own_way() -> None:
    offenders = [f"{path.relative_to(LPNN)}:{number}" for path in sorted(LPNN.rglob("*.py"))
                 if path.name != "processes.py"
                 for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
                 if OWN_START.search(line)]
    assert offenders == []
