"""The leak-aware exact reference (reference_fast.fast_decimation(..., leaks=LeakWeighting)) on two rooms split by a
wall: every error it sums is the leak-weighted one, checked against errors and leaks computed afresh by the metric
(metric/leaks.py), not by the decimation's own state."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.metric.leaks import leaking_points
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.placement.decimation.removal_costs import SerialCosts
from lpnn.quality.placement.decimation.reference_fast import fast_decimation
from lpnn.quality.placement.leak_aware import LeakWeighting
from lpnn.quality.placement.policies import reference_tolerance

from quality_support import OPEN, WALLED, two_rooms

TOLERANCE = 0.05
WEIGHT = 8.0


@pytest.fixture(scope="module")
def field() -> ReferenceField:
    return two_rooms()[0]


@pytest.fixture(scope="module")
def blind(field: ReferenceField):
    return fast_decimation(field)


@pytest.fixture(scope="module")
def aware(field: ReferenceField):
    return fast_decimation(field, leaks=LeakWeighting(WALLED, WEIGHT))


def _fresh_weighted_sum(field: ReferenceField, probes: np.ndarray, weight: float) -> float:
    """The leak-weighted error sum of `probes` from scratch: the metric's errors and leaks of a new
    tetrahedralisation."""
    leaking, errors = leaking_points(field, probes, WALLED)
    return float(np.sum(np.where(leaking, weight * errors, errors)))


def test_without_a_wall_or_with_weight_one_it_is_the_leak_blind_reference(field: ReferenceField, blind) -> None:
    for leaks in (LeakWeighting(OPEN, WEIGHT), LeakWeighting(WALLED, 1.0)):
        same = fast_decimation(field, leaks=leaks)
        assert np.array_equal(same.removed, blind.removed)
        assert np.array_equal(same.error_curve, blind.error_curve, equal_nan=True)
        assert same.leak_weight == leaks.weight
    assert blind.leak_weight is None


def test_its_curve_is_the_fresh_leak_weighted_error_of_every_set_it_held(field: ReferenceField, aware) -> None:
    assert aware.leak_weight == WEIGHT
    for count in (field.point_count - 1, 400, 150, 60, 20, 8):
        expected = _fresh_weighted_sum(field, aware.prefix(count), WEIGHT) / field.point_count
        assert aware.error_curve[count] == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_a_removal_costs_the_fresh_weighted_error_without_the_probe_minus_the_set_s(field: ReferenceField,
                                                                                    blind) -> None:
    """Every removal's cost from a set with stencils across the wall (the leak-blind reference's 20 probes), interior
    and hull probes alike, against fresh evaluations of the set without that probe and of the set."""
    held = blind.prefix(20)
    assert leaking_points(field, held, WALLED)[0].any()
    costs = SerialCosts(field, "irradiance", held, LeakWeighting(WALLED, WEIGHT).remembering(field))
    before = _fresh_weighted_sum(field, held, WEIGHT)
    assert float(costs.state.errors.sum()) == pytest.approx(before, rel=1e-9)
    weighed_differently = 0
    for v, removal in zip(held.tolist(), costs.state.removals(held.tolist())):
        rest = held[held != v]
        after = _fresh_weighted_sum(field, rest, WEIGHT)
        assert removal.delta == pytest.approx(after - before, rel=1e-7, abs=1e-9), v
        plain = _fresh_weighted_sum(field, rest, 1.0) - _fresh_weighted_sum(field, held, 1.0)
        weighed_differently += abs(removal.delta - plain) > 1e-6
    assert weighed_differently >= 3  # the leaks' weight decided some of the costs
    assert int(costs.state.extreme[held].sum()) >= 4  # hull probes among them


def test_with_a_wall_its_answer_leaks_less_and_its_weighted_error_is_within_tau(field: ReferenceField, blind,
                                                                               aware) -> None:
    blind_answer = reference_tolerance(blind, TOLERANCE).indices
    aware_answer = reference_tolerance(aware, TOLERANCE).indices
    blind_leaks = int(leaking_points(field, blind_answer, WALLED)[0].sum())
    aware_leaks = int(leaking_points(field, aware_answer, WALLED)[0].sum())
    assert blind_leaks > 0 and aware_leaks < blind_leaks
    assert _fresh_weighted_sum(field, aware_answer, WEIGHT) / field.point_count <= TOLERANCE + 1e-12
    # The fewest: the set one probe smaller that the greedy held is above tau (weighted).
    smaller = aware.prefix(aware_answer.shape[0] - 1)
    assert _fresh_weighted_sum(field, smaller, WEIGHT) / field.point_count > TOLERANCE


def test_it_is_deterministic_and_the_two_process_replica_gives_the_same_result(field: ReferenceField, aware) -> None:
    again = fast_decimation(field, leaks=LeakWeighting(WALLED, WEIGHT))
    assert np.array_equal(again.removed, aware.removed)
    assert np.array_equal(again.error_curve, aware.error_curve, equal_nan=True)
    paired = fast_decimation(field, leaks=LeakWeighting(WALLED, WEIGHT), workers=2)
    assert np.array_equal(paired.removed, aware.removed)
    assert np.array_equal(paired.error_curve, aware.error_curve, equal_nan=True)


def test_a_seed_at_the_floor_reports_its_weighted_error(field: ReferenceField) -> None:
    seed = np.array([0, 16, field.point_count - 17, field.point_count - 1, 100, 300])
    left = fast_decimation(field, initial=seed, min_count=seed.shape[0], leaks=LeakWeighting(WALLED, WEIGHT))
    expected = _fresh_weighted_sum(field, np.sort(seed), WEIGHT) / field.point_count
    assert left.removed.shape[0] == 0
    assert left.error_curve[seed.shape[0]] == pytest.approx(expected, rel=1e-12)


class _Unsendable:
    """The walls, in a raycaster that cannot be sent to another process (as Embree's scene cannot)."""

    def __init__(self, inner) -> None:
        self.inner = inner

    def __getattr__(self, name: str):
        return getattr(self.inner, name)

    def __reduce__(self):
        raise TypeError("this raycaster cannot be pickled")


def test_the_two_process_replica_refuses_a_raycaster_it_cannot_receive(field: ReferenceField) -> None:
    with pytest.raises(ValueError, match="run it with workers=1"):
        fast_decimation(field, leaks=LeakWeighting(_Unsendable(WALLED), WEIGHT), workers=2)
