"""Tests/Data/pins_golden.json: pins snapped and the points near them blocked, by construction
(Tools~/golden/make_pins_golden.py); the same cases in C# (Tests/Core/PinsTests.cs)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.pins import MIN_DISTANCE_CELLS, SLACK_CELLS, SNAP_RADIUS_CELLS, PinError, pin_probes

GOLDEN = json.loads((Path(__file__).resolve().parents[3] / "Tests" / "Data" / "pins_golden.json").read_text(encoding="utf-8"))


def test_the_constants_are_the_golden_files():
    assert (GOLDEN["snap_radius_cells"], GOLDEN["min_distance_cells"], GOLDEN["slack_cells"]) == (
        SNAP_RADIUS_CELLS, MIN_DISTANCE_CELLS, SLACK_CELLS)
    assert SNAP_RADIUS_CELLS == math.sqrt(3.0) / 2.0


@pytest.mark.parametrize("case", GOLDEN["cases"], ids=[c["name"] for c in GOLDEN["cases"]])
def test_each_case_snaps_and_blocks_as_built(case: dict) -> None:
    grid = EvaluationGrid(cell_size=case["cell_size"], ids=np.asarray(case["ids"], dtype=np.int32))
    positions = np.asarray(case["pins"], dtype=np.float64).reshape(-1, 3)
    if "error" in case:
        with pytest.raises(PinError, match=case["error"].replace("(", r"\(").replace(")", r"\)")):
            pin_probes(positions, grid.positions, grid.cell_size, case["min_distance"])
        return
    pins = pin_probes(positions, grid.positions, grid.cell_size, case["min_distance"])
    assert pins.indices.tolist() == case["indices"]
    assert np.flatnonzero(pins.blocked).tolist() == case["blocked"]
