"""The compiled objective (objective_kernel.py): against the numpy formula, against TensorFlow's autodiff
(an independent gradient), and deterministic on any number of threads."""

from __future__ import annotations

import numba
import numpy as np
import pytest

import lpnn.lights.objective_kernel as kernel
from lpnn.lights.model import BYTE_MAX, ForwardModel, Gradient, Lights
import gradient_checks
from gradient_checks import assert_same_bits, objectives_on_threads
from objective_bench import largest_difference, tensorflow_objective
from synthetic_room import TRUE_LIGHTS, lit_room

FIELDS = ("positions", "colours", "intensities", "ambient", "surface_values")


@pytest.fixture(scope="module")
def room() -> ForwardModel:
    model = lit_room(TRUE_LIGHTS, divisions=12)[0]
    # bytes of fixed emitters (spotlights, surface lights of a compile), added before the clamp
    model.fixed = np.outer(model.points[:, 2] / 256.0, [30.0, 20.0, 10.0])
    # two surface lights: bytes per unit value, one warm and growing with x, one blue and growing with y
    model.surface_basis = np.stack([np.outer(model.points[:, 0] / 256.0, [0.02, 0.01, 0.0]),
                                    np.outer(model.points[:, 1] / 256.0, [0.0, 0.005, 0.02])])
    return model


def hard_lights() -> Lights:
    """Three lights off the true ones: one 10 units under the ceiling (the 16-unit clamp's branch, and
    saturated luxels above it), one bright (saturation), colours whose largest channel differs."""
    return Lights(positions=np.array([[70.0, 60.0, 246.0], [190.0, 170.0, 100.0], [128.0, 40.0, 60.0]]),
                  colours=np.array([[1.0, 0.8, 0.6], [0.5, 0.7, 1.0], [0.3, 1.0, 0.2]]),
                  intensities=np.array([260.0, 900.0, 120.0]), ambient=np.array([11.0, 9.0, 7.0]),
                  surface_values=np.array([1500.0, 800.0]))


def assert_close(a: Gradient, b: Gradient, tolerance: float) -> None:
    gradient_checks.assert_close(a, b, tolerance, FIELDS)


def test_the_scene_exercises_the_clamps(room: ForwardModel) -> None:
    lights = hard_lights()
    visible = room.visibility(lights)
    light = room.radiance_of(lights, visible) / room.albedo / (4 / 255)
    assert np.count_nonzero(np.isclose(light.max(axis=1), BYTE_MAX)) >= 10  # saturated luxels
    distance = np.linalg.norm(room.points[visible[:, 0]] - lights.positions[0], axis=1)
    assert (distance < 16).any()  # pairs inside the 16-unit distance clamp


def test_compiled_pass_matches_the_numpy_formula(room: ForwardModel) -> None:
    lights = hard_lights()
    visible = room.visibility(lights)
    assert_close(room.objective(lights, visible), room.objective_numpy(lights, visible), 1e-12)
    value_only = room.objective(lights, visible, with_gradient=False)
    assert value_only.value == room.objective(lights, visible).value
    assert not np.any(value_only.positions)


def test_analytic_gradients_match_tensorflow_autodiff(room: ForwardModel) -> None:
    lights = hard_lights()
    visible = room.visibility(lights)
    autodiff = tensorflow_objective(room, lights, visible)(lights)
    assert autodiff.value > 0.01
    assert_close(room.objective(lights, visible), autodiff, 1e-10)
    assert_close(room.objective_numpy(lights, visible), autodiff, 1e-10)
    # and the comparison can fail: a gradient off by 1 % in one light's position is caught
    wrong = room.objective(lights, visible)
    wrong.positions[1] *= 1.01
    assert largest_difference(wrong, autodiff) > 1e-4


def test_the_same_bits_on_one_and_two_threads_and_on_every_call(room: ForwardModel,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(kernel, "PARALLEL_POINTS", 100)  # many slices on this small room
    assert kernel.chunks_for(room.point_count) >= 8
    lights = hard_lights()
    visible = room.visibility(lights)
    runs = objectives_on_threads(room, lights, visible)
    assert numba.config.NUMBA_NUM_THREADS >= 2  # the two-thread run did use two threads
    assert_same_bits(runs, FIELDS)
    # slicing changes only the summation order: the same numbers to rounding
    monkeypatch.setattr(kernel, "PARALLEL_POINTS", 10**9)
    assert_close(room.objective(lights, visible), runs[0], 1e-12)


def test_no_visible_pair_and_no_light(room: ForwardModel) -> None:
    lights = hard_lights()
    hidden = room.objective(lights, np.zeros((room.point_count, lights.count), dtype=bool))
    assert not np.any(hidden.positions) and not np.any(hidden.colours) and not np.any(hidden.intensities)
    ambient_only = Lights(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), ambient=lights.ambient,
                          surface_values=lights.surface_values)
    none = room.objective(ambient_only, np.zeros((room.point_count, 0), dtype=bool))
    assert none.value == pytest.approx(hidden.value, rel=1e-14)
    np.testing.assert_allclose(none.ambient, hidden.ambient, rtol=1e-14)
    np.testing.assert_allclose(none.surface_values, hidden.surface_values, rtol=1e-14)
    assert none.positions.shape == (0, 3)


def test_a_visibility_of_the_wrong_shape_is_refused(room: ForwardModel) -> None:
    lights = hard_lights()
    with pytest.raises(ValueError, match=rf"shape \({room.point_count}, 2\).*{room.point_count} target points x 3"):
        room.objective(lights, np.ones((room.point_count, 2), dtype=bool))


def test_surface_values_of_the_wrong_count_are_refused(room: ForwardModel) -> None:
    lights = hard_lights()
    lights.surface_values = np.array([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="3 surface light values for the model's 2 surface lights"):
        room.objective(lights, room.visibility(lights))


def test_the_compiled_visibility_casts_the_numpy_rays(room: ForwardModel) -> None:
    lights = hard_lights()
    lights.positions = np.concatenate([lights.positions, [[128.0, 128.0, 170.0], [5.0, 250.0, 0.2]]])
    lights.colours = np.concatenate([lights.colours, np.ones((2, 3))])
    lights.intensities = np.concatenate([lights.intensities, [5.0, 50.0]])  # a short-range light, one on the floor
    rays = room.rays
    compiled = room.visibility(lights)
    compiled_rays = room.rays - rays
    reference = room.visibility_numpy(lights)
    assert np.array_equal(compiled, reference)
    assert room.rays - rays - compiled_rays == compiled_rays  # the same number of rays cast
    assert compiled.any() and not compiled.all()  # shadows, range and backs all take some pairs out
    free = ForwardModel.__new__(ForwardModel)
    free.__dict__.update(room.__dict__, raycaster=None)  # no occluder: every candidate pair is visible
    assert np.array_equal(free.visibility(lights), free.visibility_numpy(lights))
