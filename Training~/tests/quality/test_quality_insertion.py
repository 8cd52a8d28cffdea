"""Error-driven insertion (quality/insertion.py): the non-learned lighting-driven yardstick."""

from __future__ import annotations

import numpy as np

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.baselines import heuristic_ranking, random_ranking, uniform_selector
from lpnn.quality.insertion import insertion_ranking, typical_tetrahedron
from lpnn.quality.metric import POINT_ERRORS, ReferenceField, placement_error
from lpnn.quality.policies import budget_count, prefix_selection
from lpnn.quality.triangulation import flatness

from quality_support import MEDIUM_ROOM, room_capture


def _grid(capture: Capture) -> EvaluationGrid:
    return EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)


def test_insertion_is_a_deterministic_permutation_starting_from_a_typical_tetrahedron(medium_capture: Capture) -> None:
    field = ReferenceField.from_capture(medium_capture)
    grid = _grid(medium_capture)
    ranking = insertion_ranking(field, grid)
    np.testing.assert_array_equal(np.sort(ranking), np.arange(medium_capture.point_count))
    np.testing.assert_array_equal(ranking, insertion_ranking(field, grid))
    start = typical_tetrahedron(field, grid)
    np.testing.assert_array_equal(ranking[:start.shape[0]], start)
    assert start.shape[0] == 4 and flatness(field.local[start]) is None
    # Its lighting is among the 10 % nearest the median lighting.
    median = np.median(field.light, axis=0, keepdims=True)
    deviation = POINT_ERRORS["irradiance"](np.broadcast_to(median, field.light.shape), field.light, field.scale)
    assert np.all(deviation[start] <= np.quantile(deviation, 0.1) + 1e-12)


def test_insertion_beats_the_heuristic_random_and_uniform_at_a_20_percent_budget() -> None:
    """Measured: irradiance error 0.029 / 0.025 / 0.033 against the heuristic's 0.042 / 0.028 / 0.045 (ratios 0.68 /
    0.90 / 0.74). Seed 4's ratio moves between machines (0.86 on one, 0.90 on another): the regular triangulation
    resolves the lattice's co-spherical ties by rounding, which differs with the CPU's vector width. So each seed
    must beat the heuristic, and the seeds together by 15 %."""
    ratios = []
    for seed in (3, 4, 5):
        capture = room_capture(seed, MEDIUM_ROOM, 0.4)
        field = ReferenceField.from_capture(capture)
        grid = _grid(capture)
        count = budget_count(0.2, capture.point_count)
        inserted = placement_error(field, prefix_selection(grid, insertion_ranking(field, grid))(count)).mean
        heuristic = placement_error(field, prefix_selection(grid, heuristic_ranking(grid, capture.sh,
                                                                                     capture.lighting_scale))(count)).mean
        random = placement_error(field, prefix_selection(grid, random_ranking(capture.point_count))(count)).mean
        uniform = placement_error(field, uniform_selector(grid)(count)).mean
        assert inserted < heuristic and inserted < 0.7 * random and inserted < 0.7 * uniform, seed
        ratios.append(inserted / heuristic)
    assert np.mean(ratios) < 0.85, ratios
