"""The compiled neighbour comparisons (features_kernel.py) give the numpy formulas' numbers bit for bit."""

from __future__ import annotations

import numpy as np

from lpnn.core import features_kernel


def _neighbours(count: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A +offset map (distinct targets, some absent) and its inverse, as a grid's neighbour() gives."""
    plus = rng.permutation(count).astype(np.int64)
    plus[rng.uniform(size=count) < 0.2] = -1
    minus = np.full(count, -1, dtype=np.int64)
    present = np.flatnonzero(plus >= 0)
    minus[plus[present]] = present
    return plus, minus


def test_change_and_curvature_equal_the_numpy_formulas() -> None:
    rng = np.random.default_rng(0)
    count = 5_000
    light = (rng.lognormal(size=(count, 42)) * rng.choice([-1.0, 1.0], size=(count, 42))).astype(np.float32).astype(np.float64)
    abs_sum = np.abs(light).sum(axis=1)
    floor = 42 * 1e-3 * 0.37
    plus, minus = _neighbours(count, rng)

    change = rng.uniform(0.0, 0.5, count)  # earlier offsets' maxima
    expected_change = change.copy()
    present = np.flatnonzero(plus >= 0)
    q = plus[present]
    rel = np.abs(light[q] - light[present]).sum(axis=1) / (abs_sum[q] + abs_sum[present] + floor)
    expected_change[present] = np.maximum(expected_change[present], rel)
    expected_change[q] = np.maximum(expected_change[q], rel)
    features_kernel.raise_change(light, abs_sum, floor, plus, change)
    np.testing.assert_array_equal(change, expected_change)

    curvature = rng.uniform(0.0, 0.5, count)
    expected_curvature = curvature.copy()
    both = np.flatnonzero((plus >= 0) & (minus >= 0))
    midpoint = (light[plus[both]] + light[minus[both]]) * 0.5
    rel = np.abs(midpoint - light[both]).sum(axis=1) / (abs_sum[both] + np.abs(midpoint).sum(axis=1) + floor)
    expected_curvature[both] = np.maximum(expected_curvature[both], rel)
    features_kernel.raise_curvature(light, abs_sum, floor, plus, minus, curvature)
    np.testing.assert_array_equal(curvature, expected_curvature)


def test_pairwise_sum_is_numpys_for_every_short_length() -> None:
    rng = np.random.default_rng(1)
    for length in range(0, 129):
        values = rng.lognormal(size=(3, length)) * 1e3
        expected = values.sum(axis=1)
        for row in range(3):
            assert features_kernel.pairwise_sum(values[row], length) == expected[row], length
