"""CLI round trip (train -> model.onnx + card -> score CSV; export; model info/check) and CLI errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.main import main
from lpnn.core.capture_file import read_capture
from lpnn.train.onnx_scoring import OnnxScorer

from train_support import TrainedModel


def test_score_writes_a_culture_invariant_csv(trained: TrainedModel, tmp_path: Path) -> None:
    capture_path = trained.dataset / "scene_0.lpnncap"
    out = tmp_path / "scores.csv"
    assert main(["score", str(capture_path), "--model", str(trained.model), "--out", str(out)]) == 0
    lines = out.read_text(encoding="utf-8").splitlines()
    capture = read_capture(capture_path)
    assert lines[0] == "index,i,j,k,score" and len(lines) == capture.point_count + 1
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert rows.shape == (capture.point_count, 5)
    np.testing.assert_array_equal(rows[:, 0], np.arange(capture.point_count))
    np.testing.assert_array_equal(rows[:, 1:4], capture.ids)
    np.testing.assert_array_equal(rows[:, 4].astype(np.float32), OnnxScorer(trained.model).score(capture.features))
    assert [p.name for p in tmp_path.iterdir()] == ["scores.csv"]


def test_export_from_checkpoint_reproduces_the_model(trained: TrainedModel, tmp_path: Path) -> None:
    out = tmp_path / "again.onnx"
    assert main(["export", str(trained.checkpoint), "--out", str(out), "--data", str(trained.dataset / "scene_1.lpnncap")]) == 0
    features = read_capture(trained.dataset / "scene_1.lpnncap").features
    np.testing.assert_allclose(OnnxScorer(out).score(features), OnnxScorer(trained.model).score(features), atol=1e-6)
    card = json.loads(out.with_suffix(".card.json").read_text(encoding="utf-8"))
    assert card["model_file"] == "again.onnx" and "scene_1.lpnncap" in card["parity"]["cases"]


def test_model_info_and_check(trained: TrainedModel, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["model", "info", str(trained.model)]) == 0
    assert json.loads(capsys.readouterr().out)["format"] == "lpnn.modelcard"
    assert main(["model", "check", str(trained.model), "--capture", str(trained.dataset / "scene_2.lpnncap")]) == 0
    printed = capsys.readouterr().out
    report = json.loads(printed[: printed.rindex("}") + 1])
    assert report["permutation_max_abs_diff"] < 1e-5 and report["batch_max_abs_diff"] < 1e-5
    assert printed.rstrip().endswith(": ok")


def test_model_check_fails_when_the_card_does_not_match(trained: TrainedModel, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    model = tmp_path / "m.onnx"
    model.write_bytes(trained.model.read_bytes())
    card = json.loads(trained.card.read_text(encoding="utf-8"))
    card["ops"] = card["ops"][1:]
    model.with_suffix(".card.json").write_text(json.dumps(card), encoding="utf-8")
    assert main(["model", "check", str(model)]) == 1
    assert "the card lists ops" in capsys.readouterr().err


def test_cli_errors_are_one_line_user_errors(tmp_path: Path, trained: TrainedModel,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["train", str(empty), "--out", str(tmp_path / "m.onnx"), "--quiet"]) == 1
    assert "lpnn train: error: no captures (*.lpnncap) found in" in capsys.readouterr().err
    assert main(["train", str(trained.dataset), "--out", str(tmp_path / "m.txt"), "--quiet"]) == 1
    assert "must end in .onnx" in capsys.readouterr().err
    assert not (tmp_path / "m.onnx").exists()
