"""Tools~/experiments/score-ceilings.py: ceilings of per-point scores on training/validation crops; held-out levels refused."""

from __future__ import annotations

from pathlib import Path

import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture_file import write_capture
from tools_support import card_with_held_out, load_tool

SCRIPT = "score-ceilings.py"


def test_held_out_levels_are_refused(tmp_path: Path) -> None:
    card = card_with_held_out(tmp_path, ["oa_dm1"])
    with pytest.raises(SystemExit, match="held-out level"):
        load_tool(SCRIPT).main([str(tmp_path / "oa_dm1@1.626m__0.lpnncap"), "--card", str(card), "--no-model"])


def test_the_oracle_rows_on_a_room(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The oracle's top-K is the reference's placement, so the steepest spread of it must come near it at 30 %, and
    every row has six finite ratios >= ~1 (nothing beats the reference by much at the same count)."""
    path = tmp_path / "room@0.5m__0.lpnncap"
    write_capture(path, AnalyticScene.random(3, cell_size=0.5, room_size=(4.0, 2.5, 3.0)).capture(name="room"))
    assert load_tool(SCRIPT).main([str(path), "--card", str(card_with_held_out(tmp_path, ["oa_dm1"])), "--no-model", "--workers", "1"]) == 0
    rows = {line.split(" | ")[0].strip("| "): [float(v) for v in line.strip(" |").split(" | ")[1:]]
            for line in capsys.readouterr().out.splitlines() if line.startswith("| ") and "ranking" not in line}
    assert set(rows) == {"insertion", "insertion guided by the oracle score", "insertion guided by the oracle importance",
                         "spread of the oracle, exponent 0.5", "spread of the oracle, exponent 4",
                         "spread of the oracle, exponent 8", "spread of the density oracle"}
    assert all(len(v) == 6 and min(v) > 0.8 for v in rows.values())
    assert rows["spread of the oracle, exponent 8"][4] < rows["spread of the oracle, exponent 0.5"][4]
