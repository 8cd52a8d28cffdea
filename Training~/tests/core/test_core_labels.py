"""lpnn.core.labels: half-open cells, outside probes, errors (Documentation~/selection.md, "Labels")."""

from __future__ import annotations

import time

import numpy as np
import pytest

from lpnn.core.grid_box import Box
from lpnn.core.grid_builder import build_grid
from lpnn.core.labels import LabelError, LabelStats, labels_from_probes


def test_half_open_cells():
    grid = build_grid([Box.axis_aligned([0, 0, 0], [1.5, 0, 0])], 0.5)  # ids 0..3 along x
    probes = np.array([[0.25, 0, 0],  # exactly on the face between 0 and 1: belongs to 1 ([0.25, 0.75))
                       [0.2499, 0, 0],  # -> 0
                       [1.0, 0.2499, -0.25],  # -> 2 (y, z inside [-0.25, 0.25))
                       [1.0, 0.25, 0],  # y on the upper face: cell j = 1, not a grid point
                       [1.01, 0, 0]])  # -> 2 again
    labels, stats = labels_from_probes(grid, probes)
    assert labels.dtype == np.uint8 and labels.tolist() == [1, 1, 1, 0]
    assert stats == LabelStats(probes_matched=4, probes_outside=1, positive_points=3)


def test_no_probes_and_far_away_probes():
    grid = build_grid([Box.axis_aligned([0, 0, 0], [1, 1, 1])], 0.5)
    labels, stats = labels_from_probes(grid, np.zeros((0, 3)))
    assert labels.sum() == 0 and stats == LabelStats(0, 0, 0)
    labels, stats = labels_from_probes(grid, np.array([[1e30, -1e30, 0.0], [2.0**40, 0, 0]]))
    assert labels.sum() == 0 and stats.probes_outside == 2


def test_non_finite_probe_is_an_error_naming_it():
    grid = build_grid([Box.axis_aligned([0, 0, 0], [1, 1, 1])], 0.5)
    with pytest.raises(LabelError, match=r"probe 2 has a non-finite position .*2 of 4 probes"):
        labels_from_probes(grid, np.array([[0, 0, 0], [0.5, 0, 0], [np.nan, 0, 0], [0, np.inf, 0]]))


def test_many_probes_are_linear_time():
    grid = build_grid([Box.axis_aligned([0, 0, 0], [49.5, 49.5, 19.5])], 0.5)  # 400k points
    rng = np.random.default_rng(0)
    probes = rng.uniform(-1, 51, size=(300_000, 3))
    start = time.perf_counter()
    labels, stats = labels_from_probes(grid, probes)
    assert time.perf_counter() - start < 3.0
    ids = np.floor(probes / 0.5 + 0.5)
    inside = np.all((ids >= 0) & (ids <= [99, 99, 39]), axis=1)
    assert stats.probes_matched == int(inside.sum()) and stats.probes_outside == int((~inside).sum())
    assert stats.positive_points == len({tuple(r) for r in ids[inside].astype(int).tolist()}) == int(labels.sum())
