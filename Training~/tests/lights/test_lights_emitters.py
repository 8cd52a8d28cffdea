"""Spotlights, surface (area) lights and the grid's sampling rules (lpnn.lights.emitters, compare):
closed-form cases from q3map2's formulas (Documentation~/lights.md §3)."""

from __future__ import annotations

import math
import zipfile
from pathlib import Path

import numpy as np
import pytest

from lpnn.lights.compare import grid_sample_points
from lpnn.lights.emitters import (AREA_SCALE, FORM_FACTOR_VALUE_SCALE, AreaLights, Emitters, ShaderLight, Spots, Suns,
                                  emitter_bytes, emitters_at_points, form_factor, read_shader_scripts,
                                  script_declares_sky, script_order, shader_light, shader_suns, spot_factor,
                                  subdivide_winding)
from lpnn.lights.model import POINT_SCALE
from lpnn.lights.pipeline import rig_emitters, shader_emitters, surface_light
from lpnn.lights.rig import Rig, entity_lights, read_rig, write_rig
from lpnn.lights.shadows import shadow_raycaster
from lpnn.scenes.bsp import read_bsp
from lpnn.scenes.levels import Level
from lpnn.scenes.raycast import EmbreeRaycaster
from synthetic_bsp import make_level


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


def test_shader_sun_lines(tmp_path) -> None:
    """q3map_sun R G B intensity degrees elevation (shaders.c): the colour to unit length, the direction toward the
    sun from azimuth and elevation; q3map_sunExt's extra deviance and samples are read past."""
    script = """textures/skies/night
{
    surfaceparm sky
    q3map_sun 0.333333 0.45098 0.576471 155 360 90
    q3map_surfacelight 20
}
textures/skies/hell
{
    q3map_sunExt 1 1 0.5 150 30 60 2 16
}
textures/skies/none
{
    q3map_sun 0 0 0 100 0 90
}
"""
    pak = tmp_path / "a.pk3"
    with zipfile.ZipFile(pak, "w") as archive:
        archive.writestr("scripts/sky.shader", script)
    scripts = read_shader_scripts([pak])
    [(colour, photons, direction)] = shader_suns(scripts, "textures/skies/night")
    norm = math.sqrt(0.333333 ** 2 + 0.45098 ** 2 + 0.576471 ** 2)
    np.testing.assert_allclose(colour, np.array([0.333333, 0.45098, 0.576471]) / norm)
    assert photons == 155
    np.testing.assert_allclose(direction, [0.0, 0.0, 1.0], atol=1e-12)  # elevation 90: straight up to the sun
    [(colour, photons, direction)] = shader_suns(scripts, "textures/skies/hell")
    np.testing.assert_allclose(colour, np.array([1.0, 1.0, 0.5]) / 1.5)
    np.testing.assert_allclose(direction, [math.cos(math.radians(30)) * 0.5, math.sin(math.radians(30)) * 0.5,
                                           math.sqrt(3) / 2])
    assert shader_suns(scripts, "textures/skies/none") == []  # black: no light
    assert shader_suns(scripts, "textures/skies/missing") == []


def sun_scene() -> tuple[Suns, EmbreeRaycaster]:
    """A sky quad at z = 1000 over x, y in [-500, 500]; a roof quad at z = 100 over x in [100, 300] (the only
    opaque geometry); a sun of 150 photons, colour (0.6, 0.8, 0), 60 degrees up along +x."""
    def quad(x0: float, x1: float, y0: float, y1: float, z: float) -> tuple[np.ndarray, np.ndarray]:
        vertices = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]])
        return vertices, np.array([[0, 1, 2], [0, 2, 3]])

    sky = EmbreeRaycaster(*quad(-500, 500, -500, 500, 1000.0), threads=1)
    roof = EmbreeRaycaster(*quad(100, 300, -50, 50, 100.0), threads=1)
    elevation = math.radians(60)
    direction = np.array([math.cos(elevation), 0.0, math.sin(elevation)])
    suns = Suns(directions=direction[None], colours=np.array([[0.6, 0.8, 0.0]]), photons=np.array([150.0]),
                shader=np.array([0]), sky=sky)
    return suns, roof


def test_sun_lights_a_luxel_that_sees_the_sky() -> None:
    """LightContributionToSample, EMIT_SUN: colour x photons x cos to the surface's normal, when the ray toward the
    sun meets the sky first; under the roof (its shadow) and facing away, nothing."""
    suns, roof = sun_scene()
    points = np.array([[-200.0, 0.0, 0.0],  # open sky toward the sun
                       [150.0, 0.0, 0.0],  # the ray toward the sun (+x, up 60 degrees) passes x = 207 at z = 100: roof
                       [-200.0, 0.0, 0.0],  # a wall facing -x: away from the sun
                       [-200.0, 0.0, 0.0]])  # a wall facing +x
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    got = emitter_bytes(points, normals, Emitters(suns=suns), roof)
    colour = np.array([0.6, 0.8, 0.0])
    np.testing.assert_allclose(got[0], 150.0 * math.sin(math.radians(60)) * colour)
    np.testing.assert_allclose(got[1], 0.0)
    np.testing.assert_allclose(got[2], 0.0)
    np.testing.assert_allclose(got[3], 150.0 * math.cos(math.radians(60)) * colour)


def test_sun_lights_the_grid_without_a_cosine() -> None:
    """LightContributionToPoint, EMIT_SUN: photons x colour along the sun's direction, shadowed as on surfaces; a
    sun without sky triangles lights nothing."""
    suns, roof = sun_scene()
    nodes = np.array([[-200.0, 0.0, 50.0], [150.0, 0.0, 50.0]])
    colour, unit = emitters_at_points(nodes, Emitters(suns=suns), roof)
    assert colour.shape == (2, 1, 3)
    np.testing.assert_allclose(colour[0, 0], 150.0 * np.array([0.6, 0.8, 0.0]))
    np.testing.assert_allclose(unit[0, 0], suns.directions[0])
    np.testing.assert_allclose(colour[1, 0], 0.0)
    skyless = Suns(suns.directions, suns.colours, suns.photons, suns.shader, sky=None)
    np.testing.assert_allclose(emitters_at_points(nodes, Emitters(suns=skyless), roof)[0], 0.0)


def test_scripts_of_the_level_release_win_over_later_updates(tmp_path) -> None:
    """emitters.script_order: later releases' updates (pak6-patch*.pk3) are read first, so the level's release
    defines a shader both have; a level shipped in an update reads the engine's order."""
    def pak(name: str, value: int) -> Path:
        path = tmp_path / name
        with zipfile.ZipFile(path, "w") as archive:
            archive.writestr("scripts/light.shader", f"textures/base_light/ceil1_22a\n{{\n q3map_surfacelight {value}\n}}\n")
        return path

    paks = [pak("pak0.pk3", 300), pak("pak1-maps.pk3", 0), pak("pak6-patch088.pk3", 10000)]
    paks[1].unlink()
    with zipfile.ZipFile(paks[1], "w") as archive:  # the level's pak: maps, no script
        archive.writestr("maps/x.bsp", b"")
    level_pak = paks[1]
    order = script_order(paks, level_pak)
    assert [p.name for p in order] == ["pak6-patch088.pk3", "pak0.pk3", "pak1-maps.pk3"]
    light = shader_light(read_shader_scripts(order), "textures/base_light/ceil1_22a", lambda path: None)
    assert light is not None and light.value == 300
    assert script_order(paks, paks[2]) == paks  # a level of the update: the engine's order, the update wins
    assert script_order(paks, None) == [paks[2], paks[0], paks[1]]


def test_within_a_pak_the_first_definition_of_a_shader_wins_and_a_later_pak_still_overrides(tmp_path) -> None:
    """q3map2's shaders.c: ParseShaderFile appends a shaderInfo for every block, ShaderInfoForShader returns the first of
    that name. pak0.pk3's oalite.shader defines base_light/wsupprt1_12 twice (3000 with nomarks, then 600): the
    first one is what kaos was compiled with (its BSP flags the shader SURF_NOMARKS)."""
    def block(value: int) -> str:
        return f"textures/base_light/wsupprt1_12\n{{\n q3map_surfacelight {value}\n}}\n"

    release = tmp_path / "pak0.pk3"
    with zipfile.ZipFile(release, "w") as archive:
        archive.writestr("scripts/a.shader", block(3000) + block(600))
        archive.writestr("scripts/b.shader", block(1000))  # read after a.shader: the first definition is a's
    update = tmp_path / "pak6-patch085.pk3"
    with zipfile.ZipFile(update, "w") as archive:
        archive.writestr("scripts/base_light.shader", block(600))

    def value(paks: list[Path]) -> float:
        scripts = read_shader_scripts(paks)
        light = shader_light(scripts, "textures/base_light/wsupprt1_12", lambda path: None)
        assert light is not None
        return light.value

    assert value([release]) == 3000
    assert read_shader_scripts([release]).sources["textures/base_light/wsupprt1_12"] == "pak0.pk3:scripts/a.shader"
    assert value([update, release]) == 3000  # the release read last overrides the update (script_order)
    assert value([release, update]) == 600


def test_a_sky_script_on_a_shader_the_bsp_does_not_flag_sky_was_not_compiled(tmp_path) -> None:
    """The BSP stores the surface flags its compile gave a shader; a script that makes the shader sky (surfaceparm
    sky, or a sun line, which applies it) on a shader without SURF_SKY is not the script the level was built with."""
    script = """textures/skies/a
{
    surfaceparm sky
    q3map_surfacelight 100
}
textures/skies/b
{
    q3map_sun 1 1 1 50 0 90
}
textures/base/lamp
{
    q3map_surfacelight 100
}
"""
    pak = tmp_path / "a.pk3"
    with zipfile.ZipFile(pak, "w") as archive:
        archive.writestr("scripts/s.shader", script)
    scripts = read_shader_scripts([pak])
    assert script_declares_sky(scripts, "textures/skies/a") and script_declares_sky(scripts, "textures/skies/b")
    assert not script_declares_sky(scripts, "textures/base/lamp")
    assert not script_declares_sky(scripts, "textures/none")


def test_a_rig_file_relights_its_surface_lights_with_the_settings_they_were_built_with(tmp_path) -> None:
    """A surface light built two-sided, subdivided at 32 units and with its own backsplash (as a shader script may say,
    and as the fit's bases are built) is written to a rig and read back: the rig's emitters give every grid point the
    same light as the original's, behind the surface too (q3map2's defaults would light nothing there)."""
    level_bytes = make_level().to_bytes()
    level = Level(name="room", location="room.bsp", pak=None, data=level_bytes, bsp=read_bsp(level_bytes, "room.bsp"))
    light = ShaderLight(value=2000.0, colour=np.array([1.0, 0.5, 0.25]), subdivide=32.0, backsplash_fraction=0.1,
                        backsplash_distance=8.0, two_sided=True, colour_source="test")
    built = shader_emitters(level.bsp, {2: light})  # shader 2: the glass quad at x = 100 (no shadow caster)
    rig = Rig(positions=np.zeros((0, 3)), colours=np.zeros((0, 3)), intensities=np.zeros(0),
              surfaces=[surface_light(level.bsp.shader_name(2), light)])
    relit = rig_emitters(level, read_rig(write_rig(tmp_path / "rig.json", rig)))
    assert relit.areas.count == built.areas.count > 4  # subdivided at 32 units, not 999
    points = np.array([[130.0, 128.0, 60.0], [70.0, 128.0, 60.0], [40.0, 200.0, 230.0]])  # on both sides of the quad
    raycaster = shadow_raycaster(level.bsp)
    expected, _ = emitters_at_points(points, built, raycaster)
    got, _ = emitters_at_points(points, relit, raycaster)
    assert expected[0].sum() > 0 and expected[1:].sum() > 0  # the two-sided light reaches both sides
    np.testing.assert_allclose(got.sum(axis=1), expected.sum(axis=1), rtol=1e-12)
