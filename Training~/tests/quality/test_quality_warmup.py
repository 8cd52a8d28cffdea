"""The demo's warm-up compiles the default placement's kernels, and the import's: once it ran, the default on a room
takes a fraction of the warm-up's first time, and importing and placing a real level needs no kernel variant the
warm-up did not compile (else a checkout's first `make demo` would count that compilation as their time)."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

from lpnn.quality.placement.warmup import compile_placement_kernels

TRAINING = Path(__file__).resolve().parents[2]

# In a fresh process (nothing compiled or loaded yet): the warm-up, then the variants of every numba kernel of lpnn
# that an import and the default's placements (leak-aware and leak-blind) add to what the warm-up made. A variant
# loaded from the disk cache counts too: on a fresh clone it would be compiled.
NEW_VARIANTS = textwrap.dedent("""
    import json, sys
    from pathlib import Path
    from numba.core.registry import CPUDispatcher
    from lpnn.quality.placement.warmup import compile_placement_kernels

    def variants():
        found = set()
        for module in list(sys.modules.values()):
            if getattr(module, "__name__", "").startswith("lpnn"):
                for kernel in vars(module).values():
                    if isinstance(kernel, CPUDispatcher):
                        name = kernel.py_func.__module__ + "." + kernel.py_func.__qualname__
                        found.update((name, str(signature)) for signature in kernel.signatures)
        return found

    compile_placement_kernels()
    from lpnn.core.grid import EvaluationGrid
    from lpnn.quality.metric.leaks import field_with_geometry
    from lpnn.quality.placement.leak_aware import leaks_to_avoid
    from lpnn.quality.placement.refined_insertion import refined_insertion
    from lpnn.scenes.importer import import_level
    from lpnn.scenes.levels import load_pak_member
    before = variants()
    capture = import_level(load_pak_member(Path(sys.argv[1]), "maps/fan.bsp"), timings_in_source=False).capture
    field = field_with_geometry(capture)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    for choice in ("avoid", "ignore"):
        refined_insertion(field, grid, tolerance=0.05, leaks=leaks_to_avoid(field, choice))
    print(json.dumps(sorted(variants() - before)))
""")


def test_the_warm_up_runs_the_default_and_reports_its_seconds() -> None:
    first = compile_placement_kernels()
    again = compile_placement_kernels()
    assert math.isfinite(first) and first > 0.0
    assert 0.0 < again <= first + 0.5  # compiled (or cached) by the first call: never slower than it


def test_a_level_imported_and_placed_after_the_warm_up_needs_no_other_kernel_variant(openarena_pak: Path) -> None:
    """fan (validation level): its points outside the probes' hull reach the hull projection's centroid tree and
    certificate, which the warm-up's room alone never did (~1.3 s compiled inside the default's first timed run)."""
    environment = dict(os.environ, PYTHONPATH=str(TRAINING))
    printed = subprocess.run([sys.executable, "-c", NEW_VARIANTS, str(openarena_pak)], check=True, capture_output=True,
                             text=True, env=environment).stdout
    assert json.loads(printed.strip().splitlines()[-1]) == []
