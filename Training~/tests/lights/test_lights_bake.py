"""The probe baker (lpnn.lights.bake) against closed forms in the analytic box room."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.sh import evaluate
from lpnn.lights.bake import BakeScene, BakeSettings, bake_sh, bounce_sh, gather_directions
from lpnn.lights.rig import Rig
from lpnn.scenes.coords import quake_to_unity
from lpnn.scenes.raycast import EmbreeRaycaster

from synthetic_room import room_geometry, room_target, wall_albedo

PER_BYTE = 4.0 / 255.0
DIRECT_ONLY = BakeSettings(bounce=False, ambient=False)


def room_scene(pillar: bool) -> BakeScene:
    vertices, normals, triangles = room_geometry(divisions=8, pillar=pillar)
    target = room_target(vertices, normals, triangles, np.zeros_like(vertices), wall_albedo(vertices))
    return BakeScene.build(target, triangles, EmbreeRaycaster(vertices, triangles, threads=1))


def one_light(quake_position, colour=(1.0, 0.5, 0.25), intensity=300.0, ambient=(0.0, 0.0, 0.0)) -> Rig:
    return Rig.from_quake(np.array([quake_position], dtype=float), np.array([colour]), np.array([intensity]),
                          ambient=np.array(ambient, dtype=float))


def test_one_light_in_an_empty_box_has_the_closed_form_dc_and_linear_terms():
    scene = room_scene(pillar=False)
    point_q = np.array([128.0, 128.0, 64.0])
    light_q = np.array([128.0, 128.0 + 60.0, 64.0 + 80.0])  # 100 units away: 7500 * 300 / 100^2 = 225 bytes
    colour = np.array([1.0, 0.5, 0.25])
    sh = bake_sh(scene, one_light(light_q, colour), quake_to_unity(point_q[None]), DIRECT_ONLY).sh[0]
    c = colour * 7500.0 * 300.0 / 100.0 ** 2 * PER_BYTE  # normal-incidence light, linear units
    toward = quake_to_unity((light_q - point_q)[None] / 100.0, scale=1.0)[0]  # Unity axes (x, y, z)
    coefficients = sh.reshape(3, 9)
    np.testing.assert_allclose(coefficients[:, 0], c / 4, rtol=1e-12)
    # order (1, y, z, x): the linear terms are d l / 2
    np.testing.assert_allclose(coefficients[:, 1], c * toward[1] / 2, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(coefficients[:, 2], c * toward[2] / 2, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(coefficients[:, 3], c * toward[0] / 2, rtol=1e-12, atol=1e-15)
    # facing the light, the L2 lobe is brighter than facing away
    facing, away = evaluate(sh[None], np.stack([toward, -toward]))[0]
    assert np.all(facing > 5 * np.abs(away))


def test_the_distance_is_clamped_at_16_units_and_one_light_saturates_at_255_bytes():
    scene = room_scene(pillar=False)
    point_q = np.array([128.0, 128.0, 64.0])
    near = bake_sh(scene, one_light(point_q + [0, 0, 8.0], colour=(1, 1, 1), intensity=5.0),
                   quake_to_unity(point_q[None]), DIRECT_ONLY).sh[0]
    np.testing.assert_allclose(near[0], 7500.0 * 5.0 / 16.0 ** 2 * PER_BYTE / 4, rtol=1e-12)  # 146 bytes
    bright = bake_sh(scene, one_light(point_q + [0, 0, 8.0], colour=(1, 0.5, 0), intensity=300.0),
                     quake_to_unity(point_q[None]), DIRECT_ONLY).sh[0]
    np.testing.assert_allclose(bright.reshape(3, 9)[:, 0], np.array([1.0, 0.5, 0.0]) * 255.0 * PER_BYTE / 4)


def test_a_shadowed_point_gets_no_direct_light():
    scene = room_scene(pillar=True)  # pillar: x, y in [112, 144], z in [0, 160]
    light_q = np.array([128.0, 200.0, 64.0])
    behind = np.array([128.0, 60.0, 64.0])  # the pillar is between
    beside = np.array([60.0, 200.0, 64.0])  # same distance scale, in the open
    sh = bake_sh(scene, one_light(light_q), quake_to_unity(np.stack([behind, beside])), DIRECT_ONLY).sh
    assert np.all(sh[0] == 0.0)
    assert sh[1, 0] > 0.0


def test_the_ambient_is_added_to_the_dc_term_in_linear_units():
    scene = room_scene(pillar=True)
    rig = one_light([128.0, 200.0, 64.0], ambient=(30.0, 20.0, 10.0))
    points = quake_to_unity(np.array([[128.0, 60.0, 64.0]]))  # in the pillar's shadow
    sh = bake_sh(scene, rig, points, BakeSettings(bounce=False)).sh[0].reshape(3, 9)
    np.testing.assert_allclose(sh[:, 0], np.array([30.0, 20.0, 10.0]) * PER_BYTE, rtol=1e-12)
    assert np.all(sh[:, 1:] == 0.0)


def test_a_closed_room_of_constant_radiance_gathers_that_radiance_in_every_direction():
    scene = room_scene(pillar=True)
    radiance = np.tile([0.6, 0.3, 0.1], (len(scene.target.positions), 1))
    points = np.array([[40.0, 50.0, 60.0], [200.0, 210.0, 190.0], [128.0, 60.0, 30.0]])
    sh = bounce_sh(points, scene, radiance, gather_directions(256))
    shading = evaluate(sh, np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0], [0.6, 0.0, -0.8]]))
    np.testing.assert_allclose(shading, np.broadcast_to([0.6, 0.3, 0.1], shading.shape), rtol=0.03)


def test_surfaces_seen_from_behind_gather_nothing():
    scene = room_scene(pillar=False)  # walls face into the room
    radiance = np.ones((len(scene.target.positions), 3))
    outside = np.array([[-50.0, 128.0, 128.0]])
    assert np.all(bounce_sh(outside, scene, radiance, gather_directions(64)) == 0.0)


def test_the_bounce_of_a_lit_room_is_brighter_near_the_lit_wall_and_the_bake_is_deterministic():
    scene = room_scene(pillar=True)
    rig = one_light([128.0, 128.0, 240.0], colour=(1, 1, 1), intensity=800.0)
    points = quake_to_unity(np.array([[60.0, 60.0, 200.0], [60.0, 60.0, 20.0]]))
    settings = BakeSettings(directions=64, ambient=False)
    first = bake_sh(scene, rig, points, settings)
    second = bake_sh(scene, rig, points, settings)
    assert first.sh.tobytes() == second.sh.tobytes()
    bounce = first.sh - bake_sh(scene, rig, points, BakeSettings(bounce=False, ambient=False)).sh
    assert np.all(bounce[:, 0] > 0)  # the lit walls add light
    assert first.rays > 0


def test_gather_directions_are_unit_and_balanced():
    directions = gather_directions(128)
    np.testing.assert_allclose(np.linalg.norm(directions, axis=1), 1.0, rtol=1e-12)
    assert np.linalg.norm(directions.mean(axis=0)) < 1e-2
    with pytest.raises(ValueError, match="at least 1"):
        gather_directions(0)


def test_against_the_grid_rule_one_light_gives_two_thirds_of_the_grids_dc():
    """lights.md §8 "Units and scale": the grid stores D = c, A = 0.125 c, i.e. DC 0.375 c; the bake 0.25 c."""
    from lpnn.core.sh import ambient_plus_directed
    from lpnn.lights.compare import relight_grid

    scene = room_scene(pillar=False)
    rig = one_light([100.0, 150.0, 200.0], colour=(1.0, 0.9, 0.7), intensity=200.0)
    point_q = np.array([[120.0, 90.0, 60.0]])
    grid = relight_grid(point_q, rig, scene.occluders)
    grid_sh = PER_BYTE * ambient_plus_directed(grid.ambient, grid.directed, quake_to_unity(grid.direction, scale=1.0))
    baked = bake_sh(scene, rig, quake_to_unity(point_q), DIRECT_ONLY).sh
    np.testing.assert_allclose(baked.reshape(3, 9)[:, 0] / grid_sh.reshape(3, 9)[:, 0], 2.0 / 3.0, rtol=1e-9)
    # the same direction: the linear terms agree exactly (both are d l / 2 with d = c)
    np.testing.assert_allclose(baked.reshape(3, 9)[:, 1:4], grid_sh.reshape(3, 9)[:, 1:4], rtol=1e-9)


def test_a_rig_with_surface_lights_is_refused_not_baked_without_them():
    from lpnn.lights.rig import RigError, SurfaceLight

    rig = one_light([128.0, 128.0, 64.0])
    rig.surfaces = [SurfaceLight("textures/base_light/ceil1_22a", 2500.0, np.ones(3))]
    with pytest.raises(RigError, match=r"1 surface light\(s\) \(textures/base_light/ceil1_22a"):
        bake_sh(room_scene(pillar=False), rig, np.zeros((1, 3)), DIRECT_ONLY)
