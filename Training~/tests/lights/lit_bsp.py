"""The importer tests' synthetic level with baked light: a lightmapped quad and a vertex-lit patch."""

from __future__ import annotations

import numpy as np

from synthetic_bsp import SyntheticLevel, make_level

PAGE_BYTE = 90  # lightmap value of the lit quad
PATCH_COLOUR = (100, 50, 25)
PER_BYTE = 4 / 255  # quake3-bsp.md §3: overbright, 2 map bits


def lit_level(page: np.ndarray | None = None) -> SyntheticLevel:
    """make_level() with its opaque quad (face 0, z = 128, x 64..192, y 0..256) on lightmap page 0,
    texels 8..72 on both axes, and its flat patch (face 3) vertex-lit in PATCH_COLOUR."""
    level = make_level()
    extras = [(0, 0, 0, 0, 0, 0, 1, 255, 255, 255, 255)] * len(level.vertices)
    for index in range(4):  # face 0's corners
        x, y, _ = level.vertices[index]
        s, t = (x - 64) / 128, y / 256
        extras[index] = (s, t, (8 + 64 * s) / 128, (8 + 64 * t) / 128, 0, 0, 1, 255, 255, 255, 255)
    patch = level.faces[3]
    for index in range(patch["first_vert"], patch["first_vert"] + patch["num_verts"]):
        extras[index] = (0, 0, 0, 0, 0, 0, 1, *PATCH_COLOUR, 255)
    level.vertex_extras = extras
    level.faces[0]["lightmap"] = 0
    level.faces[3]["lightmap"] = -3
    if page is None:
        page = np.full((128, 128, 3), PAGE_BYTE, dtype=np.uint8)
    level.lightmaps = page.astype(np.uint8).tobytes()
    return level
