"""A minimal valid IBSP v46 writer for tests, independent of the reader (plain `struct`, the byte
layout of quake3-bsp.md §1), so the reader's dtypes are checked against the spec, not themselves.

`make_level()` is a small level in Quake units:
  - world bounds (0,0,0)..(256,256,256); light grid 64x64x128 -> 5 x 5 x 3 cells;
  - one solid brush, the cube [0,64]^3;
  - a one-node BSP: plane x = 192; x > 192 is leaf 1 (cluster -1: outside the map), the rest
    leaf 0 (cluster 0, holding the brush);
  - faces: 0 an opaque quad at z = 128 over x in [64,192], y in [0,256]; 1 a sky quad at z = 200;
    2 a translucent quad at x = 100; 3 a flat 3x3 patch at z = 160; 4 a billboard;
  - entities: worldspawn (gridsize) and two lights.
"""

from __future__ import annotations

import struct
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

HEADER_BYTES = 8 + 17 * 8
GRID_DIMS = (5, 5, 3)
SURF_SKY = 0x4
CONTENTS_SOLID = 0x1
CONTENTS_TRANSLUCENT = 0x20000000


def face(**fields: object) -> dict:
    record = dict(shader=0, fog=-1, type=1, first_vert=0, num_verts=0, first_index=0, num_indexes=0,
                  lightmap=-1, lm=(0, 0, 0, 0), lm_origin=(0.0, 0.0, 0.0), lm_vecs=(0.0,) * 9,
                  patch_width=0, patch_height=0)
    record.update(fields)
    return record


@dataclass
class SyntheticLevel:
    entities: str = ""
    shaders: list[tuple[str, int, int]] = field(default_factory=list)
    planes: list[tuple[float, float, float, float]] = field(default_factory=list)
    nodes: list[tuple[int, int, int]] = field(default_factory=list)  # plane, front, back
    leafs: list[dict] = field(default_factory=list)
    leaf_surfaces: list[int] = field(default_factory=list)
    leaf_brushes: list[int] = field(default_factory=list)
    models: list[tuple] = field(default_factory=list)  # mins3, maxs3, first_surface, n, first_brush, n
    brushes: list[tuple[int, int, int]] = field(default_factory=list)
    brush_sides: list[tuple[int, int]] = field(default_factory=list)
    vertices: list[tuple[float, float, float]] = field(default_factory=list)
    mesh_verts: list[int] = field(default_factory=list)
    faces: list[dict] = field(default_factory=list)
    light_grid: bytes = b""
    lightmaps: bytes = b""  # lump 14: 128*128*3 bytes a page
    # optional full vertex records (st, lightmap st, normal, rgba) parallel to `vertices`
    vertex_extras: list[tuple] | None = None
    visibility: tuple[int, int] | None = (1, 8)
    magic: bytes = b"IBSP"
    version: int = 46

    def lump_bytes(self) -> list[bytes]:
        entity_text = self.entities.encode("latin-1") + b"\0"
        shaders = b"".join(struct.pack("<64sii", n.encode(), s, c) for n, s, c in self.shaders)
        planes = b"".join(struct.pack("<4f", *p) for p in self.planes)
        nodes = b"".join(struct.pack("<9i", p, a, b, 0, 0, 0, 0, 0, 0) for p, a, b in self.nodes)
        leafs = b"".join(struct.pack("<12i", l["cluster"], 0, 0, 0, 0, 0, 0, 0, l.get("first_surface", 0),
                                     l.get("num_surfaces", 0), l.get("first_brush", 0), l.get("num_brushes", 0))
                         for l in self.leafs)
        ints = lambda values: b"".join(struct.pack("<i", v) for v in values)  # noqa: E731
        models = b"".join(struct.pack("<6f4i", *m) for m in self.models)
        brushes = b"".join(struct.pack("<3i", *b) for b in self.brushes)
        sides = b"".join(struct.pack("<2i", *s) for s in self.brush_sides)
        default_extra = (0, 0, 0, 0, 0, 0, 1, 255, 255, 255, 255)
        extras = self.vertex_extras or [default_extra] * len(self.vertices)
        vertices = b"".join(struct.pack("<3f2f2f3f4B", *v, *e) for v, e in zip(self.vertices, extras))
        faces = b"".join(
            struct.pack("<12i3f9f2i", f["shader"], f["fog"], f["type"], f["first_vert"], f["num_verts"],
                        f["first_index"], f["num_indexes"], f["lightmap"], *f["lm"], *f["lm_origin"],
                        *f["lm_vecs"], f["patch_width"], f["patch_height"])
            for f in self.faces
        )
        vis = b"" if self.visibility is None else (
            struct.pack("<2i", *self.visibility) + b"\xff" * (self.visibility[0] * self.visibility[1]))
        return [entity_text, shaders, planes, nodes, leafs, ints(self.leaf_surfaces), ints(self.leaf_brushes),
                models, brushes, sides, vertices, ints(self.mesh_verts), b"", faces, self.lightmaps, self.light_grid, vis]

    def to_bytes(self) -> bytes:
        lumps = self.lump_bytes()
        directory, body = [], b""
        for data in lumps:
            directory.append((HEADER_BYTES + len(body), len(data)))
            body += data + b"\0" * (-len(data) % 4)
        header = self.magic + struct.pack("<i", self.version) + b"".join(struct.pack("<2i", *d) for d in directory)
        return header + body


def set_lump(data: bytes, lump: int, offset: int | None = None, length: int | None = None) -> bytes:
    """Rewrite one directory entry of an encoded file."""
    at = 8 + 8 * lump
    old_offset, old_length = struct.unpack_from("<2i", data, at)
    entry = struct.pack("<2i", old_offset if offset is None else offset, old_length if length is None else length)
    return data[:at] + entry + data[at + 8:]


def grid_record(ambient: tuple[int, int, int], directed: tuple[int, int, int], theta: int, phi: int) -> bytes:
    return bytes([*ambient, *directed, theta, phi])


def make_grid_bytes() -> bytes:
    """5x5x3 cells, x fastest: ambient (10+10x, 20+5y, 30+3z), directed (50,60,70), light straight up."""
    records = []
    for z in range(GRID_DIMS[2]):
        for y in range(GRID_DIMS[1]):
            for x in range(GRID_DIMS[0]):
                records.append(grid_record((10 + 10 * x, 20 + 5 * y, 30 + 3 * z), (50, 60, 70), 0, 0))
    return b"".join(records)


def quad(z_or_x: float, axis: str, lo: tuple[float, float], hi: tuple[float, float]) -> list[tuple[float, float, float]]:
    if axis == "z":
        return [(lo[0], lo[1], z_or_x), (hi[0], lo[1], z_or_x), (hi[0], hi[1], z_or_x), (lo[0], hi[1], z_or_x)]
    return [(z_or_x, lo[0], lo[1]), (z_or_x, hi[0], lo[1]), (z_or_x, hi[0], hi[1]), (z_or_x, lo[0], hi[1])]


def make_level() -> SyntheticLevel:
    level = SyntheticLevel()
    level.entities = (
        '{\n"classname" "worldspawn"\n"gridsize" "64 64 128"\n"message" "synthetic // not a comment"\n}\n'
        '{\n"classname" "light"\n"origin" "100 100 100"\n"light" "300"\n}\n'
        '{\n"classname" "lightJunior"\n"origin" "10 10 10"\n}\n'
        '{\n"classname" "info_player_deathmatch"\n"origin" "96 96 40"\n}\n'
    )
    level.shaders = [("textures/test/wall", 0, CONTENTS_SOLID), ("textures/test/sky", SURF_SKY, CONTENTS_SOLID),
                     ("textures/test/glass", 0, CONTENTS_TRANSLUCENT | CONTENTS_SOLID)]
    # cube [0,64]^3: outward normals, n.p <= dist inside, axial sides in the compilers' order
    # (-x, +x, -y, +y, -z, +z); then the node plane x = 192
    level.planes = [(-1, 0, 0, 0), (1, 0, 0, 64), (0, -1, 0, 0), (0, 1, 0, 64), (0, 0, -1, 0), (0, 0, 1, 64),
                    (1, 0, 0, 192)]
    level.brush_sides = [(p, 0) for p in range(6)]
    level.brushes = [(0, 6, 0)]
    level.nodes = [(6, -2, -1)]  # front -> leaf 1, back -> leaf 0
    level.leafs = [dict(cluster=0, first_surface=0, num_surfaces=0, first_brush=0, num_brushes=1),
                   dict(cluster=-1)]
    level.leaf_brushes = [0]

    vertices, mesh_verts, faces = [], [], []

    def add_quad(points: list, shader: int) -> None:
        faces.append(face(shader=shader, type=1, first_vert=len(vertices), num_verts=4,
                          first_index=len(mesh_verts), num_indexes=6))
        vertices.extend(points)
        mesh_verts.extend([0, 1, 2, 0, 2, 3])

    add_quad(quad(128, "z", (64, 0), (192, 256)), 0)
    add_quad(quad(200, "z", (0, 0), (256, 256)), 1)
    add_quad(quad(100, "x", (0, 0), (256, 256)), 2)
    patch = [(x, y, 160.0) for y in (0, 32, 64) for x in (0, 32, 64)]  # row = y, column = x
    faces.append(face(shader=0, type=2, first_vert=len(vertices), num_verts=9, patch_width=3, patch_height=3))
    vertices.extend(patch)
    faces.append(face(shader=0, type=4, first_vert=len(vertices), num_verts=1))
    vertices.append((50, 50, 50))
    level.vertices, level.mesh_verts, level.faces = vertices, mesh_verts, faces
    level.models = [(0, 0, 0, 256, 256, 256, 0, len(faces), 0, 1)]
    level.light_grid = make_grid_bytes()
    return level


def write_pk3(path: Path, members: dict[str, bytes]) -> Path:
    with zipfile.ZipFile(path, "w") as archive:
        for name, data in members.items():
            archive.writestr(name, data)
    return path
