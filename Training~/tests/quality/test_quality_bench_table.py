"""Tools~/experiments/bench-table.py: geometric means with the count of the ratios they leave out (issue 17, item 11)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from lpnn.quality.bench.results import BenchRow, rows_csv

SCRIPT = Path(__file__).resolve().parents[3] / "Tools~" / "experiments" / "bench-table.py"
METHODS = ("network", "guided", "guided-exact-refined", "insertion", "heuristic", "apv", "uniform")


def _row(capture: str, method: str, policy: str, ratio: float) -> BenchRow:
    tolerance = policy == "tolerance"
    return BenchRow(capture=capture, points=100, method=method, policy=policy, parameter=0.05 if tolerance else 0.2,
                    probes=10, seconds=0.01, feature_seconds=None, inference_seconds=None, selection_seconds=None,
                    refine_seconds=0.5, mean_error=0.1, p95_error=0.2, smape_mean=0.1, smape_p95=0.2,
                    reference_error=0.1, error_ratio=1.0 if tolerance else ratio,
                    reference_probes=10 if tolerance else None, probes_ratio=ratio if tolerance else None)


def test_means_leave_out_non_finite_ratios_and_say_how_many(tmp_path: Path) -> None:
    rows = []
    for capture, lpnn_ratio in (("a", 2.0), ("b", float("inf")), ("c", 8.0)):
        for method in (*METHODS, "fast-reference"):
            for policy in ("budget", "tolerance"):
                rows.append(_row(capture, method, policy, lpnn_ratio if method == "network" else 1.5))
    rows = [r for r in rows if not (r.capture == "c" and r.method == "apv")]  # apv failed on c: no rows
    path = tmp_path / "bench.csv"
    path.write_text(rows_csv(rows), encoding="utf-8")
    printed = subprocess.run([sys.executable, str(SCRIPT), str(path)], check=True, capture_output=True,
                             text=True).stdout.splitlines()
    mean = next(line for line in printed if line.startswith("| **geometric mean**")).split("|")[2:-1]
    left_out = next(line for line in printed if line.startswith("| ratios left out")).split("|")[2:-1]
    assert mean[0].strip() == "**4.00**"  # lpnn @20 %: sqrt(2 x 8), the infinite ratio left out
    # Budget columns (7 methods), then tolerance columns: lpnn leaves out b's infinite ratio, apv the missing c.
    assert [cell.strip() for cell in left_out[:14]] == ["1", "0", "0", "0", "0", "1", "0", "1", "0", "0", "0", "0", "1", "0"]


def test_summary_row_per_method_with_left_out_counts(tmp_path: Path) -> None:
    rows = [_row(capture, method, policy, ratio)
            for capture, ratio in (("a", 2.0), ("b", float("inf")), ("c", 8.0))
            for method in ("network", "insertion") for policy in ("budget", "tolerance")]
    path = tmp_path / "bench.csv"
    path.write_text(rows_csv(rows), encoding="utf-8")
    printed = subprocess.run([sys.executable, str(SCRIPT), str(path), "--summary"], check=True, capture_output=True,
                             text=True).stdout.splitlines()
    assert "| network | 4.00 (1) | 4.00 (1) |" in printed and "| insertion | 4.00 (1) | 4.00 (1) |" in printed


def test_leak_aware_rows_get_a_second_line_against_the_leak_aware_reference(tmp_path: Path) -> None:
    rows = []
    for capture, aware in (("a", 1.0), ("b", 4.0)):
        for method in ("insertion-refined", "insertion"):
            for policy in ("budget", "tolerance"):
                row = _row(capture, method, policy, 2.0)
                if method == "insertion-refined":  # measured against the leak-aware reference too (bench/run.py)
                    row.leak_error_ratio = aware if policy == "budget" else 1.0
                    row.leak_probes_ratio = aware if policy == "tolerance" else None
                rows.append(row)
    path = tmp_path / "bench.csv"
    path.write_text(rows_csv(rows), encoding="utf-8")
    printed = subprocess.run([sys.executable, str(SCRIPT), str(path), "--summary"], check=True, capture_output=True,
                             text=True).stdout.splitlines()
    assert "| insertion-refined | 2.00 | 2.00 |" in printed
    assert "| insertion-refined ×leak-aware ref | 2.00 | 2.00 |" in printed  # sqrt(1 x 4)
    assert not any(line.startswith("| insertion ×leak-aware ref") for line in printed)  # a leak-blind method
    trade = subprocess.run([sys.executable, str(SCRIPT), "--trade", f"crops={path}"], check=True, capture_output=True,
                           text=True).stdout.splitlines()
    line = next(line for line in trade if "×leak-aware ref" in line).split("|")
    assert line[2].strip() == "**insertion-refined** (default) ×leak-aware ref" and line[3].strip() == "2.00"
    assert line[4].strip() == "2.00" and line[-2].strip() == "against the leak-aware reference"
