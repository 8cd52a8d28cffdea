"""The warm-ups before anything is timed: the demo's compiles the default placement's kernels and the import's, the
benchmark's runs every method of its config on a synthetic room. Once they ran, importing, placing and benchmarking a
real level needs no kernel variant they did not make (else a checkout's first `make demo` or `lpnn bench` would count
numba's compilation, or the loading of its disk cache, as the first capture's time)."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from lpnn.quality.placement import warmup
from lpnn.cli.main import main
from lpnn.quality.placement.warmup import compile_placement_kernels, kernels_warm, partner_process, warm_up_marker
from lpnn.quality.placement.warmup_partner import compile_late_kernels

TRAINING = Path(__file__).resolve().parents[2]

# Run in a fresh process (nothing compiled or loaded yet): a warm-up, then every numba kernel variant of lpnn that the
# work on a real level (the pak is argv[1]) adds to the ones the warm-up made. A variant loaded from the disk cache
# counts too: on a fresh clone it would be compiled.
PROLOGUE = """
import json, sys
from pathlib import Path
from numba.core.registry import CPUDispatcher
from lpnn.scenes.importer import import_level
from lpnn.scenes.levels import load_pak_member

def variants():
    found = set()
    for module in list(sys.modules.values()):
        if getattr(module, "__name__", "").startswith("lpnn"):
            for kernel in vars(module).values():
                if isinstance(kernel, CPUDispatcher):
                    name = kernel.py_func.__module__ + "." + kernel.py_func.__qualname__
                    found.update((name, str(signature)) for signature in kernel.signatures)
    return found

def level(name):
    return import_level(load_pak_member(Path(sys.argv[1]), f"maps/{name}.bsp"), timings_in_source=False).capture
"""

DEMO = PROLOGUE + """
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.metric.leaks import field_with_geometry
from lpnn.quality.placement.leak_aware import leaks_to_avoid
from lpnn.quality.placement.refined_insertion import refined_insertion
from lpnn.quality.placement.warmup import compile_placement_kernels
compile_placement_kernels()
before = variants()
capture = level("fan")
field = field_with_geometry(capture)
grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
for choice in ("avoid", "ignore"):
    refined_insertion(field, grid, tolerance=0.05, leaks=leaks_to_avoid(field, choice))
print(json.dumps(sorted(variants() - before)))
"""

BENCH = PROLOGUE + """
from lpnn.quality.bench.results import BenchConfig
from lpnn.quality.bench.run import bench_capture
from lpnn.quality.bench.warmup import warm_up_bench
from lpnn.scenes.capture_geometry import capture_raycaster
config = BenchConfig(budgets=(0.05,), tolerance=0.05, repeats=1)
warm_up_bench(config)
before = variants()
capture = level("q3dm6ish")
bench_capture("q3dm6ish", capture, config, geometry=capture_raycaster(capture)[0])
print(json.dumps(sorted(variants() - before)))
"""


def _new_variants(script: str, pak: Path) -> list:
    environment = dict(os.environ, PYTHONPATH=str(TRAINING))
    printed = subprocess.run([sys.executable, "-c", script, str(pak)], check=True, capture_output=True, text=True,
                             env=environment).stdout
    return json.loads(printed.strip().splitlines()[-1])


def test_the_warm_up_runs_the_default_and_reports_its_seconds() -> None:
    first = compile_placement_kernels()
    again = compile_placement_kernels()
    assert math.isfinite(first) and first > 0.0
    assert 0.0 < again <= first + 0.5  # compiled (or cached) by the first call: never slower than it


def test_the_partner_runs_the_refinement_and_a_repair_derived_by_insertion() -> None:
    """What it must reach before the warm-up does: the refinement's rounds (from every point of the room) and the leak
    repair's (which adds probes where the sparse seed leaks)."""
    work = compile_late_kernels()
    assert work.refinement_rounds > 0
    assert work.repaired > work.repair_seed


def test_the_partner_command_runs_to_the_end(tmp_path: Path) -> None:
    """The command the warm-up starts (its output is discarded there, so a module renamed would only make the warm-up
    slower, silently): with its stdin open, as the warm-up keeps it, it exits 0."""
    errors = tmp_path / "stderr.txt"
    with open(errors, "w") as stderr:
        partner = subprocess.Popen(list(warmup.PARTNER_COMMAND), stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                   stderr=stderr, env=dict(os.environ, PYTHONPATH=str(TRAINING)))
        try:
            code = partner.wait(timeout=600)
        finally:
            partner.stdin.close()
            if partner.poll() is None:
                partner.kill()
    assert code == 0, errors.read_text()[-2000:]


def test_the_partner_is_stopped_when_the_block_ends() -> None:
    with partner_process([sys.executable, "-c", "import time; time.sleep(60)"]) as process:
        assert process is not None and process.poll() is None
    assert process.poll() is not None


def test_a_failing_partner_changes_nothing_and_one_core_has_none(monkeypatch: pytest.MonkeyPatch) -> None:
    seconds = compile_placement_kernels(partner=[sys.executable, "-c", "raise SystemExit(3)"])
    assert math.isfinite(seconds) and seconds > 0.0
    with partner_process([str(TRAINING / "no-such-program")]) as process:  # cannot start: the warm-up alone
        assert process is None
    monkeypatch.setattr(warmup.os, "cpu_count", lambda: 1)
    with partner_process(warmup.PARTNER_COMMAND) as process:
        assert process is None
    with partner_process(None) as process:
        assert process is None
    monkeypatch.setattr(warmup.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(warmup, "can_guard", lambda: False)  # the cache's files cannot be locked: no sharing
    with partner_process(warmup.PARTNER_COMMAND) as process:
        assert process is None


def test_the_partner_stops_when_its_stdin_closes() -> None:
    """So that it never outlives the warm-up's process, even one killed before it could stop the partner."""
    script = ("import threading, time\n"
              "from lpnn.quality.placement.warmup_partner import _stop_when_stdin_closes\n"
              "threading.Thread(target=_stop_when_stdin_closes, daemon=True).start()\n"
              "print('ready', flush=True)\n"
              "time.sleep(120)\n")
    partner = subprocess.Popen([sys.executable, "-c", script], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               text=True, env=dict(os.environ, PYTHONPATH=str(TRAINING)))
    try:
        assert partner.stdout.readline().strip() == "ready"
        partner.stdin.close()
        assert partner.wait(timeout=60) == -signal.SIGTERM
    finally:
        if partner.poll() is None:
            partner.kill()


def test_the_marker_is_named_by_the_sources_and_an_edit_renames_it(tmp_path: Path) -> None:
    """What numba's disk cache keys on (a source's path, size and modification time): the same sources give the same
    name, an edited one (here only its modification time) another, so a warm-up of older sources does not count."""
    package = tmp_path / "lpnn"
    (package / "quality").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    kernel = package / "quality" / "kernel.py"
    kernel.write_text("x = 1\n")
    os.utime(kernel, ns=(1_000_000_000, 1_000_000_000))
    first = warm_up_marker(package)
    assert warm_up_marker(package) == first and not kernels_warm(package)
    warmup._leave(first)
    assert kernels_warm(package) and first.read_bytes() == b""
    os.utime(kernel, ns=(2_000_000_000, 2_000_000_000))
    assert warm_up_marker(package) != first and not kernels_warm(package)
    first.unlink()


def test_a_finished_warm_up_leaves_the_marker_of_this_checkout() -> None:
    compile_placement_kernels(partner=None)
    assert kernels_warm()
    assert warm_up_marker().parent.name == warmup.MARKER_FOLDER


def test_lpnn_place_warms_up_first_only_where_no_warm_up_finished(capture_files: list[Path], tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    """The default method on a fresh checkout compiles before it places (so its printed times are the work's), and
    says so; once a warm-up finished for these sources it does not."""
    calls = []
    monkeypatch.setattr(warmup, "compile_placement_kernels", lambda: calls.append(1) or 12.25)
    for warm in (False, True):
        monkeypatch.setattr(warmup, "kernels_warm", lambda warm=warm: warm)
        assert main(["place", str(capture_files[0]), "--tolerance", "0.05", "--out", str(tmp_path / "p.json")]) == 0
        err = capsys.readouterr().err
        assert ("compiling the placement kernels first" in err and "compiled in 12.2 s" in err) == (not warm)
    assert calls == [1]


def test_a_level_imported_and_placed_after_the_warm_up_needs_no_other_kernel_variant(openarena_pak: Path) -> None:
    """fan (validation level): its points outside the probes' hull reach the hull projection's centroid tree and
    certificate, which the warm-up's room alone never did (~1.3 s compiled inside the default's first timed run)."""
    assert _new_variants(DEMO, openarena_pak) == []


def test_a_benchmark_after_its_warm_up_needs_no_other_kernel_variant(openarena_pak: Path) -> None:
    """`lpnn bench` warms each process up with every method of its config on a synthetic room (warm_up_bench): a real
    level's whole benchmark then adds no kernel variant, so its first capture's times hold no compilation (the
    default took 31.5 s on a fresh checkout's first crop before) and no cache loading (~0.3 s)."""
    assert _new_variants(BENCH, openarena_pak) == []
