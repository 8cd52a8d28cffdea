"""Spotlights, surface (area) lights and the grid's sampling rules (lpnn.lights.emitters, compare):
closed-form cases from q3map2's formulas (Documentation~/lights.md §3)."""

from __future__ import annotations

import math
import zipfile

import numpy as np
import pytest

from lpnn.lights.compare import grid_sample_points
from lpnn.lights.emitters import (AREA_SCALE, FORM_FACTOR_VALUE_SCALE, AreaLights, Emitters, Spots, emitter_bytes,
                                  form_factor, read_shader_scripts, shader_light, spot_factor, subdivide_winding)
from lpnn.lights.model import POINT_SCALE
from lpnn.lights.rig import entity_lights


def square(side: float, height: float) -> np.ndarray:
    h = side / 2
    return np.array([[-h, -h, height], [h, -h, height], [h, h, height], [-h, h, height]], dtype=float)


def test_small_square_emitter_tends_to_the_point_light_limit() -> None:
    # a small patch of area A at distance h, facing the point: projected solid angle A / h^2; q3map2's
    # form factor is the projected solid angle over pi (Lambert's edge sum over 2 pi), A / (pi h^2)
    for side, height in ((2.0, 200.0), (1.0, 50.0)):
        factor = form_factor(np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]), square(side, height)[None])[0]
        assert factor == pytest.approx(side * side / (math.pi * height * height), rel=1e-3)


def test_large_square_emitter_covers_half_the_hemisphere_form_factor() -> None:
    factor = form_factor(np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]), square(1e5, 1.0)[None])[0]
    assert factor == pytest.approx(1.0, abs=1e-3)  # the whole hemisphere: pi / pi
    facing_away = form_factor(np.zeros((1, 3)), np.array([[0.0, 0.0, -1.0]]), square(2.0, 100.0)[None])[0]
    assert facing_away < 0  # one-sided lights ignore it


def area_light(side: float, height: float, value: float, two_sided: bool = False) -> AreaLights:
    corners = square(side, height)  # wound as a BSP face facing down: positive form factor below it
    return AreaLights(corners=corners[None], normals=np.array([[0.0, 0.0, -1.0]]),
                      origins=np.array([[0.0, 0.0, height - 1.0]]), areas=np.array([side * side]),
                      add=np.array([value * FORM_FACTOR_VALUE_SCALE * AREA_SCALE]), colours=np.array([[1.0, 0.5, 0.0]]),
                      two_sided=np.array([two_sided]), shader=np.array([0]))


def test_area_light_bytes_at_a_receiver_below_it() -> None:
    light = area_light(4.0, 100.0, 1000.0)
    got = emitter_bytes(np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]), Emitters(areas=light), None)[0]
    expected = 1000.0 * 3 * 0.25 * 16.0 / (math.pi * 100.0 ** 2)
    np.testing.assert_allclose(got, [expected, 0.5 * expected, 0.0], rtol=1e-3)
    # behind the light's plane: nothing (one-sided); a two-sided light lights it
    above = np.array([[0.0, 0.0, 200.0]])
    assert emitter_bytes(above, np.array([[0.0, 0.0, -1.0]]), Emitters(areas=light), None).max() == 0.0
    two = emitter_bytes(above, np.array([[0.0, 0.0, -1.0]]), Emitters(areas=area_light(4.0, 100.0, 1000.0, True)), None)
    assert two[0, 0] == pytest.approx(expected, rel=2e-2)


def test_spotlight_cone_and_its_soft_edge() -> None:
    # light at the origin pointing down -z, radius 64 at 64 units: radiusByDist = 80 / 64
    spots = dict(positions=np.zeros((1, 3)), directions=np.array([[0.0, 0.0, -1.0]]), radius_by_dist=np.array([1.25]))
    points = np.array([[0, 0, -100], [0, 0, 100], [0, 124, -100], [0, 130, -100], [0, 110.5, -100]], float)
    factor = spot_factor(points, **spots)[:, 0]
    np.testing.assert_allclose(factor, [1.0, 0.0, 1.0 / 32, 0.0, 14.5 / 32])
    # on the axis the spotlight is q3map2's point light
    spot = Spots(colours=np.ones((1, 3)), intensities=np.array([300.0]), **spots)
    got = emitter_bytes(np.array([[0.0, 0.0, -100.0]]), np.array([[0.0, 0.0, 1.0]]), Emitters(spots=spot), None)
    np.testing.assert_allclose(got[0], POINT_SCALE * 300.0 / 100.0 ** 2)


def test_light_entity_with_a_target_is_a_spotlight() -> None:
    entities = [{"classname": "worldspawn"},
                {"classname": "light", "origin": "0 0 100", "light": "200", "target": "t1", "radius": "48"},
                {"classname": "info_null", "targetname": "t1", "origin": "0 0 20"},
                {"classname": "light", "origin": "0 0 50", "light": "100", "target": "missing"}]
    real = entity_lights(entities, "test")
    assert real.spot.tolist() == [True, False]
    np.testing.assert_allclose(real.spot_direction[0], [0.0, 0.0, -1.0])
    assert real.radius_by_dist[0] == pytest.approx((48 + 16) / 80)


def test_shader_script_surface_light(tmp_path) -> None:
    script = """// comment
textures/test/lamp
{
    qer_editorimage textures/test/lamp_ed.tga
    q3map_surfacelight 2500
    q3map_lightRGB 1 0.5 0.25
    q3map_lightSubdivide 64
    surfaceparm nomarks
    { map $lightmap }
}
textures/test/plain
{
    { map textures/test/plain.tga }
}
"""
    pak = tmp_path / "a.pk3"
    with zipfile.ZipFile(pak, "w") as archive:
        archive.writestr("scripts/test.shader", script)
    scripts = read_shader_scripts([pak])
    light = shader_light(scripts, "textures/test/lamp", lambda path: None)
    assert light is not None and light.value == 2500 and light.subdivide == 64
    np.testing.assert_allclose(light.colour, [1.0, 0.5, 0.25])
    assert shader_light(scripts, "textures/test/plain", lambda path: None) is None
    assert shader_light(scripts, "textures/none", lambda path: None) is None


def test_subdivided_winding_keeps_area_and_respects_the_size() -> None:
    triangle = [np.array([0.0, 0.0, 0.0]), np.array([300.0, 0.0, 0.0]), np.array([0.0, 200.0, 0.0])]
    pieces = subdivide_winding(triangle, 64.0)
    total = 0.0
    for piece in pieces:
        p = np.array(piece)
        assert np.all(p.max(axis=0) - p.min(axis=0) <= 64.0 + 1e-9)
        total += 0.5 * sum(np.linalg.norm(np.cross(p[i - 1] - p[0], p[i] - p[0])) for i in range(2, len(p)))
    assert total == pytest.approx(0.5 * 300 * 200)


def test_grid_nodes_in_solid_are_nudged_as_trace_grid_does() -> None:
    def is_open(points: np.ndarray) -> np.ndarray:  # open only where x > 5 and y > 5 and z < 0
        return (points[:, 0] > 5) & (points[:, 1] > 5) & (points[:, 2] < 0)

    nodes = np.array([[0.0, 0.0, 0.0], [10.0, 10.0, -10.0], [-100.0, 0.0, 0.0]])
    got = grid_sample_points(nodes, is_open)
    np.testing.assert_allclose(got[0], [9.0, 9.0, -9.0])  # i = 3: +x, +y, -z at step 9
    np.testing.assert_allclose(got[1], nodes[1])  # already open
    np.testing.assert_allclose(got[2], nodes[2])  # nothing open within 18 units: unchanged
