"""The one way the trainer starts worker processes: `spawn`, on every platform.

`fork` does not exist on Windows, and forking a process in which a library has started threads
(onnxruntime, TensorFlow, OpenMP in numpy's BLAS) can leave the child holding a lock no thread will
ever release; Python 3.12 warns when it happens and 3.14 no longer forks by default on Linux. `spawn`
starts a fresh interpreter instead: each worker imports what its task needs once, and everything
handed to it must pickle. A script of yours that calls the recipe or the two-process fast reference must
keep its top-level code under `if __name__ == "__main__":` (Python's rule for spawn: each worker imports
the main script again); the `lpnn` command already does.
"""

from __future__ import annotations

import multiprocessing
import os
from multiprocessing.context import SpawnContext
from multiprocessing.pool import Pool
from typing import Any, Callable

START_METHOD = "spawn"
CONTEXT: SpawnContext = multiprocessing.get_context(START_METHOD)


def worker_pool(workers: int) -> Pool:
    """A pool of `workers` processes, each limited to one OpenMP thread (the pool provides the parallelism)."""
    return CONTEXT.Pool(workers, initializer=_one_thread_per_worker)


def worker_process(target: Callable[..., Any], args: tuple) -> multiprocessing.Process:
    """One daemon worker process (not started)."""
    return CONTEXT.Process(target=target, args=args, daemon=True)


def _one_thread_per_worker() -> None:
    os.environ.setdefault("OMP_NUM_THREADS", "1")
