"""The analytic test scene of Tests/Data/README.md: light field formula, slab raycaster rules, JSON."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from lpnn.core.analytic_scene import (
    AnalyticBoxRaycaster,
    AnalyticLightField,
    AnalyticScene,
    AxisBox,
    LightBlob,
    load_scene,
)
from lpnn.core.capture_file import read_capture, write_capture
from lpnn.core.features import Raycaster


def cast_one(raycaster, origin, direction, max_distance=100.0):
    t, n = raycaster.cast(np.array([origin], float), np.array([direction], float), max_distance)
    return float(t[0]), n[0].tolist()


def test_light_field_formula():
    base = np.arange(27) * 0.01
    blob_sh = np.linspace(-1, 2, 27)
    field = AnalyticLightField(base, (LightBlob([1.0, 2.0, -0.5], 1.5, blob_sh), LightBlob([0, 0, 0], 0.7, base)))
    p = np.array([[0.3, 1.1, 0.2]], dtype=np.float32)
    x, y, z = (float(v) for v in p[0])
    w1 = math.exp(-((x - 1) ** 2 + (y - 2) ** 2 + (z + 0.5) ** 2) / 1.5**2)
    w2 = math.exp(-(x * x + y * y + z * z) / 0.7**2)
    expected = np.array([base[c] + blob_sh[c] * w1 + base[c] * w2 for c in range(27)], dtype=np.float32)
    actual = field.sample(p)
    assert actual.dtype == np.float32 and actual.shape == (1, 27)
    assert np.array_equal(actual[0], expected)


def test_ray_from_inside_hits_the_exit_wall():
    room = AnalyticBoxRaycaster(room=AxisBox([-1, -2, -3], [4, 5, 6]))
    assert cast_one(room, [0, 0, 0], [1, 0, 0]) == (4.0, [-1.0, 0.0, 0.0])
    assert cast_one(room, [0, 0, 0], [0, 0, -1]) == (3.0, [0.0, 0.0, 1.0])
    assert isinstance(room, Raycaster)


def test_ray_from_outside_hits_the_entry_face_and_misses_behind_or_beside():
    box = AnalyticBoxRaycaster(obstacles=(AxisBox([2, -1, -1], [3, 1, 1]),))
    assert cast_one(box, [0, 0, 0], [1, 0, 0]) == (2.0, [-1.0, 0.0, 0.0])
    assert cast_one(box, [0, 0, 0], [-1, 0, 0]) == (math.inf, [0.0, 0.0, 0.0])  # box behind: t_far < 0
    assert cast_one(box, [0, 2, 0], [1, 0, 0]) == (math.inf, [0.0, 0.0, 0.0])  # parallel, outside the y slab
    assert cast_one(box, [0, 1, 0], [1, 0, 0]) == (2.0, [-1.0, 0.0, 0.0])  # on the slab boundary: inside
    assert cast_one(box, [0, 0, 0], [1, 0, 0], max_distance=1.5) == (math.inf, [0.0, 0.0, 0.0])
    assert cast_one(box, [0, 0, 0], [1, 0, 0], max_distance=2.0)[0] == 2.0  # t <= max counts


def test_ties_go_to_the_lowest_axis_and_to_the_room_first():
    s = 1 / math.sqrt(2)
    corner = AnalyticBoxRaycaster(room=AxisBox([-1, -1, -1], [1, 1, 1]))
    assert cast_one(corner, [0, 0, 0], [s, s, 0])[1] == [-1.0, 0.0, 0.0]  # exit: x and y tie -> x
    outside = AnalyticBoxRaycaster(obstacles=(AxisBox([1, 1, -1], [2, 2, 1]),))
    assert cast_one(outside, [0, 0, 0], [s, s, 0])[1] == [-1.0, 0.0, 0.0]  # entry: tie -> x
    # an obstacle face coinciding with the room wall: same t, the room's normal wins (identical here)
    both = AnalyticBoxRaycaster(room=AxisBox([-1, -1, -1], [1, 1, 1]), obstacles=(AxisBox([1, -2, -2], [2, 2, 2]),))
    t, n = cast_one(both, [0, 0, 0], [1, 0, 0])
    assert t == 1.0 and n == [-1.0, 0.0, 0.0]
    nearer = AnalyticBoxRaycaster(room=AxisBox([-9, -9, -9], [9, 9, 9]), obstacles=(AxisBox([0.5, -1, -1], [2, 1, 1]),))
    assert cast_one(nearer, [0, 0, 0], [1, 0, 0]) == (0.5, [-1.0, 0.0, 0.0])


def test_scene_json_round_trip_and_load_scene():
    scene = AnalyticScene.random(seed=4)
    data = json.loads(json.dumps(scene.to_json()))
    assert set(data) == {"cell_size", "boxes", "room", "obstacles", "light_field"}
    boxes, cell_size, field, raycaster = load_scene(data)
    assert cell_size == scene.cell_size and len(boxes) == len(scene.boxes)
    assert np.array_equal(boxes[0].half_edges, scene.boxes[0].half_edges)
    positions = scene.grid().positions
    assert np.array_equal(field.sample(positions), scene.light_field.sample(positions))
    origins = positions.astype(np.float64)
    directions = np.tile([0.0, 0.0, 1.0], (origins.shape[0], 1))
    for a, b in zip(raycaster.cast(origins, directions, 2.0), scene.raycaster.cast(origins, directions, 2.0)):
        assert np.array_equal(a, b)


def test_random_scenes_are_deterministic_and_make_valid_captures(tmp_path):
    first, second = AnalyticScene.random(seed=9), AnalyticScene.random(seed=9)
    assert json.dumps(first.to_json()) == json.dumps(second.to_json())
    assert json.dumps(first.to_json()) != json.dumps(AnalyticScene.random(seed=10).to_json())
    capture = first.capture(name="room9")
    path = write_capture(tmp_path / "room9.lpnncap", capture)
    again = read_capture(path)
    assert np.array_equal(again.features, capture.features) and again.source["scene"] == "room9"


def test_invalid_scene_values_are_rejected():
    with pytest.raises(ValueError, match="sigma"):
        LightBlob([0, 0, 0], 0.0, np.zeros(27))
    with pytest.raises(ValueError, match="27 finite numbers"):
        AnalyticLightField(np.zeros(26))
    with pytest.raises(ValueError, match="exceeds max"):
        AxisBox([1, 0, 0], [0, 1, 1])
