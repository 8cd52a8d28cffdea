"""Tools~/experiments/refine-trade.py: the refine tier's ratios to the reference and time fractions, by seed factor."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import read_capture, write_capture
from lpnn.quality.placement.lpnn_placement import lpnn_placement
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.placement.policies import reference_tolerance
from lpnn.quality.placement.decimation.reference_fast import fast_decimation
from lpnn.train.onnx_scoring import OnnxScorer
from tools_support import load_tool

SCRIPT = "refine-trade.py"


def test_one_line_per_policy_and_factor_and_a_table(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, AnalyticScene.random(3, cell_size=0.5, room_size=(4.0, 2.5, 3.0)).capture(name="room"))
    tool = load_tool(SCRIPT)
    assert tool.main([str(path), "--factors", "2", "--budgets", "0.2", "--repeats", "1"]) == 0
    out = capsys.readouterr().out
    rows = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    assert [(row["budget"], row["factor"]) for row in rows] == [(0.2, 1.0), (0.2, 2.0), (None, 1.0), (None, 2.0)]
    # The tolerance rows' ratio is the tier's probe count over the reference's, recomputed here independently.
    capture = read_capture(path)
    field = ReferenceField.from_capture(capture)
    scores = OnnxScorer(tool.DEFAULT_MODEL).score_capture(capture)
    reference = reference_tolerance(fast_decimation(field), 0.05).indices.shape[0]
    refined = lpnn_placement(capture, scores=scores, tolerance=0.05, refine=2.0, reference=field).indices.shape[0]
    assert rows[3]["probes"] == refined and rows[3]["ratio"] == pytest.approx(refined / reference)
    assert all(row["seconds"] > 0 and row["reference_seconds"] > 0 for row in rows)
    table = [line for line in out.splitlines() if line.startswith("| 1 (guided") or line.startswith("| 2 |")]
    assert len(table) == 2


def test_bad_factors_are_refused(tmp_path: Path) -> None:
    with pytest.raises(SystemExit, match="must be > 1"):
        load_tool(SCRIPT).main([str(tmp_path / "x.lpnncap"), "--factors", "1"])
