"""`lpnn label`, `lpnn place`, `lpnn bench` end to end on small synthetic captures."""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.main import main
from lpnn.cli.scores_file import write_scores_csv
from lpnn.core.capture import Capture
from lpnn.core.capture_file import read_capture, write_capture
from lpnn.quality.bench.results import CSV_COLUMNS, BenchConfig
from lpnn.quality.bench.run import bench_capture
from lpnn.quality.placement.lpnn_placement import lpnn_placement
from lpnn.quality.metric.metric import ReferenceField, placement_error
from lpnn.quality.placement.decimation.reference_fast import fast_decimation


def test_label_round_trip_into_a_new_folder(capture_files: list[Path], tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "labelled"
    assert main(["label", *map(str, capture_files[:2]), "--budget", "0.2", "--out-dir", str(out), "--quiet"]) == 0
    for path in capture_files[:2]:
        original = read_capture(path)
        labelled = read_capture(out / path.name)
        assert labelled.label_source == "reference:fast-greedy budget=0.2"
        assert int(labelled.labels.sum()) == round(0.2 * original.point_count)
        np.testing.assert_array_equal(labelled.sh, original.sh)
        assert original.labels is None  # the source was not touched
        field = ReferenceField.from_capture(original)
        expected = fast_decimation(field, workers=1).prefix(int(labelled.labels.sum()))
        np.testing.assert_array_equal(np.flatnonzero(labelled.labels), expected)
    assert "positive" in capsys.readouterr().out
    # Never replaces an existing file: a second run into the same folder fails and writes nothing.
    before = (out / capture_files[0].name).read_bytes()
    assert main(["label", str(capture_files[0]), "--tolerance", "0.05", "--out-dir", str(out), "--quiet"]) == 1
    assert (out / capture_files[0].name).read_bytes() == before
    assert "exists" in capsys.readouterr().err


def test_label_in_place_with_tolerance_and_the_faithful_method(capture_files: list[Path]) -> None:
    path = capture_files[0]
    assert main(["label", str(path), "--tolerance", "0.05", "--method", "faithful", "--in-place", "--quiet"]) == 0
    labelled = read_capture(path)
    assert labelled.label_source == "reference:faithful-greedy tolerance=0.05"
    field = ReferenceField.from_capture(labelled)
    assert placement_error(field, np.flatnonzero(labelled.labels)).mean <= 0.05


def test_label_refuses_the_faithful_method_on_large_captures(tmp_path: Path, medium_capture: Capture,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "medium.lpnncap"
    write_capture(path, medium_capture)
    assert main(["label", str(path), "--budget", "0.1", "--method", "faithful", "--in-place", "--quiet"]) == 1
    assert "use --method fast" in capsys.readouterr().err


@pytest.mark.parametrize("method", ["fast-reference", "insertion", "insertion-refined", "uniform", "heuristic", "apv", "random"])
def test_place_writes_a_probes_file(capture_files: list[Path], tmp_path: Path, method: str,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / f"{method}.probes.json"
    assert main(["place", str(capture_files[1]), "--method", method, "--budget", "0.25", "--out", str(out)]) == 0
    document = json.loads(out.read_text(encoding="utf-8"))
    capture = read_capture(capture_files[1])
    assert document["format"] == "lpnn.probes" and document["version"] == 1 and document["space"] == "world"
    assert document["count"] == len(document["positions"]) == round(0.25 * capture.point_count)
    grid_points = {tuple(p) for p in capture.positions.tolist()}
    assert all(tuple(np.float32(p).tolist()) in grid_points for p in document["positions"])
    printed = capsys.readouterr().out
    assert "kept" in printed and "mean error" in printed
    assert "in use (not recorded): mean error n/a" in printed  # the fixture's captures hold no in-use section


def test_place_without_a_source_places_by_refined_insertion(capture_files: list[Path], tmp_path: Path) -> None:
    """The default method is the best one measured with the dense lighting (benchmarks.md "The speed/accuracy trade, every method"): insertion refined in
    batches."""
    default, explicit = tmp_path / "default.probes.json", tmp_path / "refined.probes.json"
    assert main(["place", str(capture_files[1]), "--budget", "0.25", "--out", str(default)]) == 0
    assert main(["place", str(capture_files[1]), "--method", "insertion-refined", "--budget", "0.25",
                 "--out", str(explicit)]) == 0
    assert json.loads(default.read_text(encoding="utf-8"))["positions"] == json.loads(explicit.read_text(encoding="utf-8"))["positions"]
    assert main(["place", str(capture_files[1]), "--method", "network-topk", "--budget", "0.25", "--out", str(default)]) == 1


def test_place_from_a_scores_file_with_a_tolerance(capture_files: list[Path], tmp_path: Path) -> None:
    capture = read_capture(capture_files[2])
    scores = np.random.default_rng(0).uniform(0, 1, capture.point_count)
    scores_file = tmp_path / "scores.csv"
    write_scores_csv(scores_file, capture.ids, scores.astype(np.float32))
    out = tmp_path / "scored.probes.json"
    assert main(["place", str(capture_files[2]), "--method", "network", "--scores", str(scores_file), "--tolerance", "0.1",
                 "--out", str(out)]) == 0
    document = json.loads(out.read_text(encoding="utf-8"))
    assert document["source"]["mean_error"] <= 0.1
    # --no-report: the same probes, the search's mean error, no final evaluation (no p95).
    quick = tmp_path / "quick.probes.json"
    assert main(["place", str(capture_files[2]), "--method", "network", "--scores", str(scores_file), "--tolerance", "0.1",
                 "--no-report", "--out", str(quick)]) == 0
    fast = json.loads(quick.read_text(encoding="utf-8"))
    assert fast["positions"] == document["positions"] and "p95_error" not in fast["source"]
    assert fast["source"]["mean_error"] == document["source"]["mean_error"]
    assert main(["place", str(capture_files[2]), "--method", "network", "--scores", str(scores_file), "--budget", "0.2",
                 "--no-report", "--out", str(quick)]) == 0
    assert "mean_error" not in json.loads(quick.read_text(encoding="utf-8"))["source"]


def test_place_refines_in_batches_with_scores_or_without(capture_files: list[Path], tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    capture = read_capture(capture_files[2])
    scores_file = tmp_path / "scores.csv"
    write_scores_csv(scores_file, capture.ids, np.linspace(0.1, 1.0, capture.point_count).astype(np.float32))
    batched, refined = tmp_path / "batched.probes.json", tmp_path / "refined.probes.json"
    assert main(["place", str(capture_files[2]), "--method", "guided-refined", "--scores", str(scores_file),
                 "--tolerance", "0.05", "--out", str(batched)]) == 0
    assert "batched refine 2" in capsys.readouterr().out
    assert json.loads(batched.read_text(encoding="utf-8"))["source"]["mean_error"] <= 0.05
    assert main(["place", str(capture_files[2]), "--method", "insertion-refined", "--tolerance", "0.05",
                 "--out", str(refined)]) == 0
    assert json.loads(refined.read_text(encoding="utf-8"))["source"]["mean_error"] <= 0.05


def test_place_rejects_scores_of_another_capture(capture_files: list[Path], tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    capture = read_capture(capture_files[0])
    scores_file = tmp_path / "scores.csv"
    write_scores_csv(scores_file, capture.ids[::-1].copy(), np.zeros(capture.point_count, dtype=np.float32))
    assert main(["place", str(capture_files[0]), "--method", "network", "--scores", str(scores_file), "--budget", "0.2",
                 "--out", str(tmp_path / "x.json")]) == 1
    assert "does not match" in capsys.readouterr().err


def test_label_reports_a_failing_capture_labels_the_others_and_exits_non_zero(
        capture_files: list[Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    broken = tmp_path / "in" / "broken.lpnncap"
    broken.parent.mkdir()
    broken.write_bytes(capture_files[0].read_bytes()[:200])  # truncated: reading it fails
    out = tmp_path / "labelled"
    code = main(["label", str(broken), str(capture_files[1]), "--budget", "0.2", "--out-dir", str(out), "--quiet"])
    assert code == 1
    assert read_capture(out / capture_files[1].name).labels is not None and not (out / broken.name).exists()
    err = capsys.readouterr().err
    assert "FAILED" in err and "broken.lpnncap" in err and "1 of 2 capture(s) failed" in err and "Traceback" not in err


def test_bench_end_to_end_writes_csv_and_figures(capture_files: list[Path], tmp_path: Path) -> None:
    out = tmp_path / "bench"
    assert main(["bench", str(capture_files[0]), "--budgets", "0.1,0.3", "--repeats", "1", "--out", str(out)]) == 0
    with (out / "bench.csv").open(encoding="utf-8", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert tuple(rows[0].keys()) == CSV_COLUMNS
    methods = {row["method"] for row in rows}
    assert methods == {"uniform", "random", "heuristic", "apv", "insertion", "insertion-refined", "fast-reference",
                       "faithful-reference"}
    assert {row["policy"] for row in rows} == {"budget", "tolerance"}
    assert len(rows) == 8 * 3
    assert not (out / "failures.csv").exists()
    for row in rows:
        assert float(row["mean_error"]) >= 0.0 and "," not in row["mean_error"]
        if row["method"].endswith("reference") and row["policy"] == "budget":
            assert float(row["error_ratio"]) == pytest.approx(1.0)
    for suffix in ("error", "time"):
        figure = out / f"{capture_files[0].stem}.{suffix}.png"
        assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bench_refuses_limits_it_cannot_use_naming_the_value(capture_files: list[Path], tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    for option, value, says in (("--full-reference-limit", "3", "must be at least 4 points"),
                                ("--refine-limit", "-1", "must be >= 0 points")):
        assert main(["bench", str(capture_files[0]), option, value, "--out", str(tmp_path / "bench")]) == 1
        err = capsys.readouterr().err
        assert f"{option} {value} {says}" in err and "Traceback" not in err
    assert not (tmp_path / "bench").exists()


def test_bench_goes_on_after_a_failing_capture_keeps_every_result_and_exits_non_zero(
        capture_files: list[Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    broken = tmp_path / "broken.lpnncap"
    broken.write_bytes(capture_files[0].read_bytes()[:200])  # a truncated capture: reading it fails
    out = tmp_path / "bench"
    code = main(["bench", str(broken), str(capture_files[1]), "--budgets", "0.2", "--no-tolerance",
                 "--repeats", "1", "--out", str(out)])
    assert code == 1
    with (out / "bench.csv").open(encoding="utf-8", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert {row["capture"] for row in rows} == {capture_files[1].stem} and len(rows) == 8
    with (out / "failures.csv").open(encoding="utf-8", newline="") as handle:
        failures = list(csv.DictReader(handle))
    assert [(f["capture"], f["method"]) for f in failures] == [("broken", "*")] and failures[0]["reason"]
    printed = capsys.readouterr().out
    assert "FAILED broken" in printed and "1 failure(s)" in printed and "Traceback" not in printed


def test_bench_records_a_failing_method_and_keeps_the_others(small_captures: dict[int, Capture],
                                                             monkeypatch: pytest.MonkeyPatch) -> None:
    import lpnn.quality.bench.methods as bench_methods

    def broken(*args: object, **kwargs: object) -> np.ndarray:
        raise ValueError("all 4 probes lie in one plane")

    monkeypatch.setattr(bench_methods, "InsertionOrder", broken)
    result = bench_capture("room1", small_captures[1], BenchConfig(budgets=(0.2,), repeats=1, faithful_limit=0))
    assert [(f.method, f.reason) for f in result.failures] == [("insertion", "ValueError: all 4 probes lie in one plane")]
    # insertion-refined runs its own insertion order (refined_insertion.py), untouched by the patch.
    assert {row.method for row in result.rows} == {"uniform", "random", "heuristic", "apv", "fast-reference",
                                                   "insertion-refined"}


class _StubScorer:
    """Stands in for OnnxScorer: scores = the DC luminance (any deterministic score will do)."""

    def check_capture(self, capture: Capture, name: str = "") -> None:
        pass

    def score_capture(self, capture: Capture, name: str = "") -> np.ndarray:
        return capture.sh[:, 0].astype(np.float32)


def test_bench_reports_the_lpnn_tiers_with_their_time_split(small_captures: dict[int, Capture]) -> None:
    capture = replace(small_captures[2], source={**small_captures[2].source, "feature_seconds": 0.25})
    config = BenchConfig(budgets=(0.2,), tolerance=0.05, repeats=1, faithful_limit=0)
    result = bench_capture("room2", capture, config, scorer=_StubScorer())
    by_method = {(row.method, row.policy): row for row in result.rows}
    assert {m for m, _ in by_method} == {"uniform", "random", "heuristic", "apv", "insertion", "insertion-refined",
                                          "fast-reference", "network-topk", "network", "guided", "guided-refined",
                                          "guided-exact-refined"}
    assert result.failures == []
    for method in ("network-topk", "network", "guided", "guided-refined", "guided-exact-refined"):
        row = by_method[(method, "budget")]
        assert row.feature_seconds == 0.25 and row.inference_seconds is not None and row.selection_seconds is not None
        # Every tier ranks inside its selection (the guided tier lazily, its rounds up to the row's count).
        assert row.seconds == pytest.approx(row.feature_seconds + row.inference_seconds + row.selection_seconds
                                            + (row.refine_seconds or 0.0))
        assert (row.refine_seconds is not None) == (method in ("guided-exact-refined", "guided-refined"))
        assert row.probes == round(0.2 * capture.point_count)
        assert row.error_ratio == pytest.approx(row.mean_error / row.reference_error)
        assert row.reference_error == pytest.approx(result.reference_curve[row.probes])
        tolerance = by_method[(method, "tolerance")]
        assert tolerance.mean_error <= 0.05 and tolerance.reference_probes is not None
    field = ReferenceField.from_capture(capture)
    scores = _StubScorer().score_capture(capture)
    spread = lpnn_placement(capture, scores=scores, budget=0.2, reference=field)
    assert by_method[("network", "budget")].mean_error == pytest.approx(spread.mean_error)
    refined = lpnn_placement(capture, scores=scores, budget=0.2, refine=2.0, reference=field)
    assert by_method[("guided-exact-refined", "budget")].mean_error == pytest.approx(refined.mean_error)
    guided = lpnn_placement(capture, scores=scores, budget=0.2, guided=True, reference=field)
    assert by_method[("guided", "budget")].mean_error == pytest.approx(guided.mean_error)


def test_above_the_refine_limit_the_bench_skips_only_the_refine_tier(small_captures: dict[int, Capture]) -> None:
    """Each guided-exact-refined row decimates again (minutes on a whole level): above `refine_limit` points only that tier is
    left out; the yardstick is still the full reference below `full_reference_limit`, and the other tiers' rows are
    those of a run without the limit."""
    capture = small_captures[2]
    config = BenchConfig(budgets=(0.2,), tolerance=0.05, repeats=1, faithful_limit=0)
    below = bench_capture("room2", capture, replace(config, refine_limit=capture.point_count), scorer=_StubScorer())
    above = bench_capture("room2", capture, replace(config, refine_limit=capture.point_count - 1), scorer=_StubScorer())
    assert below.yardstick == above.yardstick == "fast-reference" and below.failures == above.failures == []
    assert "guided-exact-refined" in {row.method for row in below.rows}
    assert {row.method for row in above.rows} == {row.method for row in below.rows} - {"guided-exact-refined"}
    kept = {(row.method, row.policy): (row.probes, row.mean_error) for row in below.rows if row.method != "guided-exact-refined"}
    assert {(row.method, row.policy): (row.probes, row.mean_error) for row in above.rows} == kept


def test_the_bench_hands_out_its_rows_after_every_method(small_captures: dict[int, Capture]) -> None:
    """A whole level's methods take minutes each: `partial` gets the rows so far after each, so the CLI can write them."""
    seen: list[list[str]] = []
    config = BenchConfig(budgets=(0.2,), tolerance=0.05, repeats=1, faithful_limit=0)
    result = bench_capture("room2", small_captures[2], config, partial=lambda rows: seen.append([r.method for r in rows]))
    methods = list(dict.fromkeys(row.method for row in result.rows))
    assert len(seen) == len(methods) and seen[-1] == [row.method for row in result.rows]
    assert [calls[-1] for calls in seen] == methods  # one call per method, each adding that method's rows


def test_above_the_guides_limit_the_guided_rows_are_the_insertion_rows(small_captures: dict[int, Capture],
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """Above GUIDED_POINT_LIMIT guided insertion is plain insertion: the bench reuses the insertion baseline's rows
    (same probes and errors; the time adds the inference) instead of running minutes of rounds again."""
    from lpnn.quality.placement import insertion

    monkeypatch.setattr(insertion, "GUIDED_POINT_LIMIT", 10)
    config = BenchConfig(budgets=(0.1, 0.2), tolerance=0.05, repeats=1, faithful_limit=0)
    result = bench_capture("room2", small_captures[2], config, scorer=_StubScorer())
    plain = {(row.policy, row.parameter): row for row in result.rows if row.method == "insertion"}
    guided = {(row.policy, row.parameter): row for row in result.rows if row.method == "guided"}
    assert result.failures == [] and guided.keys() == plain.keys() and len(plain) == 3
    for key, row in guided.items():
        assert (row.probes, row.mean_error, row.error_ratio) == (plain[key].probes, plain[key].mean_error,
                                                                 plain[key].error_ratio)
        assert row.inference_seconds is not None and plain[key].inference_seconds is None
        assert row.seconds == pytest.approx(plain[key].seconds + row.inference_seconds)


def test_place_from_scores_uses_the_spread_ranking_topk_refinement_and_guided_insertion(capture_files: list[Path], tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    capture = read_capture(capture_files[2])
    scores = np.random.default_rng(1).uniform(0, 1, capture.point_count).astype(np.float32)
    scores_file = tmp_path / "scores.csv"
    write_scores_csv(scores_file, capture.ids, scores)
    field = ReferenceField.from_capture(capture)
    for method, expected in (("network", lpnn_placement(capture, scores=scores, budget=0.25, reference=field)),
                             ("network-topk", lpnn_placement(capture, scores=scores, budget=0.25, topk=True,
                                                             reference=field)),
                             ("guided-exact-refined", lpnn_placement(capture, scores=scores, budget=0.25, refine=2.0,
                                                                     reference=field)),
                             ("guided", lpnn_placement(capture, scores=scores, budget=0.25, guided=True,
                                                       reference=field))):
        out = tmp_path / "p.probes.json"
        assert main(["place", str(capture_files[2]), "--method", method, "--scores", str(scores_file), "--budget",
                     "0.25", "--out", str(out)]) == 0
        document = json.loads(out.read_text(encoding="utf-8"))
        np.testing.assert_array_equal(np.asarray(document["positions"], dtype=np.float32),
                                      capture.positions[expected.indices])
        assert document["source"]["mean_error"] == pytest.approx(expected.mean_error, abs=1e-6)
        assert document["source"]["method"] == method and document["source"]["scores"] == "scores scores.csv"
        printed = capsys.readouterr().out
        assert printed.startswith(f"{method}: ")
        assert ("top-K" in printed) == (method == "network-topk")
        assert ("refinement" in printed) == (method == "guided-exact-refined")
        assert ("guided insertion" in printed) == method.startswith("guided")  # the refinement's seed too


@pytest.mark.parametrize("method", ["guided-refined", "guided", "network", "network-topk", "guided-exact-refined"])
def test_a_method_that_reads_the_scores_asks_for_the_flag_that_supplies_them(
        capture_files: list[Path], tmp_path: Path, capsys: pytest.CaptureFixture[str], method: str) -> None:
    assert main(["place", str(capture_files[2]), "--method", method, "--budget", "0.2",
                 "--out", str(tmp_path / "x.json")]) == 1
    assert (f"--method {method} reads the network's scores: add --model M.onnx (or --scores SCORES.csv"
            in capsys.readouterr().err)
    assert not (tmp_path / "x.json").exists()


@pytest.mark.parametrize("method, source", [("insertion-refined", "--model"), ("insertion", "--scores"),
                                            ("fast-reference", "--model"), ("uniform", "--scores"),
                                            ("random", "--model")])
def test_a_method_without_a_model_refuses_one_naming_the_method(
        capture_files: list[Path], tmp_path: Path, capsys: pytest.CaptureFixture[str], method: str, source: str) -> None:
    given = tmp_path / ("m.onnx" if source == "--model" else "s.csv")  # never read: the rule comes first
    assert main(["place", str(capture_files[2]), "--method", method, source, str(given), "--budget", "0.2",
                 "--out", str(tmp_path / "x.json")]) == 1
    err = capsys.readouterr().err
    assert f"--method {method} needs no model: drop --model/--scores" in err
    assert "guided-refined, guided, network, network-topk, guided-exact-refined" in err


def test_the_default_method_refuses_a_model_too(capture_files: list[Path], tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["place", str(capture_files[2]), "--model", str(tmp_path / "m.onnx"), "--budget", "0.2",
                 "--out", str(tmp_path / "x.json")]) == 1
    assert "--method insertion-refined needs no model" in capsys.readouterr().err


def test_no_report_applies_only_to_the_methods_that_read_the_scores(capture_files: list[Path], tmp_path: Path,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["place", str(capture_files[2]), "--method", "insertion", "--no-report", "--budget", "0.2",
                 "--out", str(tmp_path / "x.json")]) == 1
    assert "--no-report applies to the methods that read the network's scores" in capsys.readouterr().err


def test_keep_is_refused_by_the_methods_that_read_the_scores(capture_files: list[Path], tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    scores_file = tmp_path / "scores.csv"
    capture = read_capture(capture_files[2])
    write_scores_csv(scores_file, capture.ids, np.ones(capture.point_count, dtype=np.float32))
    assert main(["place", str(capture_files[2]), "--method", "guided", "--scores", str(scores_file), "--keep",
                 str(tmp_path / "pins.json"), "--budget", "0.2", "--out", str(tmp_path / "x.json")]) == 1
    assert "--keep does not apply to --method guided" in capsys.readouterr().err


@pytest.mark.parametrize("old", [["--refine", "2"], ["--batched"], ["--topk"], ["--guided"], ["--method", "fast"],
                                 ["--method", "lpnn-batched"]])
def test_the_old_spellings_are_gone(capture_files: list[Path], tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                    old: list[str]) -> None:
    with pytest.raises(SystemExit):
        main(["place", str(capture_files[2]), *old, "--budget", "0.2", "--out", str(tmp_path / "x.json")])
    err = capsys.readouterr().err
    assert "unrecognized arguments" in err or "invalid choice" in err


def test_the_method_choices_and_help_come_from_the_table(capsys: pytest.CaptureFixture[str]) -> None:
    from lpnn.quality.placement.methods import BY_NAME, PLACEABLE

    with pytest.raises(SystemExit):
        main(["place", "--help"])
    printed = capsys.readouterr().out
    for name in PLACEABLE:
        assert f"\n  {name:<22}{BY_NAME[name].summary}" in printed  # the epilog: one line per method
    assert "faithful-reference" not in printed and "blockwise-reference" not in printed
    with pytest.raises(SystemExit):
        main(["place", "x.lpnncap", "--method", "faithful-reference", "--budget", "0.2", "--out", "x.json"])
    assert "invalid choice: 'faithful-reference'" in capsys.readouterr().err


def test_a_flat_capture_is_a_one_line_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    j, i = np.meshgrid(np.arange(4), np.arange(5), indexing="ij")
    ids = np.stack([i.ravel(), j.ravel(), np.zeros(20, dtype=np.int64)], axis=1).astype(np.int32)
    flat = Capture(ids=ids, positions=ids.astype(np.float32), sh=np.ones((20, 27), dtype=np.float32),
                   features=np.zeros((20, 1), dtype=np.float32), schema="test.flat", feature_names=["zero"],
                   cell_size=1.0, lighting_scale=1.0)
    path = tmp_path / "flat.lpnncap"
    write_capture(path, flat)
    assert main(["label", str(path), "--budget", "0.5", "--in-place", "--quiet"]) == 1
    assert main(["place", str(path), "--method", "uniform", "--budget", "0.5", "--out", str(tmp_path / "p.json")]) == 1
    errors = capsys.readouterr().err.strip().splitlines()
    assert len(errors) == 2 and all("flat.lpnncap" in line and "plane" in line for line in errors)


def test_above_the_full_reference_limit_the_blockwise_reference_is_the_yardstick(medium_capture: Capture,
                                                                                 tmp_path: Path) -> None:
    """quality.md §3.3 as the bench's yardstick: every ratio divides by the blockwise reference at the same count (its
    ranking's prefix) or by its tolerance answer's count; the methods that run the full reference are not run. Its
    finished blocks are kept in the bench's folder (a rerun resumes)."""
    from lpnn.core.grid import EvaluationGrid
    from lpnn.quality.placement.decimation.blockwise import blockwise_reference
    from lpnn.quality.metric.metric import placement_error
    from lpnn.quality.placement.policies import prefix_selection

    config = BenchConfig(budgets=(0.05, 0.2), tolerance=0.05, repeats=1, faithful_limit=0, full_reference_limit=100,
                         checkpoints=str(tmp_path))
    result = bench_capture("room3", medium_capture, config, scorer=_StubScorer())
    assert result.failures == [] and result.yardstick == "blockwise-reference"
    assert (tmp_path / "room3.blockwise.npz").is_file()
    methods = {row.method for row in result.rows}
    assert "blockwise-reference" in methods and {"insertion", "network", "guided"} <= methods
    assert not methods & {"fast-reference", "faithful-reference", "guided-exact-refined"}
    assert all(row.yardstick == "blockwise-reference" for row in result.rows)
    field = ReferenceField.from_capture(medium_capture)
    grid = EvaluationGrid(cell_size=medium_capture.cell_size, ids=medium_capture.ids)
    blockwise = blockwise_reference(field, medium_capture.ids)
    select = prefix_selection(grid, blockwise.ranking)
    for row in (r for r in result.rows if r.policy == "budget"):
        assert row.reference_error == pytest.approx(placement_error(field, select(row.probes)).mean), row.method
        assert row.error_ratio == pytest.approx(row.mean_error / row.reference_error)
    own = {row.policy: row for row in result.rows if row.method == "blockwise-reference"}
    assert own["budget"].error_ratio == pytest.approx(1.0)
    assert own["tolerance"].probes == own["tolerance"].reference_probes == blockwise.within(0.05).shape[0]
    for row in (r for r in result.rows if r.policy == "tolerance"):
        assert row.probes_ratio == pytest.approx(row.probes / own["tolerance"].probes)
    # Below the limit nothing changes: the fast reference is the yardstick.
    assert bench_capture("room3", medium_capture, replace(config, full_reference_limit=10**6)).yardstick == "fast-reference"
