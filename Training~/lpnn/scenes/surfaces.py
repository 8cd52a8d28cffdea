"""Which faces are geometry for rays, and all of them as one triangle soup (Quake units).

Rule (Documentation~/openarena.md): a face is ray geometry when it is a drawn, opaque surface,
i.e. one that blocks light in the light compile and that a Unity level would have as an opaque
mesh:
  - polygons, meshes and patches; billboards (flares) have no geometry;
  - not SURF_SKY: the sky is open (light comes in through it; Unity's sky is a skybox, not a mesh);
  - not SURF_NODRAW: invisible;
  - not CONTENTS_TRANSLUCENT ("surfaceparm trans": glass, beams, decals, fences, light covers),
    nor a fog/water/slime/lava volume: q3map2 lets light through them.
Brush-model faces (doors, platforms) count, at their compiled position.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bsp import FACE_BILLBOARD, FACE_MESH, FACE_PATCH, FACE_POLYGON, Bsp
from .patches import PATCH_LEVEL, tessellate_patches
from .ranges import concatenated_ranges

# code/game/surfaceflags.h
SURF_SKY = 0x4
SURF_NODRAW = 0x80
CONTENTS_SOLID = 0x1
CONTENTS_LAVA = 0x8
CONTENTS_SLIME = 0x10
CONTENTS_WATER = 0x20
CONTENTS_FOG = 0x40
CONTENTS_TRANSLUCENT = 0x20000000
SEE_THROUGH_CONTENTS = CONTENTS_TRANSLUCENT | CONTENTS_FOG | CONTENTS_WATER | CONTENTS_SLIME | CONTENTS_LAVA


@dataclass(frozen=True)
class FaceSelection:
    """Per-face decision and the reason counts `lpnn scene info` prints."""

    is_geometry: np.ndarray  # (faces,) bool
    excluded: dict[str, int]  # reason -> faces excluded for it (first matching reason)


@dataclass(frozen=True)
class TriangleSoup:
    vertices: np.ndarray  # (V, 3) float64, Quake units
    triangles: np.ndarray  # (T, 3) int64 into vertices; no zero-area triangles
    face_of_triangle: np.ndarray  # (T,) int64 face index in the BSP

    @property
    def triangle_count(self) -> int:
        return int(len(self.triangles))


def select_ray_faces(bsp: Bsp) -> FaceSelection:
    kind = bsp.faces["type"]
    shader = bsp.faces["shader"]
    surface = bsp.shaders["surface_flags"][shader]
    contents = bsp.shaders["content_flags"][shader]
    reasons = (
        ("billboard", kind == FACE_BILLBOARD),
        ("sky", (surface & SURF_SKY) != 0),
        ("nodraw", (surface & SURF_NODRAW) != 0),
        ("translucent or liquid/fog", (contents & SEE_THROUGH_CONTENTS) != 0),
    )
    excluded: dict[str, int] = {}
    is_geometry = np.ones(len(kind), dtype=bool)
    for reason, hit in reasons:
        excluded[reason] = int(np.count_nonzero(hit & is_geometry))
        is_geometry &= ~hit
    return FaceSelection(is_geometry=is_geometry, excluded=excluded)


def ray_geometry(bsp: Bsp, patch_level: int = PATCH_LEVEL, faces_kept: np.ndarray | None = None) -> TriangleSoup:
    """The triangles rays can hit: indexed polygons/meshes plus tessellated patches; with `faces_kept` ((faces,)
    bool), only those of the faces it keeps (the light rig's shadow casters, lights/shadows.py)."""
    selected = select_ray_faces(bsp).is_geometry
    if faces_kept is not None:
        selected = selected & faces_kept
    faces = bsp.faces
    positions = bsp.vertices["position"].astype(np.float64)

    indexed = np.flatnonzero(selected & np.isin(faces["type"], (FACE_POLYGON, FACE_MESH)))
    counts = faces["num_indexes"][indexed].astype(np.int64)
    corner_owner = np.repeat(indexed, counts)
    corners = faces["first_vert"][corner_owner].astype(np.int64) + \
        bsp.mesh_verts[concatenated_ranges(faces["first_index"][indexed], counts)]
    indexed_triangles = corners.reshape(-1, 3)
    indexed_faces = corner_owner[::3]

    patched = np.flatnonzero(selected & (faces["type"] == FACE_PATCH))
    patch_vertices, patch_triangles, patch_face = tessellate_patches(
        positions, faces["first_vert"][patched], faces["patch_width"][patched], faces["patch_height"][patched],
        patch_level,
    )
    vertices = np.concatenate([positions, patch_vertices])
    triangles = np.concatenate([indexed_triangles, patch_triangles + len(positions)])
    face_of_triangle = np.concatenate([indexed_faces, patched[patch_face]]).astype(np.int64)

    keep = triangle_areas(vertices, triangles) > 0.0
    return TriangleSoup(vertices=vertices, triangles=triangles[keep], face_of_triangle=face_of_triangle[keep])


def triangle_areas(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    v = vertices[triangles]
    return 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)
