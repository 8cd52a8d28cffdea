"""The in-use rule against Tests/Data/in_use_golden.json (built by construction, Tools~/golden/make_in_use_golden.py)."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core import in_use
from lpnn.core.analytic_scene import AnalyticBoxRaycaster
from lpnn.core.grid import EvaluationGrid
from lpnn.core.in_use import InUseParameters, in_band, in_use_mask, reachable

GOLDEN = "in_use_golden.json"


@pytest.fixture(scope="module")
def scene(golden):
    data = golden(GOLDEN)
    grid = EvaluationGrid(cell_size=data["cell_size"], ids=np.array(data["ids"], dtype=np.int32))
    seeds = np.array([s["position"] for s in data["seeds"]], dtype=np.float64)
    return data, grid, AnalyticBoxRaycaster.from_json(data), seeds


def _cases(golden):
    return golden(GOLDEN)["cases"]


def test_the_golden_covers_what_it_promises(scene) -> None:
    data, grid, _, _ = scene
    assert len(data["cases"]) >= 2 and grid.point_count == len(data["ids"]) > 1000
    for case in data["cases"]:
        band, reached = np.array(case["in_band"]), np.array(case["reachable"])
        assert not np.any(reached & ~band), case["name"]  # reachable is a subset of band
        assert 0 < reached.sum() < band.sum() < grid.point_count, case["name"]
    names = {case["name"] for case in data["cases"]}
    assert {landmark["case"] for landmark in data["landmarks"]} <= names


@pytest.mark.parametrize("case_index", range(4))
def test_masks_and_floor_heights_equal_the_golden(scene, case_index: int) -> None:
    data, grid, raycaster, seeds = scene
    case = data["cases"][case_index]
    parameters = InUseParameters(**case["parameters"])
    band, floor = in_band(grid, raycaster, parameters)
    expected_band = np.array(case["in_band"])
    wrong = np.flatnonzero(band != expected_band)
    assert wrong.shape[0] == 0, f"{case['name']}: in band differs at ids {grid.ids[wrong[:5]].tolist()}"
    expected_floor = np.array([np.nan if f is None else f for f in case["floor_height"]])
    tolerance = data["tolerance"]["floor_height"]["abs"]
    assert np.array_equal(np.isnan(floor), np.isnan(expected_floor))
    assert np.nanmax(np.abs(floor - expected_floor)) <= tolerance
    reached = reachable(grid, raycaster, parameters, seeds, band=(band, floor))
    expected_reached = np.array(case["reachable"])
    wrong = np.flatnonzero(reached != expected_reached)
    assert wrong.shape[0] == 0, f"{case['name']}: reachable differs at ids {grid.ids[wrong[:5]].tolist()}"
    assert np.array_equal(in_use_mask("reachable", grid, raycaster, parameters, seeds), expected_reached)
    assert np.array_equal(in_use_mask("band", grid, raycaster, parameters), expected_band)


@pytest.mark.parametrize("case_index", range(4))
def test_seed_start_points_equal_the_golden(scene, case_index: int) -> None:
    data, grid, raycaster, seeds = scene
    case = data["cases"][case_index]
    band = np.array(case["in_band"])
    starts = in_use._seed_starts(grid, raycaster, band, seeds, None)
    assert starts.tolist() == case["start_points"]


def test_landmarks_read_from_the_masks(scene) -> None:
    """The designed answers (the step, the 2.1 m block, the platform's item, the thin wall, the gap, the pit) hold
    in the computed masks: a failure names the feature of the layout that broke."""
    data, grid, raycaster, seeds = scene
    cases = {case["name"]: InUseParameters(**case["parameters"]) for case in data["cases"]}
    computed = {}
    for name, parameters in cases.items():
        band = in_band(grid, raycaster, parameters)
        computed[name] = (band[0], reachable(grid, raycaster, parameters, seeds, band=band))
    for landmark in data["landmarks"]:
        point = int(grid.index_of(np.array([landmark["id"]]))[0])
        assert point >= 0
        band, reached = computed[landmark["case"]]
        assert (bool(band[point]), bool(reached[point])) == (landmark["in_band"], landmark["reachable"]), \
            f"{landmark['case']}: {landmark['why']}"
