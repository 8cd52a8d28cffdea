"""Tools~/experiments/relit-comparison.py (benchmarks.md "The network") reduced to one level per role, one crop each and one epoch:
both runs are made, on the same held-out crop, the relit one with more training crops, each row with real figures."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from tools_support import run_experiment

pytestmark = [pytest.mark.openarena, pytest.mark.slow]


def test_a_row_per_run_on_the_same_held_out_crop(openarena_pak: Path, tmp_path: Path) -> None:
    out = run_experiment("relit-comparison.py", "--pak", str(openarena_pak), "--work", str(tmp_path),
                         "--levels", "aggressor,oa_dm2,oa_dm4", "--crops-per-level", "1", "--epochs", "1",
                         env={"LPNN_OPENARENA_PAK": str(openarena_pak)}).stdout
    rows = {m.group(1): m for m in re.finditer(
        r"^\| (without|with-2) \| (\d+) \| (\d+) \| ([0-9.]+) \| ([0-9.]+) \| ([0-9.]+) / ([0-9.]+) / ([0-9.]+) \| "
        r"([0-9.]+) \| ([0-9.]+) \((\d+) of (\d+) within\) \|$", out, re.M)}
    assert set(rows) == {"without", "with-2"}, out
    without, relit = rows["without"], rows["with-2"]
    assert int(relit.group(2)) > int(without.group(2)) >= 1  # the relit variants are added to the training crops
    assert without.group(3) == relit.group(3) == "1"  # the same held-out crop
    for row in (without, relit):
        assert 0 <= float(row.group(4)) <= 1 and all(float(row.group(i)) > 0 for i in range(6, 11))
    summaries = [json.loads((tmp_path / f"{label}.summary.json").read_text(encoding="utf-8"))
                 for label in ("without", "with-2")]
    assert summaries[0]["crops"] == summaries[1]["crops"] == 1
