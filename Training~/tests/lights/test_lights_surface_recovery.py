"""Surface lights as fitted rig elements: the analytic room lit by two point lights and a ceiling panel
(a q3map2 area light, emitters.py) of a known value; the fit recovers the lights and the panel's value."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights.emitters import AreaLights, Emitters, ShaderLight, surface_bases
from lpnn.lights.model import ForwardModel, Lights
from lpnn.lights.optimise import Fitter, initial_grid, initial_intensity
from lpnn.lights.settings import SCHEMES
from synthetic_room import ROOM_SIDE, TRUE_LIGHTS, inside_room, lit_room

BOUNDS = (np.full(3, 1.0), np.full(3, ROOM_SIDE - 1.0))
PANEL_VALUE = 2500.0  # q3map_surfacelight


def panel(value: float) -> Emitters:
    """A 64 x 64 panel just under the ceiling (z = 255), facing down, warm white, shader 7."""
    corners = np.array([[[96.0, 160.0, 255.0], [160.0, 160.0, 255.0], [160.0, 224.0, 255.0], [96.0, 224.0, 255.0]]])
    normal = np.array([[0.0, 0.0, -1.0]])
    colour = np.array([1.0, 0.9, 0.7])
    areas = AreaLights(corners=corners, normals=normal, origins=np.array([[128.0, 192.0, 254.0]]),
                       areas=np.array([64.0 * 64.0]), add=np.array([value * 3 * 0.25]), colours=colour[None],
                       two_sided=np.zeros(1, bool), shader=np.array([7]))
    light = ShaderLight(value=value, colour=colour, subdivide=999.0, backsplash_fraction=0.05,
                        backsplash_distance=23.0, two_sided=False, colour_source="test")
    return Emitters(areas=areas, shaders={7: light}, splash_positions=np.array([[128.0, 192.0, 231.0]]),
                    splash_colours=colour[None], splash_intensities=np.array([value * 4096 * 0.25 * 0.05 / 7500]),
                    splash_shader=np.array([7]))


@pytest.fixture(scope="module")
def room() -> ForwardModel:
    model, raycaster = lit_room(TRUE_LIGHTS)
    shaders, basis = surface_bases(model.points, model.normals, panel(PANEL_VALUE), raycaster)
    assert shaders == [7]
    model.surface_basis = basis
    truth = Lights(TRUE_LIGHTS.positions, TRUE_LIGHTS.colours, TRUE_LIGHTS.intensities, TRUE_LIGHTS.ambient,
                   surface_values=np.array([PANEL_VALUE]))
    model.radiance = model.radiance_of(truth, model.visibility(truth))
    model.norm = float(np.sum(model.weights[:, None] * model.radiance ** 2))
    # the panel is a real part of the target: the true lights without it miss much of it
    dark_panel = Lights(truth.positions, truth.colours, truth.intensities, truth.ambient, surface_values=np.zeros(1))
    assert model.objective(dark_panel, model.visibility(truth)).value > 0.02
    return model


def test_the_basis_is_linear_in_the_value(room: ForwardModel) -> None:
    _, half = surface_bases(room.points, room.normals, panel(PANEL_VALUE / 2), room.raycaster)
    np.testing.assert_allclose(half, room.surface_basis, rtol=1e-9, atol=1e-12)
    # bytes under the panel's centre, 255 units below it (the floor): add x form factor, the form factor of a
    # small facing square A / (pi r^2) within 2 % at this distance, plus the backsplash light 232 units away
    floor = np.flatnonzero((room.points[:, 2] == 0) & (np.linalg.norm(room.points[:, :2] - [128, 192], axis=1) < 1))
    assert floor.size == 1
    expected = PANEL_VALUE * 0.75 * 4096 / (np.pi * 255.0 ** 2) + 7500 * (PANEL_VALUE * 4096 * 0.25 * 0.05 / 7500) \
        / 232.0 ** 2
    assert room.surface_basis[0, floor[0], 0] * PANEL_VALUE == pytest.approx(expected, rel=0.02)


def test_the_fit_recovers_the_panel_value_and_the_lights(room: ForwardModel) -> None:
    start = initial_intensity(room, initial_grid(BOUNDS[0], BOUNDS[1], (2, 2, 2), inside_room))
    assert start.surface_values.shape == (1,)
    result = Fitter(room, BOUNDS, inside_room, room.points).fit(start, SCHEMES["lbfgs"])
    assert result.objective < 1e-3
    assert result.lights.surface_values[0] == pytest.approx(PANEL_VALUE, rel=0.05)
    power = result.lights.intensities * result.lights.colours.max(axis=1)
    for true_position in TRUE_LIGHTS.positions:
        assert np.min(np.linalg.norm(result.lights.positions[power > 0.05 * power.sum()] - true_position, axis=1)) < 8.0
    # the objective reported is that of the rig with its own visibility
    assert result.objective == pytest.approx(room.objective(result.lights, room.visibility(result.lights)).value,
                                             rel=1e-9)


def test_a_fit_with_surface_lights_is_deterministic(room: ForwardModel) -> None:
    from lpnn.lights.settings import ALL, Phase

    phases = (Phase("adam", ALL, 0.1, 8), Phase("lbfgs", ALL, 1.0, 8))
    start = initial_grid(BOUNDS[0], BOUNDS[1], (2, 2, 2), inside_room)
    first, second = (Fitter(room, BOUNDS, inside_room, room.points).fit(initial_intensity(room, start), phases)
                     for _ in range(2))
    assert np.array_equal(first.lights.surface_values, second.lights.surface_values)
    assert np.array_equal(first.lights.positions, second.lights.positions)
    assert [p.objective for p in first.curve] == [p.objective for p in second.curve]
