"""Rig-vs-rig figures and the light grid re-lit from a rig, on hand-computed cases."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights.compare import (GridNodes, SurfacePieces, compare_grid, compare_rigs, equal_flux_intensity,
                                 polygon_distance, relight_grid, shade)
from lpnn.lights.rig import Rig, SurfaceLight
from lpnn.scenes.coords import METRES_PER_UNIT


def rig(quake_positions: list[list[float]], intensities: list[float]) -> Rig:
    positions = np.array(quake_positions, dtype=float).reshape(-1, 3)
    return Rig.from_quake(positions, np.ones_like(positions), np.array(intensities, dtype=float))


def test_rig_comparison_by_hand() -> None:
    metre = 1.0 / METRES_PER_UNIT  # Quake units
    real = rig([[0, 0, 0], [1000, 0, 0]], [300, 100])
    recovered = rig([[0.5 * metre, 0, 0], [1000 + 3 * metre, 0, 0], [5000, 0, 0]], [200, 100, 1])
    c = compare_rigs(recovered, real)
    assert c.matched_share == pytest.approx(0.75)  # the 300 light is matched at 0.5 m; the 100 one is 3 m off
    assert c.real_to_recovered == pytest.approx((300 * 0.5 + 100 * 3) / 400)
    # the third light (1 of 301) is below the 1 % share: it cannot match, but it pays in the reverse distance
    far = np.linalg.norm((5000 - 1000) * METRES_PER_UNIT)
    assert c.recovered_to_real == pytest.approx((200 * 0.5 + 100 * 3 + 1 * far) / 301)
    with pytest.raises(ValueError, match="at least one light"):
        compare_rigs(rig([], []), real)


def test_relit_grid_of_one_light_by_hand() -> None:
    node = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 5000.0]])
    one = rig([[0, 0, 100]], [300])
    one.ambient = np.array([4.0, 5.0, 6.0])
    relit = relight_grid(node, one, raycaster=None)
    value = 7500 * 300 / 100 ** 2  # 225 bytes, straight up
    np.testing.assert_allclose(relit.direction[0], [0, 0, 1])
    np.testing.assert_allclose(relit.directed[0], value)
    # 0.25 (1 - 1) c + 0.125 D, and no rig ambient: q3map2 sets its grid up before it reads worldspawn's _ambient
    np.testing.assert_allclose(relit.ambient[0], 0.125 * value)
    np.testing.assert_allclose(relit.directed[1], 0.0)  # 4900 units away: 0.094 byte, dropped by q3map2
    np.testing.assert_allclose(relit.ambient[1], 0.0)
    bright = relight_grid(node[:1], rig([[0, 0, 20]], [300]), raycaster=None)
    np.testing.assert_allclose(bright.directed[0], 255.0)  # 5625 bytes clamped, hue kept


def test_grid_comparison_is_zero_for_the_same_grid_and_scales() -> None:
    stored = GridNodes(positions=np.zeros((2, 3)), ambient=np.array([[10.0, 20, 30], [5, 5, 5]]),
                       directed=np.array([[50.0, 50, 50], [0, 0, 0]]), direction=np.array([[0, 0, 1.0], [1, 0, 0]]))
    same = compare_grid(stored, stored)
    assert same.mean_error == 0.0 and same.plain_relative == 0.0
    half = GridNodes(stored.positions, stored.ambient / 2, stored.directed / 2, stored.direction)
    assert compare_grid(stored, half).plain_relative == pytest.approx(0.5)
    assert shade(stored)[0, 4 * 3 + 2] == pytest.approx(30 + 50)  # +z is D14 direction 4; blue


def square_piece(shader: str, centre_m: list[float], side_m: float, power: float) -> SurfacePieces:
    """A horizontal square (Unity y up) of the given side, in Unity metres, facing up."""
    c = np.array(centre_m, dtype=float)
    h = side_m / 2
    corners = np.array([[c + [-h, 0, -h], c + [h, 0, -h], c + [h, 0, h], c + [-h, 0, h]]])
    return SurfacePieces(shader=[shader], corners=corners, normals=np.array([[0.0, 1.0, 0.0]]),
                         power=np.array([power]))


def test_polygon_distance_by_hand() -> None:
    piece = square_piece("s", [0, 0, 0], 2.0, 1.0)
    points = np.array([[0.3, 0.5, -0.2], [2.0, 0.0, 0.0], [2.0, 1.0, 2.0], [0.0, -0.25, 1.0]])
    got = polygon_distance(points, piece.corners, piece.normals)[:, 0]
    np.testing.assert_allclose(got, [0.5, 1.0, np.sqrt(1 + 1 + 1), 0.25])  # above, beside, off a corner, on an edge


def test_surface_lights_are_matched_on_their_shader_or_by_a_light_within_1_m() -> None:
    metre = 1.0 / METRES_PER_UNIT
    real = rig([[0, 0, 0]], [100])  # a point light at the origin (Unity origin too)
    pieces = SurfacePieces(shader=["lamp", "panel"],
                           corners=np.concatenate([square_piece("lamp", [10, 3, 0], 2, 0).corners,
                                                   square_piece("panel", [-20, 3, 0], 2, 0).corners]),
                           normals=np.array([[0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]), power=np.array([200.0, 100.0]))
    # recovered: the point light, a light 0.8 m above the lamp (Unity (10, 3.8, 0) is Quake (0, -10, 3.8) m)
    recovered = rig([[0, 0, 0], [0, -10 * metre, 3.8 * metre]], [100, 50])
    c = compare_rigs(recovered, real, real_surfaces=pieces, shader_power={"panel": 0.05, "lamp": 0.05})
    assert c.matched_share == pytest.approx((100 + 200) / 400)  # the panel has nothing within 1 m
    assert c.surface_share == pytest.approx(300 / 400) and c.surface_matched_share == pytest.approx(200 / 400)
    # a recovered surface light of the panel's shader lies on it: matched when it carries >= 1 % of the power
    recovered.surfaces = [SurfaceLight("panel", 1000.0, np.ones(3))]  # 1000 x 0.05 = 50 of 200
    c = compare_rigs(recovered, real, real_surfaces=pieces, shader_power={"panel": 0.05})
    assert c.matched_share == pytest.approx(1.0) and c.recovered_power == pytest.approx(200.0)
    recovered.surfaces = [SurfaceLight("panel", 10.0, np.ones(3))]  # 0.5 of 150.5: below 1 %
    assert compare_rigs(recovered, real, real_surfaces=pieces, shader_power={"panel": 0.05}).matched_share \
        == pytest.approx(0.75)
    with pytest.raises(ValueError, match=r"\['nowhere'\] have no emitting surface"):
        recovered.surfaces = [SurfaceLight("nowhere", 10.0, np.ones(3))]
        compare_rigs(recovered, real, real_surfaces=pieces, shader_power={"panel": 0.05})


def test_equal_flux_intensity_of_an_area_light() -> None:
    # an area light's flux add x A into its hemisphere equals a point light's 7500 I 4 pi into the sphere
    assert equal_flux_intensity(750.0, 4096.0) == pytest.approx(750 * 4096 / (4 * np.pi * 7500))
