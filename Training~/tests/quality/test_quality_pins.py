"""Pinned probes (quality/placement/pins.py, Documentation~/pins.md): snapping, blocking, validation, and every method keeping
them."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.baselines import random_ranking
from lpnn.quality.placement.insertion import InsertionOrder, insertion_ranking
from lpnn.quality.metric.metric import ReferenceField, mean_placement_error
from lpnn.quality.placement.pins import PinError, pin_probes, pinned_selection, read_pins_json
from lpnn.quality.placement.policies import budget_count, place_count, place_tolerance
from lpnn.quality.placement.refined_insertion import refined_insertion

from quality_support import box_grid


def _grid(capture: Capture) -> EvaluationGrid:
    return EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)


def _pins_of(capture: Capture, every: int = 37, offset: float = 0.3):
    """Every `every`-th point, moved off the grid by `offset` cells along x (off-grid artist probes)."""
    chosen = np.arange(0, capture.point_count, every)
    positions = capture.positions[chosen].astype(np.float64) + np.array([offset * capture.cell_size, 0.0, 0.0])
    return chosen, pin_probes(positions, capture.positions, capture.cell_size)


def test_a_pin_stands_for_its_nearest_point_and_blocks_the_points_within_one_cell() -> None:
    world = box_grid(4, 3, 3, spacing=0.5)
    pins = pin_probes(np.array([[0.6, 0.5, 0.5], [1.5, 0.0, 1.0]]), world, 0.5)
    # (0.6, 0.5, 0.5) is 0.1 from grid point (0.5, 0.5, 0.5); the on-grid pin is its own point.
    assert pins.indices.tolist() == [1 + 4 * 1 + 12 * 1, 3 + 0 + 12 * 2]
    near = np.linalg.norm(world[:, None, :] - np.array([[0.6, 0.5, 0.5], [1.5, 0.0, 1.0]])[None], axis=2).min(axis=1)
    # Blocked: the pins' points and the points closer than a cell (1.0 x 0.5): (1, 0.5, 0.5) is 0.4 away; the on-grid
    # pin's neighbours at exactly one cell stay candidates.
    np.testing.assert_array_equal(np.flatnonzero(pins.blocked), np.flatnonzero(near < 0.5 - 1e-3 * 0.5))
    assert pins.blocked[2 + 4 + 12] and not pins.blocked[3 + 4 + 24] and not pins.blocked[3 + 12 * 1]


@pytest.mark.parametrize("positions, message", [
    (np.zeros((0, 3)), "no pinned positions"),
    (np.array([[0.0, np.nan, 0.0]]), "pinned probe 0 is at (0, nan, 0), not a finite position"),
    (np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]]), "pinned probes 0 and 2 are both at (0, 0, 0)"),
    (np.array([[0.5, 0.5, 0.5], [9.0, 0.0, 0.0]]), "pinned probe 1 at (9, 0, 0) is 7.5 from the nearest"),
    (np.array([[0.5, 0.5, 0.5], [0.55, 0.5, 0.5]]), "pinned probes 0 and 1 ((0.5, 0.5, 0.5), (0.55, 0.5, 0.5)) both "
                                                     "stand for evaluation point 17"),
])
def test_bad_pins_are_refused_by_name(positions: np.ndarray, message: str) -> None:
    with pytest.raises(PinError) as raised:
        pin_probes(positions, box_grid(4, 3, 3, spacing=0.5), 0.5)
    assert message in str(raised.value)


def test_a_budget_smaller_than_the_pins_names_both_numbers(medium_capture: Capture) -> None:
    field, grid = ReferenceField.from_capture(medium_capture), _grid(medium_capture)
    _, pins = _pins_of(medium_capture, every=5)
    with pytest.raises(PinError, match=f"keeps {budget_count(0.1, field.point_count)} probes but {pins.count} are pinned"):
        refined_insertion(field, grid, budget=0.1, pins=pins)


def test_insertion_ranks_the_pins_first_and_never_a_point_near_one(medium_capture: Capture) -> None:
    field, grid = ReferenceField.from_capture(medium_capture), _grid(medium_capture)
    _, pins = _pins_of(medium_capture)
    order = InsertionOrder(field, grid, pins=pins)
    ranking = order.prefix(field.point_count)
    np.testing.assert_array_equal(ranking[:pins.count], pins.indices)
    assert np.unique(ranking).shape[0] == ranking.shape[0]
    assert not np.any(pins.blocked[ranking[pins.count:]])
    np.testing.assert_array_equal(np.sort(ranking), np.flatnonzero(~pins.blocked | np.isin(np.arange(field.point_count),
                                                                                            pins.indices)))
    for count in (pins.count, pins.count + 10, 3 * pins.count):
        chosen = order.selection()(count)
        assert np.all(np.isin(pins.indices, chosen)) and chosen.shape[0] == count


def test_without_pins_insertion_is_unchanged(medium_capture: Capture) -> None:
    field, grid = ReferenceField.from_capture(medium_capture), _grid(medium_capture)
    np.testing.assert_array_equal(InsertionOrder(field, grid, pins=None).prefix(field.point_count),
                                  insertion_ranking(field, grid))


@pytest.mark.parametrize("policy", [{"budget": 0.2}, {"tolerance": 0.05}])
def test_refined_insertion_keeps_every_pin_and_no_new_probe_near_one(medium_capture: Capture, policy: dict) -> None:
    field, grid = ReferenceField.from_capture(medium_capture), _grid(medium_capture)
    _, pins = _pins_of(medium_capture)
    placed = refined_insertion(field, grid, pins=pins, **policy)
    assert np.all(np.isin(pins.indices, placed.indices))
    new = np.setdiff1d(placed.indices, pins.indices)
    assert not np.any(pins.blocked[new])
    assert placed.mean_error == pytest.approx(mean_placement_error(field, placed.indices), abs=1e-12)
    if "budget" in policy:
        assert placed.indices.shape[0] == budget_count(0.2, field.point_count)
    else:
        assert placed.mean_error <= 0.05


@pytest.mark.parametrize("policy", ["budget", "tolerance"])
def test_a_ranking_method_keeps_the_pins_first(medium_capture: Capture, policy: str) -> None:
    field, grid = ReferenceField.from_capture(medium_capture), _grid(medium_capture)
    _, pins = _pins_of(medium_capture)
    select = pinned_selection(grid, random_ranking(field.point_count, 3), pins)
    placed = (place_count(field, select, budget_count(0.2, field.point_count)) if policy == "budget"
              else place_tolerance(field, select, 0.05, smallest=pins.count))
    assert np.all(np.isin(pins.indices, placed.indices))
    assert not np.any(pins.blocked[np.setdiff1d(placed.indices, pins.indices)])
    with pytest.raises(PinError, match=f"keeps 3 probes but {pins.count} are pinned"):
        select(3)


def test_a_pins_file_is_read_and_checked(tmp_path) -> None:
    good = tmp_path / "pins.probes.json"
    good.write_text(json.dumps({"format": "lpnn.probes", "version": 1, "units": "m", "space": "world", "count": 2,
                                "positions": [[0, 1, 2], [3.5, 4, 5]], "source": {}}), encoding="utf-8")
    np.testing.assert_array_equal(read_pins_json(good, "m"), [[0, 1, 2], [3.5, 4, 5]])
    with pytest.raises(PinError, match="in 'm', the capture's in 'ft'"):
        read_pins_json(good, "ft")
    empty = tmp_path / "empty.probes.json"
    empty.write_text(json.dumps({"format": "lpnn.probes", "positions": []}), encoding="utf-8")
    with pytest.raises(PinError, match="holds no positions"):
        read_pins_json(empty)
    bad = tmp_path / "bad.probes.json"
    bad.write_text(json.dumps({"format": "lpnn.probes", "positions": [[0, 1, 2], [0, "x", 1]]}), encoding="utf-8")
    with pytest.raises(PinError, match=r"position 1 is \[0, 'x', 1\], not three numbers"):
        read_pins_json(bad)
