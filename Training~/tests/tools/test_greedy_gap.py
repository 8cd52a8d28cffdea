"""Tools~/experiments/greedy-gap.py: the default, the exact greedy from its seed and the batched refinement from that
seed at other commit fractions, with and without settled commits."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AnalyticScene, AxisBox
from lpnn.core.capture_file import read_capture, write_capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.placement.decimation.reference_fast import fast_decimation
from lpnn.quality.placement.leak_aware import LeakWeighting
from lpnn.quality.placement.policies import reference_tolerance
from lpnn.quality.placement.refined_insertion import refined_insertion
from tools_support import load_tool

SCRIPT = "greedy-gap.py"


def test_one_line_per_measurement_and_a_table(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, AnalyticScene.random(3, cell_size=0.4, room_size=(4.0, 2.5, 3.0)).capture(name="room"))
    tool = load_tool(SCRIPT)
    assert tool.main([str(path), "--leaks", "ignore", "--factors", "2", "--fractions", "0.1",
                      "--settled-fractions", "0", "--reference"]) == 0
    out = capsys.readouterr().out
    rows = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    assert [(row["seed"], row["method"], row.get("fraction")) for row in rows] == [
        ("every point", "exact greedy", None), ("2 K0", "default", None), ("2 K0", "exact greedy", None),
        ("2 K0", "batched", 0.1), ("2 K0", "batched, settled commits", 0.0)]
    assert all(row["mode"] == "leak-blind" and row["seconds"] > 0 for row in rows)
    # Independently: the reference's tau answer, the default's answer and seed, the exact greedy from that seed.
    capture = read_capture(path)
    field = ReferenceField.from_capture(capture)
    assert rows[0]["probes"] == reference_tolerance(fast_decimation(field), 0.05).indices.shape[0]
    placed = refined_insertion(field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids), tolerance=0.05)
    assert rows[1]["probes"] == placed.indices.shape[0] and rows[1]["seed_points"] == placed.seed.shape[0]
    greedy = fast_decimation(field, initial=placed.seed).smallest_count_within(0.05)
    assert rows[2]["probes"] == greedy
    # The default's refinement is the batched one at 0.1 from its seed; settled commits at 0 are the exact greedy's.
    assert rows[3]["probes"] == rows[1]["probes"]
    assert rows[4]["probes"] == greedy and rows[4]["rounds"] > rows[3]["rounds"]
    assert rows[4]["stop_reason"] == "tolerance" and rows[4]["mean_error"] <= 0.05
    assert out.splitlines()[-1].startswith(f"room.lpnncap | leak-blind | 2 K0 | batched, settled commits | 0.0 | {greedy} |")


@pytest.mark.parametrize("arguments, message", [
    (["missing.lpnncap"], "no capture"),
    (["room.lpnncap", "--fractions", "0.1,2"], "commit fraction 2.0 must be in [0, 1]"),
    (["room.lpnncap", "--factors", "1"], "--factors: 1.0 must be > 1"),
    (["room.lpnncap", "--factors", "2,two"], "'two' is not a number (use '.' for decimals"),
    (["room.lpnncap", "--tolerance", "0"], "--tolerance 0.0 must be a mean error > 0")])
def test_bad_arguments_are_refused_by_name_before_any_work(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                           arguments: list[str], message: str) -> None:
    write_capture(tmp_path / "room.lpnncap", AnalyticScene.random(1, cell_size=0.5, room_size=(2.0, 2.0, 2.0))
                  .capture(name="room"))
    with pytest.raises(SystemExit):
        load_tool(SCRIPT).main([str(tmp_path / arguments[0]), *arguments[1:]])
    captured = capsys.readouterr()
    assert message in captured.err and (arguments[0] in captured.err or arguments[0] == "room.lpnncap")
    assert "{" not in captured.out  # nothing measured


def test_leak_aware_rows_weigh_the_leaks_of_a_walled_room() -> None:
    """The leak-aware path (lpnn place's default where the geometry is known), on the analytic room with a wall: the
    default's seed includes the leak repair's points, and the exact leak-weighted greedy from it is recomputed here."""
    room = AnalyticScene.random(3, cell_size=0.5, room_size=(4.0, 2.5, 3.0))
    rays = AnalyticBoxRaycaster(room.raycaster.room,
                                room.raycaster.obstacles + (AxisBox(min=[0.1, -10.0, -10.0], max=[0.4, 10.0, 10.0]),))
    capture = AnalyticScene(cell_size=room.cell_size, boxes=room.boxes, light_field=room.light_field,
                            raycaster=rays).capture(name="walled")
    field = ReferenceField.from_capture(capture)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    rows: list[dict] = []
    load_tool(SCRIPT).measure("walled", field, grid, rays, 0.05, [2.0], [0.1], [0.0], False, rows.append)
    assert [(row["method"], row["mode"]) for row in rows] == [
        ("default", "leak-aware"), ("exact greedy", "leak-aware"), ("batched", "leak-aware"),
        ("batched, settled commits", "leak-aware")]
    placed = refined_insertion(field, grid, tolerance=0.05, leaks=rays)
    blind_seed = refined_insertion(field, grid, tolerance=0.05).seed
    assert rows[0]["probes"] == placed.indices.shape[0] and rows[0]["seed_points"] == placed.seed.shape[0]
    assert placed.seed.shape[0] > blind_seed.shape[0]  # the repair's points
    greedy = fast_decimation(field, initial=placed.seed, stop_above=0.06, leaks=LeakWeighting(rays))
    assert rows[1]["probes"] == greedy.smallest_count_within(0.05)
    assert rows[3]["probes"] == rows[1]["probes"] and rows[3]["stop_reason"] == "tolerance"
