"""`lpnn place` never places a probe at a point a capture marks inside geometry (its back-face fraction section)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.main import main
from lpnn.cli.scores_file import write_scores_csv
from lpnn.core.capture import Capture
from lpnn.core.capture_file import read_capture, write_capture
from lpnn.core.validity import CAPTURE_SECTION


def _with_fractions(capture: Capture, inside: np.ndarray) -> Capture:
    fractions = np.where(inside, np.float32(20 / 26), np.float32(1 / 26)).astype(np.float32)
    return replace(capture, extra_sections={**capture.extra_sections, CAPTURE_SECTION: fractions})


def _inside_side(capture: Capture) -> np.ndarray:
    """The plane of points with the lowest x: one side of the box, four of its corners included."""
    x = capture.positions[:, 0]
    return x == x.min()


def _placed(out: Path) -> set[tuple[float, ...]]:
    return {tuple(np.float32(p).tolist()) for p in json.loads(out.read_text(encoding="utf-8"))["positions"]}


@pytest.mark.parametrize("method", ["fast-reference", "insertion", "uniform", "heuristic", "apv", "random"])
def test_no_method_places_a_probe_inside_geometry(capture_files: list[Path], tmp_path: Path, method: str,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    capture = read_capture(capture_files[1])
    inside = _inside_side(capture)
    path = tmp_path / "marked.lpnncap"
    write_capture(path, _with_fractions(capture, inside))
    out = tmp_path / f"{method}.probes.json"
    assert main(["place", str(path), "--method", method, "--budget", "0.5", "--out", str(out)]) == 0
    invalid_positions = {tuple(p) for p in capture.positions[inside].tolist()}
    placed = _placed(out)
    assert placed and not placed & invalid_positions
    assert f"{int(inside.sum())} of {capture.point_count} points are inside geometry" in capsys.readouterr().err


def test_scores_favouring_invalid_points_still_place_only_valid_ones(capture_files: list[Path], tmp_path: Path) -> None:
    capture = read_capture(capture_files[2])
    inside = _inside_side(capture)
    path = tmp_path / "marked.lpnncap"
    write_capture(path, _with_fractions(capture, inside))
    scores = np.where(inside, 1.0, 0.0).astype(np.float32)  # every invalid point outranks every valid one
    scores_file = tmp_path / "scores.csv"
    write_scores_csv(scores_file, capture.ids, scores)
    for extra in (["--method", "network", "--budget", "0.3"], ["--method", "network-topk", "--budget", "0.3"],
                  ["--method", "network", "--tolerance", "0.2"]):
        out = tmp_path / "scored.probes.json"
        assert main(["place", str(path), "--scores", str(scores_file), *extra, "--out", str(out)]) == 0
        assert not _placed(out) & {tuple(p) for p in capture.positions[inside].tolist()}, extra
    # control: without the section the same scores pick the slab
    out = tmp_path / "unmarked.probes.json"
    assert main(["place", str(capture_files[2]), "--method", "network-topk", "--scores", str(scores_file), "--budget",
                 "0.3", "--out", str(out)]) == 0
    assert _placed(out) & {tuple(p) for p in capture.positions[inside].tolist()}


def test_too_few_valid_points_is_a_one_line_error(capture_files: list[Path], tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    capture = read_capture(capture_files[1])
    inside = np.ones(capture.point_count, dtype=bool)
    inside[:3] = False
    path = tmp_path / "walled.lpnncap"
    write_capture(path, _with_fractions(capture, inside))
    assert main(["place", str(path), "--method", "uniform", "--budget", "0.5", "--out", str(tmp_path / "p.json")]) == 1
    error = capsys.readouterr().err
    assert "only 3 of" in error and "inside geometry" in error


def test_a_bad_fraction_section_names_the_point(capture_files: list[Path], tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    capture = read_capture(capture_files[1])
    fractions = np.zeros(capture.point_count, dtype=np.float32)
    fractions[5] = 1.5
    path = tmp_path / "bad.lpnncap"
    write_capture(path, replace(capture, extra_sections={CAPTURE_SECTION: fractions}))
    assert main(["place", str(path), "--method", "uniform", "--budget", "0.5", "--out", str(tmp_path / "p.json")]) == 1
    assert "point 5 has 1.5" in capsys.readouterr().err
