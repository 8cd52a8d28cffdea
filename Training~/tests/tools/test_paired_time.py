"""Tools~/experiments/paired-time.py (how benchmarks.md's paired speed figures are taken): A and B in turn, a row per
counted pair, ratios pair by pair; a failing command fails it."""

from __future__ import annotations

import re
import subprocess
import sys

from tools_support import EXPERIMENTS_DIR, REPO, run_experiment

BUSY = f"{sys.executable} -c \"sum(i * i for i in range(3_000_000))\""  # ~0.2 s of CPU
IDLE = [sys.executable, "-c", "pass"]


def test_a_row_per_counted_pair_and_ratios_that_see_the_slower_command() -> None:
    lines = run_experiment("paired-time.py", "-n", "2", "--warmup", "1", "--vs", BUSY, "--", *IDLE).stdout.splitlines()
    assert lines[0].startswith("pair | A wall s")
    rows = [line for line in lines if re.match(r"\d+ \| ", line)]
    assert [row.split(" | ")[0] for row in rows] == ["1", "2"]
    for row in rows:
        a_wall, a_cpu, b_wall, b_cpu, wall_ratio = (float(v) for v in row.split(" | ")[1:6])
        assert 0 < a_wall < b_wall and b_cpu > a_cpu >= 0 and abs(wall_ratio * b_wall - a_wall) < 2e-3  # printed to 1 ms
    ratio = re.search(r"A/B wall ([0-9.]+) \(([0-9.]+)-([0-9.]+)\)", "\n".join(lines))
    assert ratio and float(ratio.group(2)) <= float(ratio.group(1)) <= float(ratio.group(3)) < 1.0  # the idle one is A


def test_a_failing_command_fails_the_call() -> None:
    result = subprocess.run([sys.executable, str(EXPERIMENTS_DIR / "paired-time.py"), "-n", "1", "--warmup", "0",
                             "--vs", BUSY, "--", sys.executable, "-c", "raise SystemExit(3)"],
                            cwd=REPO, capture_output=True, text=True, timeout=120)
    assert result.returncode != 0 and "exited with 3" in result.stderr


def test_a_run_over_the_timeout_fails_the_call() -> None:
    result = subprocess.run([sys.executable, str(EXPERIMENTS_DIR / "paired-time.py"), "-n", "1", "--warmup", "0",
                             "--timeout", "0.5", "--vs", BUSY, "--", sys.executable, "-c", "import time; time.sleep(5)"],
                            cwd=REPO, capture_output=True, text=True, timeout=120)
    assert result.returncode != 0 and "longer than --timeout 0.5 s" in result.stderr


def test_without_a_baseline_it_times_the_command_alone() -> None:
    lines = run_experiment("paired-time.py", "-n", "2", "--warmup", "0", "--", *IDLE).stdout.splitlines()
    assert lines[0] == "run | wall s | CPU s | peak MB so far"
    assert [line.split(" | ")[0] for line in lines[1:3]] == ["1", "2"]
    assert re.fullmatch(r"median wall s [0-9.]+ \([0-9.]+-[0-9.]+\), median CPU s [0-9.]+ \([0-9.]+-[0-9.]+\)", lines[3])
