"""Fitted spotlights (lights.md §4): the cone in the compiled objective against the numpy formula, finite
differences and the fixed emitters' spotlights; the same bits on 1 and 2 threads; a fit that recovers a spotlight."""

from __future__ import annotations

import numpy as np
import pytest

import lpnn.lights.objective_kernel as kernel
from lpnn.lights.compare import relight_grid
from lpnn.lights.emitters import Emitters, Spots, emitter_bytes
from lpnn.lights.model import ForwardModel, Lights, spot_factors
from lpnn.lights.optimise import Fitter, initial_intensity
from lpnn.lights.rig import Rig, read_rig, write_rig
from lpnn.lights.settings import SCHEMES
from lpnn.scenes.coords import quake_to_unity
from gradient_checks import assert_close, assert_same_bits, finite_difference, objectives_on_threads
from synthetic_room import ROOM_SIDE, lit_room

FIELDS = ("positions", "colours", "intensities", "ambient", "spot_directions", "radius_by_dist")


def spot_lights() -> Lights:
    """Two spotlights (one tilted, one straight down with a narrow cone) and one point light (cone 0)."""
    axes = np.array([[0.3, -0.2, -1.0], [0.0, 0.0, -1.0], [0.0, 0.0, 0.0]])
    axes[:2] /= np.linalg.norm(axes[:2], axis=1, keepdims=True)
    return Lights(positions=np.array([[80.0, 150.0, 230.0], [190.0, 70.0, 200.0], [128.0, 40.0, 60.0]]),
                  colours=np.array([[1.0, 0.8, 0.6], [0.5, 0.7, 1.0], [0.3, 1.0, 0.2]]),
                  intensities=np.array([900.0, 1400.0, 120.0]), ambient=np.array([11.0, 9.0, 7.0]),
                  spot_directions=axes, radius_by_dist=np.array([0.7, 0.35, 0.0]))


@pytest.fixture(scope="module")
def room() -> ForwardModel:
    return lit_room(spot_lights(), divisions=12)[0]


def off_lights() -> Lights:
    """spot_lights moved, turned and widened: a fit's starting point, with gradient in every parameter."""
    lights = spot_lights()
    lights.positions = lights.positions + np.array([[6.0, -5.0, -4.0], [-7.0, 4.0, 3.0], [5.0, 5.0, 5.0]])
    axes = lights.spot_directions + np.array([[0.1, 0.05, 0.0], [-0.08, 0.1, 0.0], [0.0, 0.0, 0.0]])
    axes[:2] /= np.linalg.norm(axes[:2], axis=1, keepdims=True)
    lights.spot_directions = axes
    lights.radius_by_dist = np.array([0.6, 0.45, 0.0])
    lights.intensities = np.array([700.0, 1600.0, 150.0])
    return lights


def test_the_cone_is_the_emitters_spotlight(room: ForwardModel) -> None:
    """A fitted spotlight lights the surfaces exactly as the fixed emitters' spotlight of a compile (emitters.py,
    q3map2's LightContributionToSample), and a cone of 0 is a point light."""
    lights = spot_lights()
    visible = room.visibility(lights)
    fitted = room.radiance_of(lights, visible) / room.albedo / (4 / 255)
    spot = lights.radius_by_dist > 0
    emitters = Emitters(spots=Spots(lights.positions[spot], lights.colours[spot], lights.intensities[spot],
                                    lights.spot_directions[spot], lights.radius_by_dist[spot]))
    point = Lights(lights.positions[~spot], lights.colours[~spot], lights.intensities[~spot], ambient=lights.ambient)
    room.fixed = emitter_bytes(room.points, room.normals, emitters, room.raycaster)
    try:
        fixed = room.radiance_of(point, room.visibility(point)) / room.albedo / (4 / 255)
    finally:
        room.fixed = np.zeros_like(room.points)
    np.testing.assert_allclose(fitted, fixed, rtol=1e-9, atol=1e-9)
    factor = spot_factors(room.points - lights.positions[0], np.tile(lights.spot_directions[0], (room.point_count, 1)),
                          np.full(room.point_count, lights.radius_by_dist[0]))
    assert np.count_nonzero(factor == 0) > 100 and np.count_nonzero(factor == 1) > 50  # outside and inside the cone
    assert np.count_nonzero((factor > 0) & (factor < 1)) > 20  # the 32-unit soft edge
    as_points = Lights(lights.positions, lights.colours, lights.intensities, ambient=lights.ambient,
                       spot_directions=lights.spot_directions, radius_by_dist=np.zeros(3))
    plain = Lights(lights.positions, lights.colours, lights.intensities, ambient=lights.ambient)
    np.testing.assert_array_equal(room.radiance_of(as_points, visible), room.radiance_of(plain, visible))
    assert not np.allclose(fitted, room.radiance_of(plain, visible) / room.albedo / (4 / 255))


def test_compiled_pass_matches_the_numpy_formula_with_spots(room: ForwardModel) -> None:
    lights = off_lights()
    visible = room.visibility(lights)
    compiled, reference = room.objective(lights, visible), room.objective_numpy(lights, visible)
    assert compiled.value > 0.01
    assert_close(compiled, reference, 1e-12, FIELDS)
    assert not np.any(compiled.spot_directions[2]) and compiled.radius_by_dist[2] == 0  # the point light


def test_spot_gradients_match_finite_differences(room: ForwardModel) -> None:
    lights = off_lights()
    visible = room.visibility(lights)
    analytic = room.objective(lights, visible)

    def point_lights_cone(name: str, index: tuple[int, ...]) -> bool:
        # a point light: a cone would make it a spotlight (a jump, not a derivative)
        return name in ("spot_directions", "radius_by_dist") and lights.radius_by_dist[index[0]] == 0

    steps = {"positions": 1e-4, "spot_directions": 1e-6, "radius_by_dist": 1e-6, "intensities": 1e-3}
    for name, numeric in finite_difference(room, lights, visible, steps, skip=point_lights_cone).items():
        scale = np.max(np.abs(numeric))
        assert scale > 0, name
        assert np.max(np.abs(getattr(analytic, name) - numeric)) <= 1e-5 * scale, name
    # and the check can fail: the cone's gradient of the first spotlight off by 1 % is caught
    assert abs(analytic.radius_by_dist[0] * 0.01) > 1e-5 * np.max(np.abs(analytic.radius_by_dist))


def test_the_same_bits_on_one_and_two_threads_with_spots(room: ForwardModel, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(kernel, "PARALLEL_POINTS", 100)
    assert kernel.chunks_for(room.point_count) >= 8
    lights = off_lights()
    visible = room.visibility(lights)
    assert_same_bits(objectives_on_threads(room, lights, visible), FIELDS)


def test_cones_of_the_wrong_count_are_refused(room: ForwardModel) -> None:
    lights = off_lights()
    lights.radius_by_dist = np.array([0.5, 0.5])
    with pytest.raises(ValueError, match="2 spot cones and 3 axes for 3 lights"):
        room.objective(lights, np.ones((room.point_count, 3), dtype=bool))


def fit_spots(model: ForwardModel, start: np.ndarray) -> Lights:
    def is_open(points: np.ndarray) -> np.ndarray:
        return np.all((points > 0) & (points < ROOM_SIDE), axis=1)

    lights = initial_intensity(model, start, spots=np.ones(len(start), bool))
    assert np.all(lights.radius_by_dist > 0) and np.allclose(lights.spot_directions, [0.0, 0.0, -1.0])
    fitter = Fitter(model, (np.full(3, 1.0), np.full(3, ROOM_SIDE - 1.0)), is_open, model.points, refresh=10)
    return fitter.fit(lights, SCHEMES["mixed"]).lights


def test_a_fit_recovers_a_spotlight_and_writes_it_as_a_spot(tmp_path) -> None:
    """One tilted spotlight lights the room: a spotlight fit started 30 units off, pointing down with a wide cone,
    finds its axis and cone (a point-light fit cannot), deterministically; the rig holds it as a spot and re-lights
    a grid with its cone."""
    axis = np.array([0.35, 0.2, -1.0]) / np.linalg.norm([0.35, 0.2, -1.0])
    truth = Lights(positions=np.array([[100.0, 110.0, 220.0]]), colours=np.array([[1.0, 0.9, 0.7]]),
                   intensities=np.array([1200.0]), ambient=np.array([6.0, 6.0, 6.0]),
                   spot_directions=axis[None], radius_by_dist=np.array([0.5]))
    model = lit_room(truth, divisions=10, pillar=False)[0]
    start = np.array([[120.0, 90.0, 200.0]])
    found = fit_spots(model, start)
    again = fit_spots(model, start)
    np.testing.assert_array_equal(found.positions, again.positions)
    np.testing.assert_array_equal(found.spot_directions, again.spot_directions)
    visible = model.visibility(found)
    assert model.objective(found, visible).value < 0.01
    assert float(found.spot_directions[0] @ axis) > np.cos(np.radians(5.0))
    assert found.radius_by_dist[0] == pytest.approx(0.5, abs=0.1)
    assert np.linalg.norm(found.positions[0] - truth.positions[0]) < 25.0
    point = initial_intensity(model, start)
    fitter = Fitter(model, (np.full(3, 1.0), np.full(3, ROOM_SIDE - 1.0)),
                    lambda p: np.all((p > 0) & (p < ROOM_SIDE), axis=1), model.points, refresh=10)
    as_point = fitter.fit(point, SCHEMES["mixed"])
    assert as_point.objective > 5 * model.objective(found, visible).value
    rig = Rig.from_quake(found.positions, found.colours, found.intensities, ambient=found.ambient,
                         spot_directions=quake_to_unity(found.spot_directions, scale=1.0),
                         radius_by_dist=found.radius_by_dist)
    back = read_rig(write_rig(tmp_path / "spot.json", rig))
    assert back.spot.tolist() == [True]
    nodes = np.array([[100.0, 110.0, 30.0], [100.0 + 0.35 * 190, 110.0 + 0.2 * 190, 30.0], [240.0, 20.0, 30.0]])
    relit = relight_grid(nodes, back, None)
    lit = relit.directed.max(axis=1) + relit.ambient.max(axis=1)  # the grid holds no rig ambient (compare.py)
    assert lit[1] > 10 * max(lit[2], 1e-9)  # on the axis, not outside the cone


def test_point_lights_stay_point_lights_beside_spotlights() -> None:
    """fit_scene(spots=True) starts a point light and a spotlight at every cell centre: the point lights' cones stay
    0 (they are never turned into spotlights), the spotlights' stay within the fit's bounds."""
    model = lit_room(spot_lights(), divisions=8, pillar=False)[0]
    start = np.array([[100.0, 120.0, 180.0], [100.0, 120.0, 180.0]])
    lights = initial_intensity(model, start, spots=np.array([False, True]))
    assert lights.radius_by_dist.tolist() == [0.0, 1.0]
    fitter = Fitter(model, (np.full(3, 1.0), np.full(3, ROOM_SIDE - 1.0)),
                    lambda p: np.all((p > 0) & (p < ROOM_SIDE), axis=1), model.points, refresh=5)
    found = fitter.fit(lights, SCHEMES["quick"]).lights
    assert found.radius_by_dist[0] == 0.0 and not np.any(found.spot_directions[0])
    assert 0.05 <= found.radius_by_dist[1] <= 4.0
    assert np.linalg.norm(found.spot_directions[1]) == pytest.approx(1.0)
    assert not np.array_equal(found.positions[0], found.positions[1])  # the two moved apart
    with pytest.raises(ValueError, match="1 spotlight flags for 2 lights"):
        initial_intensity(model, start, spots=np.array([True]))
