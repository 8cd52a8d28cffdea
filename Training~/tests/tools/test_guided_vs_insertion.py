"""Tools~/experiments/guided-vs-insertion.py: guided against plain insertion per capture; held-out levels refused."""

from __future__ import annotations

from pathlib import Path

import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import write_capture
from tools_support import card_with_held_out, load_tool

SCRIPT = "guided-vs-insertion.py"


def test_held_out_levels_are_refused(tmp_path: Path) -> None:
    with pytest.raises(SystemExit, match="held-out level"):
        load_tool(SCRIPT).main([str(tmp_path / "oa_dm1.lpnncap"), "--card", str(card_with_held_out(tmp_path, ["oa_dm1"]))])


def test_one_row_per_capture_with_the_shipped_model(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, AnalyticScene.random(3, cell_size=0.5, room_size=(4.0, 2.5, 3.0)).capture(name="room"))
    assert load_tool(SCRIPT).main([str(path), "--card", str(card_with_held_out(tmp_path, ["oa_dm1"]))]) == 0
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| room |")]
    assert len(rows) == 1
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    insertion, guided, ratio = int(cells[2].replace(",", "")), int(cells[3].replace(",", "")), float(cells[4])
    assert insertion >= 4 and guided >= 4 and ratio == pytest.approx(guided / insertion, abs=1e-3)
