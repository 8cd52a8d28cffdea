"""The one way the trainer fans work out: Dask distributed, on this machine or on a cluster.

    with Engine(workers=2) as engine:                      # a local cluster of 2 worker processes
    with Engine(scheduler="tcp://10.0.0.5:8786") as engine:  # a running cluster (`dask scheduler` + `dask worker`)
        for done in engine.unordered(function, tasks): ...    # as each task finishes
        for result in engine.ordered(function, tasks): ...    # in order, a few tasks ahead (lazy task lists)

With one worker and no scheduler nothing is started: the tasks run in this process, one after another,
as they always did. Otherwise each task runs in a worker process (Dask's nanny spawns it: no `fork`, see
below; OMP/MKL/OpenBLAS limited to one thread each, the workers provide the parallelism). Tasks and
their results must pickle, and `function` must be importable by the workers: a cluster's workers need
the `lpnn` package (same version) and, because tasks read and write files by path, the same file system
at the same paths (Documentation~/training.md "On a cluster").

A worker that dies (killed, out of memory) loses only the task it was running: the scheduler runs it
again on another worker, up to Dask's `distributed.scheduler.allowed-failures` times (3), after which that
task alone is reported as failed (`Done.error`, a `KilledWorker`). A task that raises is reported the same
way and is not retried (it would raise again: the work is deterministic).

Why not `fork`: forking a process in which a library has started threads (onnxruntime, TensorFlow,
OpenMP) can leave the child holding a lock no thread will release, and it does not exist on Windows.
A script of yours that uses the engine must keep its top-level code under `if __name__ == "__main__":`
(the workers import the main script again); the `lpnn` command already does.
"""

from __future__ import annotations

import logging
from collections import deque
from dataclasses import dataclass
from typing import Any, Callable, Generic, Iterable, Iterator, Sequence, TypeVar

from ..errors import UserError

Task = TypeVar("Task")
CONNECT_SECONDS = 20  # to reach a scheduler given by address before saying it is unreachable
AHEAD_PER_WORKER = 2  # ordered(): tasks submitted ahead per worker (enough to keep each busy, few in memory)


@dataclass(frozen=True)
class Done(Generic[Task]):
    """One finished task: its result, or the error that ended it (raised in the task, or its worker died
    more often than allowed)."""

    task: Task
    result: Any = None
    error: BaseException | None = None

    def value(self) -> Any:
        """The result; re-raises the task's error (for callers that stop at the first failure)."""
        if self.error is not None:
            raise self.error
        return self.result


class Engine:
    """Local (in this process, or a local cluster of `workers` processes) or a running cluster at `scheduler`."""

    def __init__(self, workers: int = 1, scheduler: str | None = None):
        if workers < 1:
            raise UserError(f"--workers {workers} must be at least 1")
        self.workers = workers
        self.scheduler = scheduler
        self._client: Any = None
        self._cluster: Any = None

    @property
    def in_process(self) -> bool:
        """True when tasks run in this process (one worker, no scheduler)."""
        return self.workers <= 1 and self.scheduler is None

    def __enter__(self) -> "Engine":
        if self.in_process:
            return self
        from distributed import Client, LocalCluster

        if self.scheduler is not None:
            try:
                self._client = Client(self.scheduler, timeout=f"{CONNECT_SECONDS}s")
            except (OSError, TimeoutError, ValueError) as exc:
                raise UserError(f"cannot reach the Dask scheduler at {self.scheduler!r} within {CONNECT_SECONDS} s "
                                f"({exc}); start one with `dask scheduler` and workers with `dask worker ADDRESS` "
                                "(Documentation~/training.md \"On a cluster\"), or leave out --scheduler to run "
                                "on this machine") from exc
        else:
            # Loopback only, and any free port for the scheduler's HTTP endpoints (the usual 8787 may be taken).
            # The workers' own logs are silenced: each failed item is reported once, by the command, with its reason.
            self._cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                         host="127.0.0.1", dashboard_address="127.0.0.1:0",
                                         silence_logs=logging.CRITICAL)
            self._client = Client(self._cluster)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._client is not None:
            self._client.close()
        if self._cluster is not None:
            self._cluster.close()
        self._client = self._cluster = None

    def unordered(self, function: Callable[[Task], Any], tasks: Sequence[Task]) -> Iterator[Done[Task]]:
        """Every task's outcome as soon as it finishes (in task order when in process)."""
        if self.in_process or len(tasks) == 0:
            yield from (_run_here(function, task) for task in tasks)
            return
        from distributed import as_completed

        futures = self._client.map(function, list(tasks), pure=False)
        task_of = {future.key: task for future, task in zip(futures, tasks)}
        for future in as_completed(futures):
            yield _outcome(future, task_of[future.key])

    def ordered(self, function: Callable[[Task], Any], tasks: Iterable[Task]) -> Iterator[Any]:
        """Every task's result in task order, raising the first error. `tasks` is consumed only a few tasks
        ahead of the results (AHEAD_PER_WORKER per worker), so a long lazy list never sits in memory at once."""
        if self.in_process:
            yield from map(function, tasks)
            return
        ahead = AHEAD_PER_WORKER * max(1, len(self._client.scheduler_info().get("workers", {})))
        pending: deque = deque()
        for task in tasks:
            pending.append(self._client.submit(function, task, pure=False))
            if len(pending) >= ahead:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()


def _run_here(function: Callable[[Task], Any], task: Task) -> Done[Task]:
    try:
        return Done(task, function(task))
    except Exception as error:  # reported as the workers' errors are
        return Done(task, error=error)


def _outcome(future: Any, task: Task) -> Done[Task]:
    try:
        return Done(task, future.result())
    except Exception as error:  # raised in the task, or KilledWorker
        return Done(task, error=error)
