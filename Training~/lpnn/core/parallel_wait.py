"""numba's parallel loops (its OpenMP threading layer here) with worker threads that sleep between loops instead of
spinning: OMP_WAIT_POLICY=PASSIVE, unless the user set a policy.

Why. A placement runs thousands of short parallel loops (metric_kernel.run_rows: a refinement round's location, errors
and leak look-ups). OpenMP's default lets an idle worker spin for a while after each loop; on a machine whose other core
is busy (other jobs, an editor, Unity) the spinning worker takes the time slices the working thread needs, and every loop
waits for the descheduled one. Measured on ctf_compromise (136,512 points, leak-aware default, load 6-8 on 2 cores,
Tools~/experiments/paired-time.py, 2026-11-28): benchmarks.md "Scale: whole levels". The numbers computed are the same
(every parallel loop's result is independent of how its slices are scheduled: metric_kernel.chunk_count)."""

from __future__ import annotations

import os

WAIT_POLICY_ENV = "OMP_WAIT_POLICY"
WAIT_POLICY = "PASSIVE"


def sleep_between_parallel_loops() -> None:
    """Call before numba starts its thread pool (before the first parallel loop runs; use_project_cache_for_numba does):
    the OpenMP runtime reads the policy once, when it loads. A policy the user set is kept."""
    os.environ.setdefault(WAIT_POLICY_ENV, WAIT_POLICY)
