"""The placement error metric: definitions, edge cases, and the LumiProbes bugs it must not have."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core import sh as shmath
from lpnn.core.capture import Capture
from lpnn.quality.metric.metric import (LIGHT_VALUES, METRIC_EPSILON, MetricError, ReferenceField, evaluate_placement,
                                        irradiance_error, placement_error, point_errors, smape_error)

from quality_support import box_grid, linear_sh


def _grid_field(sh_of_positions, nx: int = 5, ny: int = 4, nz: int = 4) -> ReferenceField:
    positions = box_grid(nx, ny, nz, 0.5)
    return ReferenceField.from_sh(positions, sh_of_positions(positions))


def _corners(positions: np.ndarray) -> np.ndarray:
    lo, hi = positions.min(axis=0), positions.max(axis=0)
    on_corner = np.all((positions == lo) | (positions == hi), axis=1)
    return np.flatnonzero(on_corner)


def test_full_set_has_zero_error(small_field: ReferenceField) -> None:
    quality = evaluate_placement(small_field, np.arange(small_field.point_count))
    assert quality.irradiance.mean == 0.0 and quality.irradiance.p95 == 0.0
    assert quality.smape.mean == 0.0 and quality.probes == small_field.point_count


def test_removing_a_probe_that_matters_costs_error_and_a_redundant_one_costs_none() -> None:
    # Lighting linear in position except a bump at one interior point.
    def sh_of(positions: np.ndarray) -> np.ndarray:
        sh = linear_sh(positions)
        bump = np.all(np.isclose(positions, [1.0, 1.0, 1.0]), axis=1)
        sh[bump] += shmath.ambient(np.array([2.0, 1.0, 0.5]))
        return sh

    field = _grid_field(sh_of)
    bump = int(np.flatnonzero(np.all(np.isclose(field.world, [1.0, 1.0, 1.0]), axis=1))[0])
    everything = np.arange(field.point_count)
    without_bump = placement_error(field, np.delete(everything, bump))
    assert without_bump.mean > 0.0 and without_bump.per_point[bump] > 0.05
    far_interior = int(np.flatnonzero(np.all(np.isclose(field.world, [1.5, 0.5, 0.5]), axis=1))[0])
    without_redundant = placement_error(field, np.delete(everything, far_interior))
    assert without_redundant.mean < 1e-12  # linear there: interpolation is exact


def test_probes_have_zero_error_and_p95_is_the_95th_percentile(small_field: ReferenceField) -> None:
    probes = np.arange(0, small_field.point_count, 3)
    summary = placement_error(small_field, probes)
    assert np.all(summary.per_point[probes] == 0.0)
    assert summary.p95 == pytest.approx(np.percentile(summary.per_point, 95))
    assert summary.mean == pytest.approx(summary.per_point.mean())


def test_all_black_scene_has_zero_error_and_no_nan() -> None:
    field = _grid_field(lambda p: np.zeros((p.shape[0], 27)))
    assert field.scale == 1.0  # features.md: S = 1 when no point is lit
    quality = evaluate_placement(field, _corners(field.world))
    assert quality.irradiance.mean == 0.0 and quality.smape.mean == 0.0
    assert np.all(np.isfinite(quality.irradiance.per_point))


@pytest.mark.parametrize("exposure", [1e-6, 1e6])
def test_relative_metrics_are_exposure_invariant(small_captures: dict[int, Capture], exposure: float) -> None:
    capture = small_captures[2]
    probes = np.arange(0, capture.point_count, 3)
    base = evaluate_placement(ReferenceField.from_sh(capture.positions, capture.sh), probes)
    scaled = evaluate_placement(ReferenceField.from_sh(capture.positions, capture.sh.astype(np.float64) * exposure),
                                probes)
    assert scaled.irradiance.mean == pytest.approx(base.irradiance.mean, rel=1e-9)
    assert scaled.irradiance.p95 == pytest.approx(base.irradiance.p95, rel=1e-9)
    assert scaled.smape.mean == pytest.approx(base.smape.mean, rel=1e-9)
    assert base.irradiance.mean > 0.01


def test_non_finite_reference_is_an_error_naming_the_point() -> None:
    positions = box_grid(3, 3, 3)
    sh = np.ones((27, 27))
    sh[5, 12] = np.nan
    with pytest.raises(MetricError, match=r"point 5 .*sh\[g,3\]"):
        ReferenceField.from_sh(positions, sh)


def test_bad_probe_indices_are_errors(small_field: ReferenceField) -> None:
    with pytest.raises(MetricError, match="more than once"):
        placement_error(small_field, np.array([0, 1, 2, 3, 3]))
    with pytest.raises(MetricError, match="outside"):
        placement_error(small_field, np.array([0, 1, 2, small_field.point_count]))
    with pytest.raises(MetricError, match="unknown metric"):
        point_errors(small_field, np.arange(8), metric="rmse")


def test_directional_differences_count_not_only_the_dc_term() -> None:
    # LumiProbes B5: averaging over a symmetric direction set keeps only the DC term. Two fields with
    # the same DC and different L1 must differ under this metric.
    directions = np.array([[1.0, 0.0, 0.0]])
    reference = np.repeat(shmath.directional(directions, np.array([[1.0, 1.0, 1.0]])), 1, axis=0)
    flipped = shmath.directional(-directions, np.array([[1.0, 1.0, 1.0]]))
    assert np.allclose(reference.reshape(3, 9)[:, 0], flipped.reshape(3, 9)[:, 0])  # same DC
    light = lambda sh: shmath.evaluate(sh, np.eye(3)[[0]]).reshape(1, -1)  # noqa: E731
    assert irradiance_error(light(flipped), light(reference), 1.0)[0] > 0.5


def test_metric_definitions_on_hand_values() -> None:
    reference = np.full((1, LIGHT_VALUES), 2.0)
    estimate = np.full((1, LIGHT_VALUES), 1.0)
    floor = LIGHT_VALUES * METRIC_EPSILON * 1.0
    assert irradiance_error(estimate, reference, 1.0)[0] == pytest.approx(LIGHT_VALUES / (3 * LIGHT_VALUES + floor))
    assert smape_error(estimate, reference, 1.0)[0] == pytest.approx(1.0 / (3.0 + METRIC_EPSILON))
    opposite = -reference
    assert smape_error(opposite, reference, 1.0)[0] <= 1.0  # bounded even across a sign flip
    assert irradiance_error(opposite, reference, 1.0)[0] <= 1.0
    # A black point that receives light counts at most 1 (not 1/eps): dark corners cannot dominate.
    black = np.zeros((1, LIGHT_VALUES))
    assert 0.99 < irradiance_error(np.full((1, LIGHT_VALUES), 5.0), black, 1.0)[0] <= 1.0


def test_dark_points_are_floored_not_exploding() -> None:
    reference = np.full((1, LIGHT_VALUES), 1e-12)
    estimate = np.zeros((1, LIGHT_VALUES))
    assert irradiance_error(estimate, reference, 1.0)[0] < 1e-9
    assert smape_error(estimate, reference, 1.0)[0] < 1e-9
