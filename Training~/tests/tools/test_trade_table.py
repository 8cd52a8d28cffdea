"""Tools~/experiments/bench-table.py --trade (benchmarks.md "The speed/accuracy trade, every method") on tiny bench.csv files: a row
per set and method with the geometric means and median times, a reason for every method without rows, a yardstick given
from elsewhere, make demo's summary.json; and --summary keeps every method (issue 34: insertion-refined and guided-refined
were left out)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from lpnn.quality.bench.results import BenchRow, rows_csv

SCRIPT = Path(__file__).resolve().parents[3] / "Tools~" / "experiments" / "bench-table.py"


def _row(capture: str, method: str, policy: str, parameter: float, ratio: float, seconds: float, points: int = 900,
         yardstick: str = "fast-reference", probes: int = 10) -> BenchRow:
    tolerance = policy == "tolerance"
    no_reference = yardstick == "none"
    return BenchRow(capture=capture, points=points, method=method, policy=policy, parameter=parameter, probes=probes,
                    seconds=seconds, feature_seconds=None, inference_seconds=None, selection_seconds=None,
                    refine_seconds=None, mean_error=0.05, p95_error=0.1, smape_mean=0.1, smape_p95=0.2,
                    reference_error=float("nan") if no_reference else 0.05,
                    error_ratio=float("nan") if no_reference else (1.0 if tolerance else ratio),
                    reference_probes=None if no_reference or not tolerance else 10,
                    probes_ratio=None if no_reference or not tolerance else ratio, yardstick=yardstick)


def _run(*args: str) -> list[str]:
    result = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout.splitlines()


def _cells(lines: list[str], set_label: str, method: str) -> list[str]:
    """A method's cells in a set (the set's name stands on its first row only)."""
    current = None
    for line in lines[2:]:
        if not line.startswith("| "):
            continue
        first = line.split("|")[1].strip()
        current = first or current
        if current == set_label and line.split("|")[2].strip() == method:
            return [cell.strip() for cell in line.split("|")[3:-1]]
    raise AssertionError(f"no row {method} in {set_label}")


def test_the_trade_table_of_crops_a_level_without_reference_and_the_demo(tmp_path: Path) -> None:
    crops = tmp_path / "crops"
    crops.mkdir()
    rows = [_row(capture, method, policy, parameter, ratio, seconds)
            for capture, ratio, seconds in (("a", 1.0, 0.5), ("b", 4.0, 1.5), ("c", 1.0, 2.5))
            for method in ("insertion-refined", "guided-refined", "insertion", "uniform", "fast-reference")
            for policy, parameter in (("budget", 0.01), ("budget", 0.2), ("tolerance", 0.05))]
    rows = [r for r in rows if not (r.method == "uniform" and r.capture == "c")]  # uniform failed on c
    (crops / "bench.csv").write_text(rows_csv(rows), encoding="utf-8")
    (crops / "failures.csv").write_text("capture,method,reason\nc,heuristic,ValueError: flat\n", encoding="utf-8")
    level = tmp_path / "level"
    level.mkdir()
    big = [_row("big", method, "tolerance", 0.05, 1.0, 60.0, points=1_000_000, yardstick="none", probes=probes)
           for method, probes in (("insertion-refined", 2000), ("guided-refined", 2000), ("heuristic", 4000))]
    (level / "bench.csv").write_text(rows_csv(big), encoding="utf-8")
    demo = tmp_path / "summary.json"
    demo.write_text(json.dumps({"level": "oa_dm1", "points": 607, "tolerance": 0.05, "methods": {
        "insertion-refined": {"probes": 313, "mean_error": 0.05, "seconds": {"selection": 0.3, "refinement": 0.5}},
        "fast-reference": {"probes": 310, "mean_error": 0.05, "seconds": {"reference": 1.7}}}}), encoding="utf-8")
    lines = _run("--trade", f"crops={crops / 'bench.csv'}", f"whole={level / 'bench.csv'}", f"the demo={demo}",
                 "--given-yardstick", "whole=4,000", "--note", "whole:guided-exact-refined=skipped: hours at this size",
                 "--note", "whole:blockwise-reference=not re-run: hours")
    assert lines[0].startswith("| set | method | error ×ref @1 % | error ×ref @20 % | probes ×ref @τ=0.05 | median s @20 % "
                               "| median s @τ | note |")
    # Geometric means over the crops (sqrt(1 x 4 x 1) = 1.59) and the median seconds per crop.
    assert _cells(lines, "crops (3 captures)", "**insertion-refined** (default)") == ["1.59", "1.59", "1.59", "1.50", "1.50", ""]
    assert _cells(lines, "crops (3 captures)", "uniform")[:3] == ["2.00 (1)", "2.00 (1)", "2.00 (1)"]
    assert _cells(lines, "crops (3 captures)", "heuristic")[-1] == "failed: ValueError: flat"
    assert _cells(lines, "crops (3 captures)", "guided-exact-refined")[-1] == "not run"
    assert _cells(lines, "crops (3 captures)", "fast-reference")[-1] == "the yardstick"
    # The level without a reference: probes over the given yardstick, budgets absent, the notes.
    whole = "whole (1,000,000 points)"
    assert _cells(lines, whole, "**insertion-refined** (default)") == ["–", "–", "0.50†", "–", "60.0", ""]
    assert _cells(lines, whole, "heuristic")[2] == "1.00†"
    assert _cells(lines, whole, "guided-refined")[-1].startswith("insertion-refined's answers (no guide above 32,768 points)")
    assert "skipped: hours at this size" in _cells(lines, whole, "guided-exact-refined")[-1]
    assert _cells(lines, whole, "fast-reference")[-1] == "not run: no reference (lpnn bench --no-reference)"
    # Without references the leak-aware one is absent for that reason, not for the geometry; on the crops, for the latter.
    assert _cells(lines, whole, "leak-aware-reference")[-1] == "not run: no reference (lpnn bench --no-reference)"
    assert _cells(lines, "crops (3 captures)", "leak-aware-reference")[-1].startswith("not run: the capture's geometry")
    assert _cells(lines, whole, "blockwise-reference")[-1] == "not re-run: hours"  # a note says why instead of "not run"
    assert _cells(lines, whole, "uniform")[-1] == "not run"
    # make demo's answers at tau.
    assert _cells(lines, "the demo (607 points)", "**insertion-refined** (default)") == ["–", "–", "1.01", "–", "0.80", ""]
    assert _cells(lines, "the demo (607 points)", "apv")[-1] == "not among make demo's methods"
    assert any(line.startswith("† probes over the yardstick's count") for line in lines)


def test_the_summary_keeps_every_method(tmp_path: Path) -> None:
    path = tmp_path / "bench.csv"
    path.write_text(rows_csv([_row("a", method, policy, parameter, 1.5, 1.0)
                              for method in ("insertion-refined", "guided-refined", "network", "fast-reference")
                              for policy, parameter in (("budget", 0.2), ("tolerance", 0.05))]), encoding="utf-8")
    lines = _run(str(path), "--summary")
    methods = [line.split("|")[1].strip() for line in lines if line.startswith("| ") and "method" not in line]
    assert methods == ["insertion-refined", "guided-refined", "network"]
