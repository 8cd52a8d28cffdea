"""Tools~/experiments/network-seed.py: the default's answers as labelled tiles, a network's likeliest points as the
default's seed; held-out levels refused."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import read_capture, write_capture
from lpnn.quality.metric.metric import ReferenceField, mean_placement_error
from tools_support import card_with_held_out, load_tool

SCRIPT = "network-seed.py"


@pytest.fixture()
def room(tmp_path: Path) -> Path:
    path = tmp_path / "room.lpnncap"
    write_capture(path, AnalyticScene.random(3, cell_size=0.5, room_size=(4.0, 2.5, 3.0)).capture(name="room"))
    return path


@pytest.mark.parametrize("command", [["labels", "--out", "x"], ["compare", "--model", "m.onnx"],
                                     ["place", "--model", "m.onnx"]])
def test_held_out_levels_are_refused(tmp_path: Path, command: list[str]) -> None:
    card = card_with_held_out(tmp_path, ["oa_dm1"])
    with pytest.raises(SystemExit, match="held-out level"):
        load_tool(SCRIPT).main([command[0], str(tmp_path / "oa_dm1@1.626m__0.lpnncap"), *command[1:], "--card", str(card)])


def test_tiles_cover_every_point_once_in_boxes_of_at_most_the_limit() -> None:
    rng = np.random.default_rng(0)
    ids = rng.integers(0, 40, size=(3000, 3))
    parts = load_tool(SCRIPT).tiles(ids, 500)
    assert max(p.shape[0] for p in parts) <= 500 and len(parts) >= 6
    np.testing.assert_array_equal(np.sort(np.concatenate(parts)), np.arange(3000))
    assert load_tool(SCRIPT).tiles(ids, 5000)[0].shape[0] == 3000  # small enough: one tile


def test_the_seed_is_the_likeliest_points_as_many_as_expected() -> None:
    tool = load_tool(SCRIPT)
    probabilities = np.array([0.1, 0.9, 0.5, 0.9, 0.2, 0.3, 0.8, 0.7])  # sum 4.4
    np.testing.assert_array_equal(tool.network_seed(probabilities, 1.0), [1, 3, 6, 7])  # ties: lower index
    np.testing.assert_array_equal(tool.network_seed(probabilities, 1.5), [1, 3, 6, 7, 2, 5, 4])  # round(6.6)
    np.testing.assert_array_equal(tool.network_seed(np.full(10, 0.01), 1.0), [0, 1, 2, 3])  # 0.1 expected: MIN_SEED
    np.testing.assert_array_equal(tool.network_seed(np.array([0.2, 0.9]), 1.0), [1, 0])  # fewer points than that: all


def test_kept_probabilities_take_the_positive_weight_out_of_the_odds_tile_by_tile() -> None:
    """Weighted BCE trains the odds p / (1 - p) `positive_weight` times too high: the calibrated odds are the network's
    divided by the weight, every point scored once, within the tile that holds it."""
    tool = load_tool(SCRIPT)
    ids = np.stack(np.meshgrid(np.arange(8), np.arange(8), np.arange(4), indexing="ij"), axis=-1).reshape(-1, 3)
    raw = np.linspace(0.01, 0.99, len(ids))
    calls: list[int] = []

    class Scorer:  # returns each point's raw score, read from its first feature (its index)
        card = SimpleNamespace(training={"positive_weight": 4.0})

        def score(self, features: np.ndarray) -> np.ndarray:
            calls.append(len(features))
            return raw[features[:, 0].astype(np.int64)]

    capture = SimpleNamespace(point_count=len(ids), ids=ids, features=np.arange(len(ids), dtype=np.float32)[:, None])
    got = tool.kept_probabilities(Scorer(), capture, tile_points=64)
    np.testing.assert_allclose(got / (1.0 - got), raw / (1.0 - raw) / 4.0, rtol=1e-12)
    assert len(calls) == 4 and max(calls) <= 64 and sum(calls) == len(ids)


def test_labels_are_the_defaults_answer_and_the_seeded_default_meets_the_tolerance(
        room: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    tool = load_tool(SCRIPT)
    card = str(card_with_held_out(tmp_path, ["oa_dm1"]))
    out = tmp_path / "tiles"
    assert tool.main(["labels", str(room), "--out", str(out), "--tile", "200", "--card", card]) == 0
    answers = json.loads((out / "answers.json").read_text(encoding="utf-8"))["room"]
    tiles = sorted(out.glob("room__t*.lpnncap"))
    assert len(tiles) >= 2
    # The labelled points of all tiles are the default's answer: that many, and a set within tau on the whole room.
    capture = read_capture(room)
    row = {tuple(i): n for n, i in enumerate(capture.ids.tolist())}
    kept = [row[tuple(i)] for t in tiles for i, label in zip(read_capture(t).ids.tolist(), read_capture(t).labels)
            if label == 1]
    assert len(kept) == answers["probes"] < capture.point_count
    assert mean_placement_error(ReferenceField.from_capture(capture), np.sort(kept)) <= 0.05
    # The seeded default (here with the shipped model's scores) answers within tau too.
    assert tool.main(["compare", str(room), "--model", str(tool._ceilings().DEFAULT_MODEL), "--card", card]) == 0
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| room |")]
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    assert int(cells[2].replace(",", "")) == answers["probes"]  # the default, as labelled
    assert float(cells[7]) <= 0.05 and int(cells[6].replace(",", "")) >= 4
    # `place`: the seeded default alone, and the default through the same path (what paired-time.py compares).
    for chosen in (["--model", str(tool._ceilings().DEFAULT_MODEL)], ["--unseeded"]):
        assert tool.main(["place", str(room), *chosen, "--card", card]) == 0
        line = capsys.readouterr().out
        assert "probes from a seed of" in line and float(line.split("mean error ")[1].split(";")[0]) <= 0.05
    assert f"{answers['probes']:,} probes from a seed of 0" in line  # --unseeded: the default's answer

