"""Tests/Data/features_golden.json (written by the C# GoldenWriter): the analytic scene's 19 features."""

from __future__ import annotations

import numpy as np

from lpnn.core.analytic_scene import load_scene
from lpnn.core.features import extract_features
from lpnn.core.grid_builder import build_grid
from lpnn.core.schema import LPNN_V1

GOLDEN = "features_golden.json"


def test_schema_and_names(golden):
    data = golden(GOLDEN)
    assert data["schema"] == LPNN_V1.id and data["feature_names"] == list(LPNN_V1.names)


def test_grid_and_sampled_sh_match(golden, assert_within):
    data = golden(GOLDEN)
    boxes, cell_size, light_field, _ = load_scene(data["scene"])
    grid = build_grid(boxes, cell_size)
    points = data["points"]
    assert [p["index"] for p in points] == list(range(len(points)))
    assert np.array_equal(grid.ids, np.asarray([p["id"] for p in points], dtype=np.int32))
    assert np.array_equal(grid.positions, np.asarray([p["position"] for p in points], dtype=np.float32))
    assert_within(light_field.sample(grid.positions), np.asarray([p["sh"] for p in points], dtype=np.float32),
                  data["tolerance"], "sampled SH")


def test_features_and_lighting_scale_match(golden, assert_within):
    data = golden(GOLDEN)
    boxes, cell_size, _, raycaster = load_scene(data["scene"])
    grid = build_grid(boxes, cell_size)
    sh = np.asarray([p["sh"] for p in data["points"]], dtype=np.float32)  # the same float32 inputs as C#
    features, scale = extract_features(grid, sh, raycaster)
    assert_within(scale, data["lighting_scale"], data["tolerance"], "lighting_scale")
    expected = np.asarray([p["features"] for p in data["points"]], dtype=np.float32)
    for column, name in enumerate(LPNN_V1.names):
        assert_within(features[:, column], expected[:, column], data["tolerance"], f"feature {column} {name}")
