"""The demo's warm-up compiles the default placement's kernels: once it ran, the default on a room takes a fraction of
the warm-up's first time."""

from __future__ import annotations

import math

from lpnn.quality.placement.warmup import compile_placement_kernels


def test_the_warm_up_runs_the_default_and_reports_its_seconds() -> None:
    first = compile_placement_kernels()
    again = compile_placement_kernels()
    assert math.isfinite(first) and first > 0.0
    assert 0.0 < again <= first + 0.5  # compiled (or cached) by the first call: never slower than it
