"""The inverse problem end to end on the analytic room: known lights -> target -> fitted rig."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights.model import ForwardModel
from lpnn.lights.optimise import Fitter, initial_grid, initial_intensity
from lpnn.lights.pipeline import held_ambient
from lpnn.lights.settings import ALL, SCHEMES, Phase
from lpnn.scenes.bsp import read_bsp
from lpnn.scenes.levels import Level
from synthetic_bsp import make_level
from synthetic_room import ROOM_SIDE, TRUE_LIGHTS, inside_room, lit_room

BOUNDS = (np.full(3, 1.0), np.full(3, ROOM_SIDE - 1.0))
GRID = (2, 2, 2)


@pytest.fixture(scope="module")
def room() -> ForwardModel:
    return lit_room(TRUE_LIGHTS)[0]


def fit(room: ForwardModel, phases: tuple[Phase, ...]):
    start = initial_grid(BOUNDS[0], BOUNDS[1], GRID, inside_room)
    return Fitter(room, BOUNDS, inside_room, room.points).fit(initial_intensity(room, start), phases)


def test_initial_grid_is_in_open_space_only() -> None:
    grid = initial_grid(BOUNDS[0], BOUNDS[1], (5, 5, 5), inside_room)
    assert len(grid) == 125 - 3  # the centre column (x = y = 128) at z = 26, 77 and 128 is in the pillar
    assert inside_room(grid).all()


def test_lbfgs_recovers_the_lights(room: ForwardModel) -> None:
    result = fit(room, SCHEMES["lbfgs"])
    power = result.lights.intensities * result.lights.colours.max(axis=1)
    strongest = np.argsort(-power)[:2]
    for true_position, true_colour, true_intensity in zip(TRUE_LIGHTS.positions, TRUE_LIGHTS.colours,
                                                          TRUE_LIGHTS.intensities):
        match = strongest[np.argmin(np.linalg.norm(result.lights.positions[strongest] - true_position, axis=1))]
        assert np.linalg.norm(result.lights.positions[match] - true_position) < 2.0  # Quake units (5 cm)
        emitted = result.lights.colours[match] * result.lights.intensities[match]
        np.testing.assert_allclose(emitted, true_colour * true_intensity, rtol=0.02)
    assert power.sum() - power[strongest].sum() < 0.01 * power.sum()  # the spare lights went dark
    np.testing.assert_allclose(result.lights.ambient, TRUE_LIGHTS.ambient, atol=0.2)  # bytes
    assert result.objective < 1e-4
    assert inside_room(result.lights.positions).all()
    objectives = [point.objective for point in result.curve]
    assert objectives[-1] < 1e-3 * objectives[0]


def test_the_fit_is_deterministic(room: ForwardModel) -> None:
    phases = (Phase("adam", ALL, 0.1, 12), Phase("lbfgs", ALL, 1.0, 12))
    first, second = fit(room, phases), fit(room, phases)
    np.testing.assert_array_equal(first.lights.positions, second.lights.positions)
    np.testing.assert_array_equal(first.lights.intensities, second.lights.intensities)
    assert [p.objective for p in first.curve] == [p.objective for p in second.curve]


def test_a_fit_holding_the_ambient_keeps_it_to_the_bit_and_still_recovers_the_lights(room: ForwardModel) -> None:
    """Fitter(fit_ambient=False) with initial_intensity's held ambient (pipeline.held_ambient: the worldspawn's): the
    start fits the lights' scale to what the ambient leaves of the target, and no phase moves the ambient."""
    held = TRUE_LIGHTS.ambient.copy()
    start = initial_intensity(room, initial_grid(BOUNDS[0], BOUNDS[1], GRID, inside_room), ambient=held)
    np.testing.assert_array_equal(start.ambient, held)
    result = Fitter(room, BOUNDS, inside_room, room.points, fit_ambient=False).fit(start, SCHEMES["mixed"])
    np.testing.assert_array_equal(result.lights.ambient, held)
    assert result.objective < 1e-4
    fitted = Fitter(room, BOUNDS, inside_room, room.points).fit(
        initial_intensity(room, initial_grid(BOUNDS[0], BOUNDS[1], GRID, inside_room), ambient=held + 3.0),
        SCHEMES["quick"])
    assert not np.array_equal(fitted.lights.ambient, held + 3.0)  # a fitted ambient moves from a wrong start


def held_ambient_of(worldspawn: str, ambient: str = "worldspawn"):
    level = make_level()
    level.entities = "{\n\"classname\" \"worldspawn\"\n" + worldspawn + "}\n"
    data = level.to_bytes()
    return held_ambient(Level(name="w", location="w.bsp", pak=None, data=data, bsp=read_bsp(data, "w.bsp")), ambient)


def test_the_held_ambient_is_the_worldspawns_as_q3map2_reads_it() -> None:
    np.testing.assert_array_equal(held_ambient_of('"ambient" "35"\n"_color" "1 0.5 0"\n'), [35.0, 17.5, 0.0])
    np.testing.assert_array_equal(held_ambient_of('"_ambient" "10"\n'), [10.0, 10.0, 10.0])
    assert held_ambient_of("") is None  # none recorded (q3map2's 0): fitted, by the training levels
    assert held_ambient_of('"_ambient" "0"\n') is None
    assert held_ambient_of('"_minlight" "25"\n') is None  # a floor the model lacks: the ambient is fitted
    assert held_ambient_of('"ambient" "35"\n', "fitted") is None
    with pytest.raises(ValueError, match="ambient 'guess' is not one of worldspawn, fitted"):
        held_ambient_of("", "guess")
