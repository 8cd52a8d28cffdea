"""Tools~/experiments/spread-bench.py (benchmarks.md "Scale: whole levels") on two tiny lattices: a row of figures per size."""

from __future__ import annotations

import re

from tools_support import run_experiment


def test_a_row_per_lattice() -> None:
    lines = run_experiment("spread-bench.py", "4", "6").stdout.splitlines()
    assert lines[0] == "points | spread ranking s | peak memory GB"
    rows = [re.fullmatch(r"(\d+) \| ([0-9.]+) \| ([0-9.]+)", line) for line in lines[1:]]
    assert all(rows) and [int(r.group(1)) for r in rows] == [64, 216]
    assert all(float(r.group(3)) > 0 for r in rows)
