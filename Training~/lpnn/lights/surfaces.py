"""The lit surfaces of a level as one triangle mesh with per-vertex attributes (Quake units and axes).

Which faces carry baked lighting (Documentation~/lights.md §1):
  - drawn, opaque faces (the importer's ray-geometry rule: not sky, nodraw, translucent or liquid);
  - polygons and patches with a lightmap page 0 <= n < pages: lightmap-lit;
  - meshes (type 3, always vertex-lit by the renderer) and faces with lightmap -3: vertex-lit, the
    light is in the vertex colours;
  - anything else (lightmap -1: fullbright / emissive shaders; a page index past lump 14) is no target.
Every face keeps its own vertices (BSP vertices are per face), so the mesh never blends lightmaps
of different faces. Patches are tessellated at the importer's level, attributes included.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scenes.bsp import FACE_MESH, FACE_PATCH, FACE_POLYGON, Bsp
from ..scenes.errors import BspError
from ..scenes.patches import PATCH_LEVEL, tessellate_patches
from ..scenes.ranges import concatenated_ranges
from ..scenes.surfaces import select_ray_faces, triangle_areas

VERTEX_LIT = -3
# Attribute columns of `LitMesh.attributes`.
POSITION, NORMAL, ST, LIGHTMAP_ST, COLOR = slice(0, 3), slice(3, 6), slice(6, 8), slice(8, 10), slice(10, 13)
ATTRIBUTE_COUNT = 13


@dataclass(frozen=True)
class LitMesh:
    attributes: np.ndarray  # (V, 13) float64: position, unit normal, st, lightmap st, vertex colour bytes
    triangles: np.ndarray  # (T, 3) int64, no zero-area triangles
    face_of_triangle: np.ndarray  # (T,) int64 BSP face
    lightmap_of_triangle: np.ndarray  # (T,) int64 page, or -1: vertex-lit (colour attribute)
    shader_of_triangle: np.ndarray  # (T,) int64 BSP shader
    excluded: dict[str, int]  # reason -> faces that are not targets

    @property
    def positions(self) -> np.ndarray:
        return self.attributes[:, POSITION]

    @property
    def normals(self) -> np.ndarray:
        return self.attributes[:, NORMAL]

    @property
    def vertex_count(self) -> int:
        return len(self.attributes)


def vertex_attributes(bsp: Bsp) -> np.ndarray:
    v = bsp.vertices
    return np.concatenate([v["position"], v["normal"], v["st"], v["lightmap_st"], v["color"][:, :3]],
                          axis=1).astype(np.float64)


def face_triangles(bsp: Bsp, faces: np.ndarray, patch_level: int = PATCH_LEVEL) -> tuple[np.ndarray, np.ndarray,
                                                                                        np.ndarray]:
    """The triangles of the given faces (ascending indices): (attributes (V, 13), the BSP's vertices then the patches'
    tessellated ones; triangles (T, 3) into them, the polygons' and meshes' by their indices, then the patches'; (T,)
    the face of each). The one reading of BSP faces as triangles of the rig code (lit_mesh, emitters.surface_triangles)."""
    table = bsp.faces
    attributes = vertex_attributes(bsp)
    kind = table["type"][faces]
    indexed = faces[np.isin(kind, (FACE_POLYGON, FACE_MESH))]
    counts = table["num_indexes"][indexed].astype(np.int64)
    owner = np.repeat(indexed, counts)
    corners = table["first_vert"][owner].astype(np.int64) + \
        bsp.mesh_verts[concatenated_ranges(table["first_index"][indexed], counts)]
    patched = faces[kind == FACE_PATCH]
    patch_attributes, patch_triangles, patch_face = tessellate_patches(
        attributes, table["first_vert"][patched], table["patch_width"][patched], table["patch_height"][patched],
        patch_level)
    triangles = np.concatenate([corners.reshape(-1, 3), patch_triangles + len(attributes)])
    face = np.concatenate([owner[::3], patched[patch_face]]).astype(np.int64)
    return np.concatenate([attributes, patch_attributes]), triangles, face


def lit_mesh(bsp: Bsp, patch_level: int = PATCH_LEVEL) -> LitMesh:
    """The level's lit faces as one mesh; BspError when the level has none."""
    faces = bsp.faces
    kind, page = faces["type"], faces["lightmap"].astype(np.int64)
    drawn = select_ray_faces(bsp).is_geometry
    lightmapped = np.isin(kind, (FACE_POLYGON, FACE_PATCH)) & (page >= 0) & (page < bsp.lightmap_count)
    vertex_lit = (kind == FACE_MESH) | (np.isin(kind, (FACE_POLYGON, FACE_PATCH)) & (page == VERTEX_LIT))
    excluded = {
        "not drawn or see-through": int(np.count_nonzero(~drawn)),
        "no baked light (lightmap -1 or a page past lump 14)": int(np.count_nonzero(drawn & ~(lightmapped | vertex_lit))),
    }
    target = drawn & (lightmapped | vertex_lit)
    if not target.any():
        raise BspError(f"{bsp.name}: no surface carries baked light (no face has a lightmap page in lump 14 "
                       f"({bsp.lightmap_count} pages) or vertex lighting): compile the level with q3map2 -light")
    face_page = np.where(lightmapped, page, -1)
    all_attributes, triangles, face = face_triangles(bsp, np.flatnonzero(target), patch_level)
    normals = all_attributes[:, NORMAL]
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    all_attributes[:, NORMAL] = np.divide(normals, lengths, out=np.zeros_like(normals), where=lengths > 0)
    keep = triangle_areas(all_attributes[:, POSITION], triangles) > 0.0
    triangles, face = triangles[keep], face[keep]
    # only the vertices triangles use: unused BSP vertices would be target points without area
    used, compact = np.unique(triangles, return_inverse=True)
    return LitMesh(attributes=all_attributes[used], triangles=compact.reshape(-1, 3), face_of_triangle=face,
                   lightmap_of_triangle=face_page[face], shader_of_triangle=faces["shader"][face].astype(np.int64),
                   excluded=excluded)


def subdivide(mesh: LitMesh, max_edge: float, max_rounds: int = 8) -> LitMesh:
    """Split triangles whose longest edge exceeds `max_edge` (Quake units) into 4 at their edge
    midpoints, repeatedly, until none does (at most `max_rounds` rounds).

    Split triangles share their midpoints; a midpoint on the edge of an unsplit neighbour is a
    hanging vertex, which the mass-lumped projection handles like any other (its value is the
    average over the triangles that contain it). Attributes are interpolated linearly, exact for
    st / lightmap st within a flat face.
    """
    if not (max_edge > 0):
        raise ValueError(f"max_edge {max_edge!r} must be > 0 (Quake units)")
    for _ in range(max_rounds):
        corners = mesh.positions[mesh.triangles]
        longest = np.max(np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2), axis=1)
        split = longest > max_edge
        if not split.any():
            break
        mesh = _split(mesh, split)
    return mesh


def _split(mesh: LitMesh, split: np.ndarray) -> LitMesh:
    triangles = mesh.triangles[split]
    edges = np.sort(np.stack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]], axis=1), axis=2)
    unique_edges, edge_index = np.unique(edges.reshape(-1, 2), axis=0, return_inverse=True)
    midpoints = 0.5 * (mesh.attributes[unique_edges[:, 0]] + mesh.attributes[unique_edges[:, 1]])
    normals = midpoints[:, NORMAL]
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    midpoints[:, NORMAL] = np.divide(normals, lengths, out=np.zeros_like(normals), where=lengths > 0)
    m = edge_index.reshape(-1, 3) + mesh.vertex_count  # midpoints of edges 01, 12, 20
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    children = np.stack([np.stack([a, m[:, 0], m[:, 2]], 1), np.stack([m[:, 0], b, m[:, 1]], 1),
                         np.stack([m[:, 2], m[:, 1], c], 1), np.stack([m[:, 0], m[:, 1], m[:, 2]], 1)], axis=1)
    kept = ~split

    def per_triangle(values: np.ndarray) -> np.ndarray:
        return np.concatenate([values[kept], np.repeat(values[split], 4)])

    return LitMesh(attributes=np.concatenate([mesh.attributes, midpoints]),
                   triangles=np.concatenate([mesh.triangles[kept], children.reshape(-1, 3)]),
                   face_of_triangle=per_triangle(mesh.face_of_triangle),
                   lightmap_of_triangle=per_triangle(mesh.lightmap_of_triangle),
                   shader_of_triangle=per_triangle(mesh.shader_of_triangle), excluded=mesh.excluded)
