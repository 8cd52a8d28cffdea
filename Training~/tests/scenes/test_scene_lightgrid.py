"""Light grid sampling against hand-computed R_SetupEntityLightingGrid values, and its SH."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.sh import evaluate
from lpnn.scenes.bsp import LightGridLayout, read_bsp
from lpnn.scenes.coords import quake_to_unity
from lpnn.scenes.errors import BspError
from lpnn.scenes.lightgrid import LINEAR_PER_BYTE, LightGrid, decode_directions
from synthetic_bsp import make_level

UP, PLUS_X = (0, 0), (64, 0)  # (theta byte, phi byte)


def grid_of(cells: dict[tuple[int, int, int], tuple], dims=(3, 2, 2)) -> LightGrid:
    """Cells (x, y, z) -> (ambient, directed, (theta, phi)); every other cell is all-zero ("in a wall")."""
    layout = LightGridLayout(origin=np.zeros(3), cell_size=np.array([64.0, 64.0, 128.0]), dims=np.array(dims))
    records = np.zeros((layout.point_count, 8), dtype=np.uint8)
    for (x, y, z), (ambient, directed, angles) in cells.items():
        records[x + dims[0] * (y + dims[1] * z)] = [*ambient, *directed, *angles]
    return LightGrid(layout, records)


CELL0 = ((100, 50, 25), (40, 40, 40), UP)
CELL1 = ((200, 100, 50), (80, 80, 80), PLUS_X)


def sample_x(grid: LightGrid, x: float):
    return grid.sample(np.array([[x, 0.0, 0.0]]))


def test_decoded_directions() -> None:
    theta = np.array([0, 64, 64, 128, 64])
    phi = np.array([0, 0, 64, 0, 128])
    expected = [[0, 0, 1], [1, 0, 0], [0, 1, 0], [0, 0, -1], [-1, 0, 0]]
    assert np.allclose(decode_directions(theta, phi), expected, atol=1e-12)


def test_sampling_on_a_cell_returns_its_bytes() -> None:
    light = sample_x(grid_of({(0, 0, 0): CELL0, (1, 0, 0): CELL1}), 64.0)
    assert light.ambient.tolist() == [[200, 100, 50]] and light.directed.tolist() == [[80, 80, 80]]
    assert np.allclose(light.direction, [[1, 0, 0]])


def test_trilinear_between_two_cells() -> None:
    light = sample_x(grid_of({(0, 0, 0): CELL0, (1, 0, 0): CELL1}), 16.0)  # a quarter of the way
    assert np.allclose(light.ambient, [[125, 62.5, 31.25]])  # 0.75*cell0 + 0.25*cell1
    assert np.allclose(light.directed, [[50, 50, 50]])
    assert np.allclose(light.direction, [np.array([0.25, 0, 0.75]) / np.sqrt(0.625)])  # w-weighted, normalised
    assert np.allclose(light.weight, [1.0])


def test_cells_in_walls_are_skipped_and_the_rest_renormalised() -> None:
    in_wall = ((0, 0, 0), (255, 255, 255), PLUS_X)  # ambient sum 0: ignored even with directed light
    light = sample_x(grid_of({(0, 0, 0): CELL0, (1, 0, 0): in_wall}), 16.0)
    assert np.allclose(light.weight, [0.75])
    assert np.allclose(light.ambient, [[100, 50, 25]]) and np.allclose(light.directed, [[40, 40, 40]])
    assert np.allclose(light.direction, [[0, 0, 1]])


def test_no_renormalisation_from_0_99() -> None:
    in_wall = ((0, 0, 0), (0, 0, 0), UP)
    light = sample_x(grid_of({(0, 0, 0): CELL0, (1, 0, 0): in_wall}), 0.005 * 64)  # W = 0.995
    assert np.allclose(light.ambient, [[99.5, 49.75, 24.875]])


def test_below_the_grid_the_base_cell_is_clamped_but_the_fraction_is_not() -> None:
    # x = -16: v = -0.25, floor -1, frac 0.75; base clamped to 0 -> 0.25*cell0 + 0.75*cell1
    light = sample_x(grid_of({(0, 0, 0): CELL0, (1, 0, 0): CELL1}), -16.0)
    assert np.allclose(light.ambient, [[175, 87.5, 43.75]])


def test_corners_beyond_the_last_cell_are_skipped() -> None:
    last = ((30, 60, 90), (10, 20, 30), UP)
    light = sample_x(grid_of({(1, 0, 0): CELL1, (2, 0, 0): last}), 2.5 * 64)  # W = 0.5 -> renormalised
    assert np.allclose(light.ambient, [[30, 60, 90]]) and np.allclose(light.weight, [0.5])


def test_positions_a_rounding_error_off_a_node_sit_on_it() -> None:
    in_wall = ((0, 0, 0), (0, 0, 0), UP)
    grid = grid_of({(0, 0, 0): CELL0, (1, 0, 0): in_wall})
    # on the in-wall node, by float32 rounding just below it: unlit, as exactly on it
    assert sample_x(grid, 64.0 - 1e-4).weight.tolist() == [0.0] == sample_x(grid, 64.0).weight.tolist()
    # a real offset keeps the renormalised value of the valid corner
    light = sample_x(grid, 64.0 - 0.5)
    assert np.allclose(light.weight, [0.5 / 64]) and np.allclose(light.ambient, [[100, 50, 25]])


def test_points_with_no_valid_corner_are_black() -> None:
    grid = grid_of({(2, 1, 1): CELL0})
    far = np.array([[0.0, 0.0, 0.0]])
    assert grid.sample(far).weight.tolist() == [0.0]
    sh, lit = grid.sh_at(quake_to_unity(far))
    assert np.all(sh == 0.0) and lit.tolist() == [False]


def test_sampling_is_vectorised_and_matches_one_by_one() -> None:
    rng = np.random.default_rng(7)
    cells = {(x, y, z): (tuple(rng.integers(0, 256, 3)), tuple(rng.integers(0, 256, 3)), tuple(rng.integers(0, 256, 2)))
             for x in range(3) for y in range(2) for z in range(2) if rng.random() > 0.2}
    grid = grid_of(cells)
    points = rng.uniform(-50, 250, size=(64, 3))
    together = grid.sample(points)
    for i in range(0, 64, 9):
        alone = grid.sample(points[i:i + 1])
        assert np.allclose(alone.ambient, together.ambient[i]) and np.allclose(alone.direction, together.direction[i])


def test_sh_reproduces_ambient_plus_directed_fit() -> None:
    # a = 4A/255, d = 4D/255; light straight up in Quake = +Y in Unity
    grid = grid_of({(1, 1, 1): ((51, 102, 153), (255, 0, 51), UP)})
    a = np.array([0.8, 1.6, 2.4])
    d = np.array([4.0, 0.0, 0.8])
    assert np.allclose(LINEAR_PER_BYTE * np.array([51, 102, 153]), a)
    sh, lit = grid.sh_at(quake_to_unity(np.array([[64.0, 64.0, 128.0]])))
    assert lit.tolist() == [True]
    values = evaluate(sh, np.array([[0, 1, 0], [0, -1, 0], [1, 0, 0]], dtype=float))[0]
    assert np.allclose(values[0], a + d * (3 / 32 + 1 / 2 + 15 / 32))  # toward the light
    assert np.allclose(values[1], a + d * (3 / 32 - 1 / 2 + 15 / 32))  # away from it
    assert np.allclose(values[2], a + d * 3 / 32)  # at the terminator


def test_the_synthetic_level_grid() -> None:
    grid = LightGrid.from_bsp(read_bsp(make_level().to_bytes(), "synthetic.bsp"))
    # cell (x, y, z) of make_grid_bytes: ambient (10+10x, 20+5y, 30+3z); between z=0 and z=1 halfway
    light = grid.sample(np.array([[128.0, 192.0, 64.0]]))
    assert np.allclose(light.ambient, [[30, 35, 31.5]])
    assert np.allclose(light.direction, [[0, 0, 1]])


def test_a_level_without_grid_cannot_be_sampled() -> None:
    level = make_level()
    level.light_grid = b""
    with pytest.raises(BspError, match="compiled without light"):
        LightGrid.from_bsp(read_bsp(level.to_bytes(), "synthetic.bsp"))
