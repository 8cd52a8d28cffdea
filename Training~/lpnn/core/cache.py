"""The project's cache folder ($LPNN_CACHE, else ~/.cache/lpnn-probes: the folder Tools~/lib.sh uses), and
numba's compiled-function cache inside it instead of beside the sources (a read-only install, a clean checkout), safe to
share between processes at once (cache_guard.py)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from .cache_guard import guard_numba_cache_files
from .parallel_wait import sleep_between_parallel_loops

CACHE_ENV = "LPNN_CACHE"
NUMBA_CACHE_ENV = "NUMBA_CACHE_DIR"


def project_cache_dir() -> Path:
    configured = os.environ.get(CACHE_ENV)
    return Path(configured) if configured else Path.home() / ".cache" / "lpnn-probes"


def use_project_cache_for_numba() -> None:
    """Call before the first `import numba`; a NUMBA_CACHE_DIR the user set is kept. Also lets numba's idle worker
    threads sleep between parallel loops (parallel_wait.py), which must be chosen before its thread pool starts too,
    and makes the cache's entries whole for processes sharing it at once (cache_guard.py)."""
    os.environ.setdefault(NUMBA_CACHE_ENV, str(project_cache_dir() / "numba"))
    sleep_between_parallel_loops()
    numba = sys.modules.get("numba")
    if numba is not None and not numba.config.CACHE_DIR:  # imported before us: its config already read the env
        numba.config.CACHE_DIR = os.environ[NUMBA_CACHE_ENV]
    guard_numba_cache_files()
