"""Tools~/experiments/csharp-selection-bench.sh (benchmarks.md "The C# core under Mono") runs: one batched round on a tiny
lattice; the whole leak-blind selection under Mono (--apply --leaks ignore) on a small synthetic capture with Python's
tetrahedraliser over a pipe; and the leak-aware default (--apply) on a real level, given lpnn place's own rays, keeping
exactly lpnn place's probes. It prints figures and asserts nothing; this checks that each mode still builds, runs and
prints its table, and the parity it prints (Mono is installed by Tools~/install-system.sh for the C# tests of make test)."""

from __future__ import annotations

import struct
import subprocess
import sys
from pathlib import Path

import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import write_capture
from lpnn.scenes.capture_geometry import capture_triangles
from lpnn.scenes.importer import import_level
from lpnn.scenes.levels import load_pak_member

ROOT = Path(__file__).resolve().parents[3]
BENCH = ROOT / "Tools~" / "experiments" / "csharp-selection-bench.sh"
TRIANGLES = ROOT / "Tools~" / "experiments" / "SelectionBench" / "write_capture_triangles.py"


def _bench(*arguments: str) -> str:
    result = subprocess.run(["bash", str(BENCH), *arguments], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout


def test_one_batched_round_on_a_tiny_lattice() -> None:
    assert "\n216 | " in _bench("--batched", "6")


def test_the_whole_leak_blind_selection_under_mono(tmp_path: Path) -> None:
    capture = AnalyticScene.random(2, cell_size=0.5).capture(name="room")
    path = write_capture(tmp_path / "room.lpnncap", capture)
    out = _bench("--apply", "--leaks", "ignore", str(path))
    assert "leak-blind" in out and "probes kept:" in out and "total" in out


def test_the_leak_aware_apply_needs_the_levels_geometry(tmp_path: Path) -> None:
    capture = AnalyticScene.random(2, cell_size=0.5).capture(name="room")
    path = write_capture(tmp_path / "room.lpnncap", capture)
    result = subprocess.run(["bash", str(BENCH), "--apply", str(path)], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert result.returncode != 0 and "no level geometry for the leak-aware Apply" in result.stderr, result.stderr


@pytest.mark.openarena
def test_the_leak_aware_apply_keeps_lpnn_places_probes_given_its_rays(openarena_pak: Path, tmp_path: Path) -> None:
    # q3dm6ish (validation) at its default cell: 2,100 points; lpnn place keeps 433 probes there (benchmarks.md).
    capture = import_level(load_pak_member(openarena_pak, "maps/q3dm6ish.bsp"), timings_in_source=False).capture
    path = write_capture(tmp_path / "q3dm6ish.lpnncap", capture)
    out = _bench("--apply", "--rays", "embree", "--compare", str(path))
    assert "rays through Python's Embree" in out and "leak repair of the seed" in out, out
    assert "THE SAME PROBES" in out, out
    # The C# hierarchy's input: the triangles lpnn place casts against, counted in the file's header.
    subprocess.run([sys.executable, str(TRIANGLES), str(path), str(tmp_path / "triangles.bin")], check=True,
                   env={"PYTHONPATH": str(ROOT / "Training~")})
    vertices, triangles = capture_triangles(capture)[0]
    data = (tmp_path / "triangles.bin").read_bytes()
    assert struct.unpack("<ii", data[:8]) == (vertices.shape[0], triangles.shape[0])
    assert len(data) == 8 + 24 * vertices.shape[0] + 12 * triangles.shape[0]
