"""`lpnn bench`'s options for whole levels (the trade table, benchmarks.md): a subset of methods, no budget rows, the
fast reference stopped above an error, or no reference at all; each gives the rows a full run gives, minus what it
leaves out."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.main import main
from lpnn.core.capture import Capture
from lpnn.quality.bench.results import BenchConfig
from lpnn.quality.bench.run import bench_capture

CONFIG = BenchConfig(budgets=(0.1, 0.2), tolerance=0.05, repeats=1, faithful_limit=0)


def _answers(rows) -> dict:
    return {(row.method, row.policy, row.parameter): (row.probes, row.mean_error) for row in rows}


@pytest.fixture(scope="module")
def full_run(small_captures: dict[int, Capture]):
    return bench_capture("room2", small_captures[2], CONFIG)


def test_a_subset_of_methods_gives_their_rows_and_the_yardsticks(small_captures: dict[int, Capture], full_run) -> None:
    subset = bench_capture("room2", small_captures[2], replace(CONFIG, methods=frozenset({"heuristic", "insertion-refined"})))
    assert {row.method for row in subset.rows} == {"heuristic", "insertion-refined", "fast-reference"}
    full = _answers(full_run.rows)
    assert all(full[key] == answer for key, answer in _answers(subset.rows).items())
    assert {row.method for row in full_run.rows} >= {"uniform", "random", "insertion", "heuristic", "insertion-refined"}


def test_without_budgets_only_the_tolerance_rows_run(small_captures: dict[int, Capture], full_run) -> None:
    result = bench_capture("room2", small_captures[2], replace(CONFIG, budgets=(), methods=frozenset({"uniform"})))
    assert [(row.method, row.policy) for row in result.rows] == [("uniform", "tolerance"), ("fast-reference", "tolerance")]
    assert _answers(result.rows).items() <= _answers(full_run.rows).items()


def test_the_stopped_reference_is_the_full_one_down_to_its_stop(small_captures: dict[int, Capture], full_run) -> None:
    stopped = bench_capture("room2", small_captures[2], replace(CONFIG, reference_stop=0.06))
    curve, full_curve = stopped.reference_curve, full_run.reference_curve
    known = np.isfinite(curve)
    assert known.sum() < np.isfinite(full_curve).sum()  # it stopped early
    assert np.array_equal(curve[known], full_curve[known])
    full = {(r.method, r.policy, r.parameter): r for r in full_run.rows}
    for row in stopped.rows:
        twin = full[(row.method, row.policy, row.parameter)]
        assert (row.probes, row.mean_error) == (twin.probes, twin.mean_error)
        if row.policy == "tolerance":
            assert row.reference_probes == twin.reference_probes and row.probes_ratio == twin.probes_ratio
        elif known[max(row.probes, 4)]:
            assert row.error_ratio == twin.error_ratio
        else:  # a count below the stop: no ratio
            assert math.isnan(row.error_ratio)


def test_without_a_reference_the_rows_have_no_ratio(small_captures: dict[int, Capture], full_run) -> None:
    result = bench_capture("room2", small_captures[2], replace(CONFIG, yardstick="none"))
    assert result.yardstick == "none" and "fast-reference" not in {row.method for row in result.rows}
    assert {row.policy for row in result.rows} == {"budget", "tolerance"}
    for row in result.rows:
        assert row.yardstick == "none" and math.isnan(row.error_ratio) and row.probes_ratio is None
    assert _answers(result.rows).items() <= _answers(full_run.rows).items()


def test_the_cli_names_unknown_methods_and_conflicting_options(capture_files: list[Path], tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["bench", str(capture_files[0]), "--methods", "insertion,magic", "--out", str(tmp_path / "b")])
    assert "magic" in capsys.readouterr().err
    code = main(["bench", str(capture_files[0]), "--no-reference", "--reference-stop", "0.1", "--out", str(tmp_path / "b")])
    assert code != 0
    code = main(["bench", str(capture_files[0]), "--methods", "uniform", "--no-budgets", "--no-reference",
                 "--repeats", "1", "--out", str(tmp_path / "ok")])
    assert code == 0
    lines = (tmp_path / "ok" / "bench.csv").read_text().splitlines()
    assert len(lines) == 2 and ",uniform,tolerance," in lines[1] and ",none," in lines[1]
