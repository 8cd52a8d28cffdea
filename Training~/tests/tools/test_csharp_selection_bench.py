"""Tools~/experiments/csharp-selection-bench.sh (benchmarks.md "The C# core under Mono") runs: one batched round on a tiny lattice, and the whole
default selection under Mono (--apply) on a small synthetic capture with Python's tetrahedraliser over a pipe. It prints
figures and asserts nothing; this checks that each mode still builds, runs and prints its table (Mono is installed by
Tools~/install-system.sh for the C# tests of make test)."""

from __future__ import annotations

import subprocess
from pathlib import Path

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import write_capture

ROOT = Path(__file__).resolve().parents[3]
BENCH = ROOT / "Tools~" / "experiments" / "csharp-selection-bench.sh"

def _bench(*arguments: str) -> str:
    result = subprocess.run(["bash", str(BENCH), *arguments], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout


def test_one_batched_round_on_a_tiny_lattice() -> None:
    assert "\n216 | " in _bench("--batched", "6")


def test_the_whole_default_selection_under_mono(tmp_path: Path) -> None:
    capture = AnalyticScene.random(2, cell_size=0.5).capture(name="room")
    path = write_capture(tmp_path / "room.lpnncap", capture)
    out = _bench("--apply", str(path))
    assert "probes kept:" in out and "total" in out
