"""The benchmark's warm-up: every method of its config once on a synthetic room, before its first capture is timed."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ...core.analytic_scene import AnalyticScene
from ..placement.warmup import compile_placement_kernels
from .results import BenchConfig
from .run import bench_capture

WARM_UP_BENCH_CELL = 0.7  # ~350 points: above the faithful reference's 200, so the warm-up skips that slow yardstick


def warm_up_bench(config: BenchConfig, scorer: Any | None = None) -> None:
    """Runs every method of `config` once on a small synthetic room, results discarded, so that a process's first
    capture does not count numba's compilation (~30 s on a fresh checkout), the loading of the compiled kernels from the
    disk cache (~0.3 s) or the scorer's first run as its methods' time. The kernels only a level reaches (the Embree ray
    check, the projection onto a large hull) by compile_placement_kernels."""
    compile_placement_kernels()
    scene = AnalyticScene.random(2, cell_size=WARM_UP_BENCH_CELL)
    bench_capture("warm-up", scene.capture(name="warm-up"),
                  replace(config, repeats=1, reference_repeats=1, checkpoints=None), scorer, geometry=scene.raycaster)
