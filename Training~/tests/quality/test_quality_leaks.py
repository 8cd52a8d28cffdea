"""Light leaking through walls (Documentation~/leaks.md): the rule's decisions, the report's figures."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AxisBox
from lpnn.core.features import FeatureError
from lpnn.core.segments import segments_free
from lpnn.quality.metric.leak_rule import LEAK_MIN_WEIGHT, stencil_leaks
from lpnn.quality.metric.leaks import leak_report, leaking_points, near_surface_mask
from lpnn.quality.metric.metric import ReferenceField

from quality_support import box_grid, linear_sh

WALL = AxisBox(min=[-0.1, -10.0, -10.0], max=[0.1, 10.0, 10.0])  # the plane x = 0, 0.2 m thick
WALLED = AnalyticBoxRaycaster(obstacles=(WALL,))
OPEN = AnalyticBoxRaycaster()


def test_a_segment_is_blocked_only_by_a_surface_before_its_end():
    starts = np.array([[-1.0, 0, 0], [-1.0, 0, 0], [-1.0, 0, 0], [0.5, 0, 0]])
    ends = np.array([[1.0, 0, 0], [-0.2, 0, 0], [-1.0, 0, 0], [3.0, 0, 0]])
    # through the wall; stopping 0.1 m short of it; zero length; beyond the wall on one side
    assert segments_free(WALLED, starts, ends).tolist() == [False, True, True, True]


class RecordingEnds:
    """WALLED's answers, recording the ray ends it is asked for; with `own_ends` it offers first_hit_distances."""

    def __init__(self, own_ends: bool) -> None:
        self.ends: list[np.ndarray] = []
        if own_ends:
            self.first_hit_distances = self._first_hit_distances

    def cast(self, origins, directions, max_distance):
        self.ends.append(np.full(len(origins), max_distance))
        return WALLED.cast(origins, directions, max_distance)

    def _first_hit_distances(self, origins, directions, max_distances):
        self.ends.append(np.array(max_distances))
        distances = WALLED.cast(origins, directions, float(np.max(max_distances)))[0]
        return np.where(distances <= max_distances, distances, np.inf)


def test_a_raycaster_that_can_end_each_ray_casts_each_segment_to_its_own_length():
    starts = np.array([[-1.0, 0, 0], [-1.0, 0, 0], [-1.0, 0, 0], [0.5, 0, 0]])
    ends = np.array([[1.0, 0, 0], [-0.2, 0, 0], [-1.0, 0, 0], [3.0, 0, 0]])
    own, shared = RecordingEnds(own_ends=True), RecordingEnds(own_ends=False)
    assert segments_free(own, starts, ends).tolist() == segments_free(shared, starts, ends).tolist() == [
        False, True, True, True]
    assert np.allclose(np.concatenate(own.ends), [2.0, 0.8, 2.5])  # the zero-length segment is not cast
    assert np.allclose(np.concatenate(shared.ends), [2.5, 2.5, 2.5])  # the longest, for every ray


class NegativeEnds:
    """A broken per-ray raycaster: every distance -1."""

    def cast(self, origins, directions, max_distance):
        raise AssertionError("the per-ray cast is expected")

    def first_hit_distances(self, origins, directions, max_distances):
        return np.full(len(origins), -1.0)


def test_a_per_ray_raycasters_distances_are_checked_as_a_plain_ones():
    with pytest.raises(FeatureError, match="distance -1.0 for ray 0"):
        segments_free(NegativeEnds(), np.zeros((1, 3)), np.ones((1, 3)))


def test_segments_of_another_shape_are_refused():
    with pytest.raises(ValueError, match="differ in shape"):
        segments_free(WALLED, np.zeros((2, 3)), np.zeros((3, 3)))


def test_a_point_leaks_when_a_weighing_probe_is_behind_the_wall():
    point = np.array([[-1.0, 0.0, 0.0]])
    probes = np.array([[-2.0, 0.0, 0.0], [2.0, 0.0, 0.0], [-2.0, 1.0, 0.0], [-2.0, 0.0, 1.0]])
    vertices = np.array([[0, 1, 2, 3]])

    def leaks(weights):
        return bool(stencil_leaks(point, probes, vertices, np.array([weights]), WALLED)[0])

    assert leaks([0.5, 0.5, 0.0, 0.0])  # half its light from the other room
    assert not leaks([0.5, 0.0, 0.25, 0.25])  # the hidden probe weighs nothing
    assert not leaks([1.0 - LEAK_MIN_WEIGHT / 10, LEAK_MIN_WEIGHT / 10, 0, 0])  # round-off, not light
    assert leaks([1.0 - LEAK_MIN_WEIGHT * 10, LEAK_MIN_WEIGHT * 10, 0, 0])
    assert not bool(stencil_leaks(point, probes, vertices, np.array([[0.5, 0.5, 0, 0]]), OPEN)[0])  # no wall


def _two_rooms(probe_sides: str) -> tuple[ReferenceField, np.ndarray]:
    """A 6 x 3 x 3 lattice from x = -2.5 to 2.5 (no point inside the wall), probes at the corners of the whole box
    ("both": tetrahedra span the wall) or of each room ("each")."""
    positions = box_grid(6, 3, 3) + np.array([-2.5, 0.0, 0.0])
    field = ReferenceField.from_sh(positions, linear_sh(positions))
    xs = positions[:, 0]
    corner = (np.isin(positions[:, 1], [0.0, 2.0])) & (np.isin(positions[:, 2], [0.0, 2.0]))
    if probe_sides == "both":
        probes = np.flatnonzero(corner & np.isin(xs, [-2.5, 2.5]))
    else:
        probes = np.flatnonzero(corner & np.isin(xs, [-2.5, -0.5, 0.5, 2.5]))
    return field, probes


def test_tetrahedra_spanning_the_wall_leak_and_rooms_of_their_own_do_not():
    field, spanning = _two_rooms("both")
    leaking, errors = leaking_points(field, spanning, WALLED)
    assert leaking.any() and not leaking[spanning].any()
    assert not leaking_points(field, spanning, OPEN)[0].any()
    # Linear lighting is reproduced exactly wherever a point is interpolated inside the hull: leaks are not errors.
    assert np.allclose(errors, 0.0, atol=1e-9)
    field, own = _two_rooms("each")
    # Every point's stencil lies in its own room, except those in the slab between the rooms (x = -0.5 .. 0.5) whose
    # tetrahedron joins the two rooms' facing corners across the wall.
    leaking = leaking_points(field, own, WALLED)[0]
    xs = field.world[:, 0]
    assert not leaking[np.abs(xs) > 0.6].any()


def test_the_report_counts_only_the_counted_points_and_averages_their_errors():
    field, probes = _two_rooms("both")
    leaking, errors = leaking_points(field, probes, WALLED)
    counted = field.world[:, 0] < 0  # one room
    near = np.abs(field.world[:, 0]) < 1.0
    report = leak_report(field, probes, WALLED, near_surface=near, counted=counted)
    assert report.points == int(counted.sum())
    assert report.leaking == int((leaking & counted).sum())
    assert math.isclose(report.leaking_share, report.leaking / report.points)
    assert report.near_surface_points == int((near & counted).sum())
    assert math.isclose(report.near_surface_error, float(errors[near & counted].mean()))
    empty = leak_report(field, probes, OPEN)
    assert empty.leaking == 0 and empty.leaking_error == 0.0 and math.isnan(empty.near_surface_error)


def test_near_surface_reads_the_nearest_surface_feature():
    features = np.array([[0.0, 0.1], [0.0, 0.25], [0.0, 0.3], [0.0, 1.0]])
    assert near_surface_mask(["x", "nearest_surface"], features).tolist() == [True, True, False, False]
    assert near_surface_mask(["x", "y"], features) is None
