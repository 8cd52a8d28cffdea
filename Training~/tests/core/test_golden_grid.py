"""Tests/Data/grid_golden.json (written by the C# GoldenWriter): identical point sets and limit errors."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.grid import GridError
from lpnn.core.grid_box import Box
from lpnn.core.grid_builder import build_grid, count_points, fitting_cell_size


def boxes_of(case: dict) -> list[Box]:
    return [Box.from_json(b) for b in case["boxes"]]


def test_grid_cases_give_the_same_ids_in_the_same_order(golden):
    data = golden("grid_golden.json")
    assert data["cases"], "grid_golden.json has no cases"
    for case in data["cases"]:
        grid = build_grid(boxes_of(case), case["cell_size"])
        expected = np.asarray(case["ids"], dtype=np.int64).reshape(-1, 3)
        assert grid.point_count == case["count"] == expected.shape[0], case["name"]
        assert np.array_equal(grid.ids.astype(np.int64), expected), case["name"]
        assert count_points(boxes_of(case), case["cell_size"]) == case["count"], case["name"]


def test_limit_cases_give_the_same_count_and_fitting_cell_size(golden):
    data = golden("grid_golden.json")
    for case in data["limit_cases"]:
        boxes, h, limit = boxes_of(case), case["cell_size"], case["point_limit"]
        assert count_points(boxes, h, point_limit=limit) == case["count"], case["name"]
        with pytest.raises(GridError) as error:
            build_grid(boxes, h, point_limit=limit)
        suggestion = fitting_cell_size(boxes, h, limit)
        assert suggestion == pytest.approx(case["fitting_cell_size"], rel=1e-12), case["name"]
        assert f"{case['count']:,}" in str(error.value) and f"{suggestion:.3g}" in str(error.value), case["name"]
