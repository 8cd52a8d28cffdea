"""q3map2's shadow casters (lpnn.lights.shadows, lights.md §3): patches and entity brush models cast no shadow by
default, `_castShadows` / `_cs` 1 makes an entity cast, and every visibility ray of the rig follows the rule."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights.model import Lights
from lpnn.lights.pipeline import load_scene
from lpnn.lights.pointlight import visible_light
from lpnn.lights.shadows import cast_shadows_key, shadow_casting_faces, shadow_raycaster
from lpnn.scenes.bsp import read_bsp
from lpnn.scenes.levels import Level
from lpnn.scenes.raycast import EmbreeRaycaster
from lpnn.scenes.surfaces import ray_geometry

from lit_bsp import lit_level
from synthetic_bsp import face, quad

DOOR = 5  # the face added below: an opaque quad at z = 180 over x, y in [100, 150], brush model *1
PATCH = 3  # make_level's flat patch at z = 160 over x, y in [0, 64]


def level_with_door(door_keys: str = "", world_keys: str = "") -> Level:
    """lit_level() plus a func_door (brush model *1) whose one face hangs over the lit quad (z = 128)."""
    level = lit_level()
    first = len(level.vertices)
    level.vertices = list(level.vertices) + quad(180, "z", (100, 100), (150, 150))
    level.vertex_extras = list(level.vertex_extras) + [level.vertex_extras[-1]] * 4
    level.faces = list(level.faces) + [face(shader=0, type=1, first_vert=first, num_verts=4,
                                            first_index=len(level.mesh_verts), num_indexes=6)]
    level.mesh_verts = list(level.mesh_verts) + [0, 1, 2, 0, 2, 3]
    level.models = [(0, 0, 0, 256, 256, 256, 0, DOOR, 0, 1), (100, 100, 180, 150, 150, 180, DOOR, 1, 0, 0)]
    level.entities = level.entities.replace('"gridsize"', world_keys + '"gridsize"') + \
        '{\n"classname" "func_door"\n"model" "*1"\n' + door_keys + '}\n'
    data = level.to_bytes()
    return Level(name="door", location="door.bsp", pak=None, data=data, bsp=read_bsp(data, "door.bsp"))


def test_patches_and_entity_surfaces_cast_no_shadow_by_default() -> None:
    """light_trace.c PopulateWithBSPModel: no patch without -patchshadows; PopulateTraceNodes / map.c: an entity's
    surfaces only with castShadows (ENTITY_CAST_SHADOWS 0), worldspawn's with it (WORLDSPAWN_CAST_SHADOWS 1)."""
    casts = shadow_casting_faces(level_with_door().bsp)
    assert casts[0] and not casts[PATCH] and not casts[DOOR]
    assert shadow_casting_faces(level_with_door('"_cs" "1"\n').bsp)[DOOR]
    assert shadow_casting_faces(level_with_door('"_castShadows" "1"\n').bsp)[DOOR]
    # group 2 shadows only receivers of group 2; every receiver here is group 1 (TraceTriangle)
    assert not shadow_casting_faces(level_with_door('"_cs" "2"\n').bsp)[DOOR]
    world_off = shadow_casting_faces(level_with_door(world_keys='"_castShadows" "0"\n').bsp)
    assert not world_off[0] and not world_off[DOOR]
    assert not shadow_casting_faces(level_with_door('"_cs" "1"\n', '"_cs" "0"\n').bsp)[0]


@pytest.mark.parametrize("value, default, expected", [("1", 0, 1), ("0", 1, 0), ("2", 0, 2), ("-1", 0, -1),
                                                      ("1.9", 0, 1), ("x", 1, 0), ("", 1, 1), (None, 0, 0)])
def test_cast_shadows_key_is_read_as_atoi(value, default, expected) -> None:
    entity = {"classname": "func_wall"} if value is None else {"classname": "func_wall", "_cs": value}
    assert cast_shadows_key(entity, default) == expected


def test_the_patch_lets_light_through_to_the_grid_and_the_full_geometry_does_not() -> None:
    """A light above the patch, a grid node below it: the full ray geometry shadows it, q3map2's casters do not."""
    bsp = level_with_door().bsp
    full = ray_geometry(bsp)
    everything = EmbreeRaycaster(full.vertices, full.triangles, threads=1)
    node, light = np.array([[32.0, 32.0, 150.0]]), np.array([[32.0, 32.0, 190.0]])
    emitted = np.array([[7500.0 * 300.0] * 3])
    blocked, _ = visible_light(node, light, emitted, everything)
    through, _ = visible_light(node, light, emitted, shadow_raycaster(bsp))
    assert blocked.max() == 0.0
    np.testing.assert_allclose(through[0, 0], 7500.0 * 300.0 / 40.0 ** 2)  # 40 units, no occluder


def test_the_forward_model_sees_through_a_door_unless_it_casts() -> None:
    """The lit quad (z = 128) under the door (z = 180), a light above the door at z = 200: the target points under
    the door see it with the default keys and are shadowed when the door has _cs 1."""
    light = Lights(positions=np.array([[125.0, 125.0, 199.0]]), colours=np.ones((1, 3)), intensities=np.array([300.0]))

    def shadowed_share(level: Level) -> float:
        model = load_scene(level, textures=False).model
        under = np.all((model.points[:, :2] > 105) & (model.points[:, :2] < 145), axis=1) & (model.points[:, 2] < 130)
        assert under.sum() > 0
        return float(1.0 - model.visibility(light)[under, 0].mean())

    assert shadowed_share(level_with_door()) == 0.0
    assert shadowed_share(level_with_door('"_cs" "1"\n')) == 1.0
