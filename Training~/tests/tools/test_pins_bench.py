"""Tools~/experiments/pins-bench.py (benchmarks.md "Pinned probes") on a synthetic room: a row per pin set, every pin kept and the
tolerance met, the rows written to its CSV."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import write_capture

ROOT = Path(__file__).resolve().parents[3]


def test_a_row_per_pin_set_within_the_tolerance(tmp_path: Path) -> None:
    capture = AnalyticScene.random(3, cell_size=0.5).capture(name="room")
    path = write_capture(tmp_path / "room.lpnncap", capture)
    out = tmp_path / "rows.csv"
    result = subprocess.run([sys.executable, str(ROOT / "Tools~" / "experiments" / "pins-bench.py"), str(path), "--out", str(out)],
                            cwd=ROOT, capture_output=True, text=True, timeout=600,
                            env={**os.environ, "PYTHONPATH": str(ROOT / "Training~")})
    assert result.returncode == 0, result.stdout + result.stderr
    lines = out.read_text().splitlines()
    assert lines[0].startswith("capture,points,pins,pinned")
    rows = [dict(zip(lines[0].split(","), line.split(","))) for line in lines[1:]]
    assert [row["pins"] for row in rows] == ["none", "lattice/4", "random-5%-moved"]
    for row in rows:
        assert float(row["mean_error"]) <= 0.05 and int(row["probes"]) >= int(row["pinned"])
    assert int(rows[1]["pinned"]) > 0 and int(rows[2]["pinned"]) > 0
