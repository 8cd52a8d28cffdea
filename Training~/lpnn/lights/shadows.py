"""Which surfaces cast shadows in q3map2's light compile: the geometry of every visibility ray of the light rig
(the forward model's shadow rays, the suns' sky test, the re-lit light grid, the probe baker's direct light;
Documentation~/lights.md §3, §6, §8).

q3map2 (TTimo/GtkRadiant tools/quake3/q3map2) fills its trace tree in light_trace.c `PopulateTraceNodes`:
  - worldspawn's surfaces (BSP model 0: the world brushes, func_groups and misc_models compiled into it) through
    `PopulateWithBSPModel`, which skips a surface whose `castShadows` is 0 and **every patch unless `-patchshadows`**
    (`ds->surfaceType == MST_PATCH && patchShadows == qfalse`; the global option, off by default in q3map2.h; the
    shader keyword `q3map_patchShadows` is parsed in shaders.c but never read by the trace);
  - an entity's brush models (`model` / `model2` "*N") only when its `castShadows` is not 0, which by default it
    is: `ENTITY_CAST_SHADOWS` 0 (q3map2.h) unless the entity has `_castShadows` or `_cs` (bspfile_abstract.c
    `GetEntityShadowFlags`, read with atoi). Worldspawn's default is `WORLDSPAWN_CAST_SHADOWS` 1 (map.c, the
    same keys on worldspawn override it).
  - A receiver takes shadows from a caster only by group (light_trace.c `TraceTriangle`): surfaces and grid
    points receive as `recvShadows` 1 (`WORLDSPAWN_RECV_SHADOWS` / `ENTITY_RECV_SHADOWS`; light.c `TraceGrid`
    sets 1), and a receiver of group 1 is shadowed only by casters of `castShadows` exactly 1. So a surface
    casts here when its entity's value is 1; other groups (values > 1 or < 0, and `_receiveShadows` keys) are
    not modelled: none of the four levels with light entities has such a key.
Sky, nodraw, translucent and liquid surfaces are not geometry at all (scenes/surfaces.py select_ray_faces; light_trace.c
skips nodraw and translucent surfaces without alphashadow or lightfilter the same way).
"""

from __future__ import annotations

import re

import numpy as np

from ..scenes.bsp import FACE_PATCH, Bsp
from ..scenes.raycast import EmbreeRaycaster
from ..scenes.surfaces import ray_geometry

WORLDSPAWN_CAST_SHADOWS = 1  # q3map2.h
ENTITY_CAST_SHADOWS = 0  # q3map2.h
CASTS_ON_DEFAULT_RECEIVERS = 1  # light_trace.c TraceTriangle: receivers of group 1 take shadows from casters of 1 only
_LEADING_INTEGER = re.compile(r"\s*([+-]?\d+)")


def cast_shadows_key(entity: dict[str, str], default: int) -> int:
    """An entity's castShadows (bspfile_abstract.c GetEntityShadowFlags): `_castShadows`, else `_cs`, read as C's atoi
    (leading integer, 0 when there is none); `default` when neither key is there or both are empty."""
    keys = {key.lower(): value for key, value in entity.items()}
    value = keys.get("_castshadows", "") or keys.get("_cs", "")
    if value == "":
        return default
    match = _LEADING_INTEGER.match(value)
    return int(match.group(1)) if match else 0


def shadow_casting_faces(bsp: Bsp) -> np.ndarray:
    """(faces,) bool: the faces q3map2 puts in its shadow-ray tree by the rules of the module docstring (before the
    ray-geometry rule, which ray_geometry applies on top): no patch; worldspawn's faces when worldspawn casts; an
    entity's brush-model faces only when the entity casts."""
    faces = len(bsp.faces)
    casts = np.zeros(faces, bool)
    models = bsp.models

    def model_faces(number: int) -> slice:
        first = int(models["first_surface"][number])
        return slice(first, first + int(models["num_surfaces"][number]))

    world = bsp.entities[0] if bsp.entities else {}
    if len(models) and cast_shadows_key(world, WORLDSPAWN_CAST_SHADOWS) == CASTS_ON_DEFAULT_RECEIVERS:
        casts[model_faces(0)] = True
    for entity in bsp.entities[1:]:
        if cast_shadows_key(entity, ENTITY_CAST_SHADOWS) != CASTS_ON_DEFAULT_RECEIVERS:
            continue
        for key in ("model", "model2"):
            value = entity.get(key, "")
            if value.startswith("*") and value[1:].isdigit() and 0 < int(value[1:]) < len(models):
                casts[model_faces(int(value[1:]))] = True
    return casts & (bsp.faces["type"] != FACE_PATCH)


def shadow_raycaster(bsp: Bsp) -> EmbreeRaycaster:
    """The level's shadow casters (shadow_casting_faces) as an Embree scene."""
    geometry = ray_geometry(bsp, faces_kept=shadow_casting_faces(bsp))
    return EmbreeRaycaster(geometry.vertices, geometry.triangles)
