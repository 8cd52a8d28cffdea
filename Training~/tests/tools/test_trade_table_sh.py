"""Tools~/experiments/trade-table.sh (benchmarks.md "The speed/accuracy trade, every method") on tiny inputs: every set runs (`lpnn bench` on tiny captures,
oa_dm1 at a coarse cell, make demo's script), each with its wall time, and the table has a row per set."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import write_capture
from tools_support import run_experiment

pytestmark = [pytest.mark.openarena, pytest.mark.slow]


def test_every_set_and_the_table(openarena_pak: Path, tmp_path: Path) -> None:
    captures = {}
    for name, seed in (("heldcrops", 1), ("valcrops", 2), ("ctf", 3), ("suspended", 4)):
        folder = tmp_path / name
        folder.mkdir()
        captures[name] = write_capture(folder / f"{name}.lpnncap",
                                       AnalyticScene.random(seed, cell_size=0.8).capture(name=name))
    out = tmp_path / "out"
    done = run_experiment("trade-table.sh", str(out), env={
        "LPNN_OPENARENA_PAK": str(openarena_pak), "HELD_CROPS": str(tmp_path / "heldcrops"),
        "VAL_CROPS": str(tmp_path / "valcrops"), "CTF": str(captures["ctf"]), "SUSPENDED": str(captures["suspended"]),
        "LEVEL3_CELL": "4"})
    walls = dict(line.split() for line in (out / "walls.txt").read_text(encoding="utf-8").splitlines())
    assert set(walls) == {"heldcrops", "valcrops", "oa_dm1", "ctf_compromise", "suspended", "demo"}
    assert "exit code" not in done.stderr, done.stderr  # a run that fails is logged and the script goes on
    for name in set(walls) - {"demo"}:
        assert (out / name / "bench.csv").is_file()
    assert json.loads((out / "summary.json").read_text(encoding="utf-8"))["level"] == "oa_dm1"
    table = (out / "table.md").read_text(encoding="utf-8")
    assert table == done.stdout
    rows = [line for line in table.splitlines() if line.startswith("| ")]
    for label in ("held-out crops", "validation crops", "oa_dm1, the demo's level (held out)",
                  "ctf_compromise (validation)", "suspended at 1.3 m (held out)", "make demo (oa_dm1, points in use)"):
        assert any(row.startswith(f"| {label} (") for row in rows), label
