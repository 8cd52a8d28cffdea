"""Tools~/experiments/in-use-bench.py (benchmarks.md "Points in use") on a real level: one row per rule, each placement within the
tolerance on its own points, the reachable one also at the reachable points of the common yardstick."""

from __future__ import annotations

from pathlib import Path

import pytest

from tools_support import load_tool

pytestmark = pytest.mark.openarena


def test_rows_of_every_rule_on_a_small_level(openarena_pak: Path, tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("LPNN_OPENARENA_PAK", str(openarena_pak))
    tool = load_tool("in-use-bench.py")
    rows = tool.measure("aggressor", tool.DEFAULT_CELL, ("all", "band", "reachable"))
    by_rule = {row["rule"]: row for row in rows}
    assert list(by_rule) == ["all", "band", "reachable"]
    assert by_rule["all"]["points"] > by_rule["band"]["points"] >= by_rule["reachable"]["points"] > 0
    assert by_rule["reachable"]["reachable_points"] == by_rule["reachable"]["points"]
    for row in rows:
        assert row["mean_error"] <= tool.TOLERANCE and row["probes"] >= 4
    assert by_rule["reachable"]["error_reachable"] <= tool.TOLERANCE + 1e-9
    assert by_rule["all"]["probes"] > by_rule["reachable"]["probes"]
