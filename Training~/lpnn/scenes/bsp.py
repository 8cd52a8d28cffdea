"""Quake III BSP (IBSP, version 46) reader: every lump as a numpy structured array, validated.

Layout: id's `code/qcommon/qfiles.h` (github.com/id-Software/Quake-III-Arena). Records are decoded with
`np.frombuffer` and structured little-endian dtypes; every count, range and index the importer
relies on is checked up front, so a damaged file fails here with a `BspError` naming the file,
the lump, the record and the value, never later inside numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .entities import parse_entities, parse_vector
from .errors import BspError
from .ranges import concatenated_ranges

MAGIC = b"IBSP"
VERSION = 46
LUMP_COUNT = 17
HEADER_DTYPE = np.dtype([("magic", "S4"), ("version", "<i4"), ("lumps", "<i4", (LUMP_COUNT, 2))])
HEADER_BYTES = HEADER_DTYPE.itemsize  # 144

LUMP_NAMES = (
    "entities", "shaders", "planes", "nodes", "leafs", "leafsurfaces", "leafbrushes", "models",
    "brushes", "brushsides", "drawverts", "drawindexes", "fogs", "surfaces", "lightmaps",
    "lightgrid", "visibility",
)
(ENTITIES, SHADERS, PLANES, NODES, LEAFS, LEAF_SURFACES, LEAF_BRUSHES, MODELS, BRUSHES, BRUSH_SIDES,
 VERTICES, MESH_VERTS, FOGS, FACES, LIGHTMAPS, LIGHT_GRID, VISIBILITY) = range(LUMP_COUNT)

SHADER_DTYPE = np.dtype([("name", "S64"), ("surface_flags", "<i4"), ("content_flags", "<i4")])
PLANE_DTYPE = np.dtype([("normal", "<f4", 3), ("dist", "<f4")])
NODE_DTYPE = np.dtype([("plane", "<i4"), ("children", "<i4", 2), ("mins", "<i4", 3), ("maxs", "<i4", 3)])
LEAF_DTYPE = np.dtype([
    ("cluster", "<i4"), ("area", "<i4"), ("mins", "<i4", 3), ("maxs", "<i4", 3),
    ("first_leaf_surface", "<i4"), ("num_leaf_surfaces", "<i4"),
    ("first_leaf_brush", "<i4"), ("num_leaf_brushes", "<i4"),
])
INDEX_DTYPE = np.dtype("<i4")
MODEL_DTYPE = np.dtype([
    ("mins", "<f4", 3), ("maxs", "<f4", 3), ("first_surface", "<i4"), ("num_surfaces", "<i4"),
    ("first_brush", "<i4"), ("num_brushes", "<i4"),
])
BRUSH_DTYPE = np.dtype([("first_side", "<i4"), ("num_sides", "<i4"), ("shader", "<i4")])
BRUSH_SIDE_DTYPE = np.dtype([("plane", "<i4"), ("shader", "<i4")])
VERTEX_DTYPE = np.dtype([
    ("position", "<f4", 3), ("st", "<f4", 2), ("lightmap_st", "<f4", 2), ("normal", "<f4", 3), ("color", "u1", 4),
])
FOG_DTYPE = np.dtype([("shader", "S64"), ("brush", "<i4"), ("visible_side", "<i4")])
FACE_DTYPE = np.dtype([
    ("shader", "<i4"), ("fog", "<i4"), ("type", "<i4"), ("first_vert", "<i4"), ("num_verts", "<i4"),
    ("first_index", "<i4"), ("num_indexes", "<i4"), ("lightmap", "<i4"), ("lightmap_rect", "<i4", 4),
    ("lightmap_origin", "<f4", 3), ("lightmap_vecs", "<f4", (3, 3)), ("patch_width", "<i4"), ("patch_height", "<i4"),
])
LIGHTMAP_SIDE = 128
LIGHTMAP_BYTES = LIGHTMAP_SIDE * LIGHTMAP_SIDE * 3
LIGHT_GRID_RECORD_BYTES = 8

RECORD_DTYPES: dict[int, np.dtype] = {
    SHADERS: SHADER_DTYPE, PLANES: PLANE_DTYPE, NODES: NODE_DTYPE, LEAFS: LEAF_DTYPE,
    LEAF_SURFACES: INDEX_DTYPE, LEAF_BRUSHES: INDEX_DTYPE, MODELS: MODEL_DTYPE, BRUSHES: BRUSH_DTYPE,
    BRUSH_SIDES: BRUSH_SIDE_DTYPE, VERTICES: VERTEX_DTYPE, MESH_VERTS: INDEX_DTYPE, FOGS: FOG_DTYPE,
    FACES: FACE_DTYPE, LIGHTMAPS: np.dtype(("u1", LIGHTMAP_BYTES)),
    LIGHT_GRID: np.dtype(("u1", LIGHT_GRID_RECORD_BYTES)),
}
# The engine's collision loader refuses maps without these (cm_load.c: "Map with no ...").
REQUIRED_LUMPS = (SHADERS, PLANES, NODES, LEAFS, MODELS)

FACE_POLYGON, FACE_PATCH, FACE_MESH, FACE_BILLBOARD = 1, 2, 3, 4
FACE_TYPE_NAMES = {FACE_POLYGON: "polygon", FACE_PATCH: "patch", FACE_MESH: "mesh", FACE_BILLBOARD: "billboard"}
# The engine tessellates control grids of up to MAX_GRID_SIZE = 65 points a side (tr_local.h).
MAX_PATCH_SIDE = 65
DEFAULT_GRID_SIZE = (64.0, 64.0, 128.0)
# Far beyond any real grid (q3map2 keeps it under 2^20 points); guards memory before allocation.
MAX_LIGHT_GRID_POINTS = 1 << 24


@dataclass(frozen=True)
class LightGridLayout:
    """Where the light grid's samples sit, in Quake units: origin + (x, y, z) * cell_size."""

    origin: np.ndarray  # (3,) float64
    cell_size: np.ndarray  # (3,) float64, from worldspawn "gridsize" or the default 64 64 128
    dims: np.ndarray  # (3,) int64, points per axis (x varies fastest in the lump)

    @property
    def point_count(self) -> int:
        return int(np.prod(self.dims))

    @property
    def maxs(self) -> np.ndarray:
        return self.origin + (self.dims - 1) * self.cell_size


@dataclass(frozen=True)
class Bsp:
    """One level. Arrays are structured records (dtypes above), in file order, in Quake units."""

    name: str
    entities: list[dict[str, str]]
    shaders: np.ndarray
    planes: np.ndarray
    nodes: np.ndarray
    leafs: np.ndarray
    leaf_surfaces: np.ndarray
    leaf_brushes: np.ndarray
    models: np.ndarray
    brushes: np.ndarray
    brush_sides: np.ndarray
    vertices: np.ndarray
    mesh_verts: np.ndarray
    fogs: np.ndarray
    faces: np.ndarray
    lightmap_count: int
    lightmaps: np.ndarray  # (pages, 128, 128, 3) uint8 RGB, rows first (lump 14; read-only view of the file)
    light_grid: np.ndarray | None  # (M, 8) uint8 records, or None when the level has no grid
    light_grid_layout: LightGridLayout
    cluster_count: int

    @property
    def worldspawn(self) -> dict[str, str]:
        return self.entities[0] if self.entities else {}

    @property
    def world_mins(self) -> np.ndarray:
        return self.models["mins"][0].astype(np.float64)

    @property
    def world_maxs(self) -> np.ndarray:
        return self.models["maxs"][0].astype(np.float64)

    def shader_name(self, index: int) -> str:
        return self.shaders["name"][index].decode("latin-1")


def read_bsp(data: bytes, name: str) -> Bsp:
    """Parse and validate a whole IBSP v46 file held in memory; `name` is used in error messages."""
    lumps = _read_directory(data, name)

    def records(lump: int) -> np.ndarray:
        offset, length = lumps[lump]
        return np.frombuffer(data, dtype=RECORD_DTYPES[lump], count=length // RECORD_DTYPES[lump].itemsize,
                             offset=offset)

    for lump in REQUIRED_LUMPS:
        if lumps[lump][1] == 0:
            raise BspError(f"{_lump(name, lump)}: is empty; a level needs at least one record")

    entity_offset, entity_length = lumps[ENTITIES]
    entity_text = bytes(data[entity_offset:entity_offset + entity_length]).split(b"\0", 1)[0].decode("latin-1")
    entities = parse_entities(entity_text, name)

    shaders, planes, nodes, leafs = records(SHADERS), records(PLANES), records(NODES), records(LEAFS)
    leaf_surfaces, leaf_brushes, models = records(LEAF_SURFACES), records(LEAF_BRUSHES), records(MODELS)
    brushes, brush_sides, vertices = records(BRUSHES), records(BRUSH_SIDES), records(VERTICES)
    mesh_verts, fogs, faces = records(MESH_VERTS), records(FOGS), records(FACES)
    cluster_count = _read_visibility(data, lumps[VISIBILITY], name)

    _check_finite(name, PLANES, "normal/dist", np.column_stack([planes["normal"], planes["dist"]]))
    _check_finite(name, VERTICES, "position", vertices["position"])
    _check_finite(name, MODELS, "mins/maxs", np.column_stack([models["mins"], models["maxs"]]))
    _check_faces(name, faces, len(shaders), len(vertices), mesh_verts)
    _check_tree(name, nodes, leafs, len(planes), len(leaf_surfaces), len(leaf_brushes), cluster_count)
    _check_indices(name, LEAF_SURFACES, "face", leaf_surfaces, len(faces))
    _check_indices(name, LEAF_BRUSHES, "brush", leaf_brushes, len(brushes))
    _check_spans(name, MODELS, "surfaces", models["first_surface"], models["num_surfaces"], len(faces))
    _check_spans(name, MODELS, "brushes", models["first_brush"], models["num_brushes"], len(brushes))
    _check_spans(name, BRUSHES, "sides", brushes["first_side"], brushes["num_sides"], len(brush_sides))
    _check_indices(name, BRUSHES, "shader", brushes["shader"], len(shaders))
    _check_indices(name, BRUSH_SIDES, "plane", brush_sides["plane"], len(planes))
    _check_indices(name, BRUSH_SIDES, "shader", brush_sides["shader"], len(shaders))

    layout = _light_grid_layout(name, entities, models)
    grid_length = lumps[LIGHT_GRID][1]
    light_grid = None
    if grid_length:
        if grid_length != LIGHT_GRID_RECORD_BYTES * layout.point_count:
            raise BspError(
                f"{_lump(name, LIGHT_GRID)}: {grid_length:,} bytes, but the world bounds and gridsize "
                f"{_fmt(layout.cell_size)} give a {'x'.join(str(int(d)) for d in layout.dims)} grid "
                f"= {LIGHT_GRID_RECORD_BYTES * layout.point_count:,} bytes (the engine would drop this grid)"
            )
        light_grid = records(LIGHT_GRID)

    return Bsp(
        name=name, entities=entities, shaders=shaders, planes=planes, nodes=nodes, leafs=leafs,
        leaf_surfaces=leaf_surfaces, leaf_brushes=leaf_brushes, models=models, brushes=brushes,
        brush_sides=brush_sides, vertices=vertices, mesh_verts=mesh_verts, fogs=fogs, faces=faces,
        lightmap_count=lumps[LIGHTMAPS][1] // LIGHTMAP_BYTES,
        lightmaps=records(LIGHTMAPS).reshape(-1, LIGHTMAP_SIDE, LIGHTMAP_SIDE, 3), light_grid=light_grid, light_grid_layout=layout,
        cluster_count=cluster_count,
    )


# ------------------------------------------------------------------------------------------ header

def _lump(name: str, lump: int) -> str:
    return f"{name}: lump {lump} ({LUMP_NAMES[lump]})"


def _fmt(values: np.ndarray) -> str:
    return " ".join(f"{float(v):g}" for v in values)


def _read_directory(data: bytes, name: str) -> list[tuple[int, int]]:
    if len(data) < HEADER_BYTES:
        raise BspError(f"{name}: file is {len(data):,} bytes, shorter than the {HEADER_BYTES}-byte IBSP header (truncated?)")
    header = np.frombuffer(data, dtype=HEADER_DTYPE, count=1)[0]
    magic = bytes(data[:4])
    if magic != MAGIC:
        raise BspError(f"{name}: byte 0: magic is {magic!r}, expected {MAGIC!r} (not a Quake III BSP)")
    version = int(header["version"])
    if version != VERSION:
        raise BspError(f"{name}: byte 4: BSP version {version}, expected {VERSION} (Quake III / OpenArena IBSP)")
    lumps: list[tuple[int, int]] = []
    for lump, (offset, length) in enumerate(header["lumps"].tolist()):
        where = _lump(name, lump)
        if length < 0 or offset < 0:
            raise BspError(f"{where}: offset {offset:,} / length {length:,} is negative")
        if length and offset < HEADER_BYTES:
            raise BspError(f"{where}: offset {offset:,} overlaps the {HEADER_BYTES}-byte header")
        if offset + length > len(data):
            raise BspError(f"{where}: bytes {offset:,}..{offset + length:,} run past the end of the "
                           f"{len(data):,}-byte file (truncated?)")
        dtype = RECORD_DTYPES.get(lump)
        if dtype is not None and length % dtype.itemsize:
            raise BspError(f"{where}: length {length:,} is not a multiple of its {dtype.itemsize}-byte record")
        lumps.append((offset, length))
    return lumps


def _read_visibility(data: bytes, lump: tuple[int, int], name: str) -> int:
    """Number of clusters (0 when the level has no visibility data)."""
    offset, length = lump
    if length == 0:
        return 0
    if length < 8:
        raise BspError(f"{_lump(name, VISIBILITY)}: {length} bytes, shorter than its 8-byte header")
    clusters, bytes_per_cluster = (int(v) for v in np.frombuffer(data, dtype="<i4", count=2, offset=offset))
    if clusters < 0 or bytes_per_cluster < 0 or 8 + clusters * bytes_per_cluster > length:
        raise BspError(f"{_lump(name, VISIBILITY)}: {clusters:,} clusters x {bytes_per_cluster:,} bytes do not fit "
                       f"in its {length:,} bytes")
    return clusters


# ------------------------------------------------------------------------------------- validation

def _check_finite(name: str, lump: int, field: str, values: np.ndarray) -> None:
    bad = np.flatnonzero(~np.isfinite(values).all(axis=-1))
    if bad.size:
        raise BspError(f"{_lump(name, lump)}: record {int(bad[0])}: field '{field}' is not finite "
                       f"({bad.size:,} such records)")


def _first_bad(name: str, lump: int, field: str, values: np.ndarray, bad: np.ndarray, rule: str) -> None:
    where = np.flatnonzero(bad)
    if where.size:
        record = int(where[0])
        raise BspError(f"{_lump(name, lump)}: record {record}: field '{field}' = {values[record]} {rule}")


def _check_indices(name: str, lump: int, field: str, values: np.ndarray, count: int) -> None:
    values = np.asarray(values, dtype=np.int64)
    _first_bad(name, lump, field, values, (values < 0) | (values >= count), f"is outside [0, {count})")


def _check_spans(name: str, lump: int, what: str, first: np.ndarray, number: np.ndarray, count: int) -> None:
    """Ranges [first, first + number) must lie inside a lump of `count` records."""
    first = np.asarray(first, dtype=np.int64)
    number = np.asarray(number, dtype=np.int64)
    _first_bad(name, lump, f"num {what}", number, number < 0, "is negative")
    _first_bad(name, lump, f"first {what}", first, (first < 0) | (first + number > count),
               f"(+ {what} count) is outside the {count:,} records it indexes")


def _check_faces(name: str, faces: np.ndarray, shaders: int, vertices: int, mesh_verts: np.ndarray) -> None:
    # Fields the importer never reads (fog, lightmap page) are not checked: shipped levels carry
    # stale values there that the engine tolerates (aggressor: fog 0 with an empty fogs lump).
    kind = faces["type"]
    _first_bad(name, FACES, "type", kind, ~np.isin(kind, list(FACE_TYPE_NAMES)), "is not 1..4")
    _check_indices(name, FACES, "shader", faces["shader"], shaders)
    _check_spans(name, FACES, "verts", faces["first_vert"], faces["num_verts"], vertices)
    _check_spans(name, FACES, "indexes", faces["first_index"], faces["num_indexes"], len(mesh_verts))

    indexed = (kind == FACE_POLYGON) | (kind == FACE_MESH)
    _first_bad(name, FACES, "num indexes", faces["num_indexes"], indexed & (faces["num_indexes"] % 3 != 0),
               "is not a multiple of 3 (triangles)")
    # Every index of a polygon/mesh must address one of that face's own vertices.
    owners = np.flatnonzero(indexed)
    counts = faces["num_indexes"][owners].astype(np.int64)
    owner_of_index = np.repeat(owners, counts)
    index_positions = concatenated_ranges(faces["first_index"][owners], counts)
    local = mesh_verts[index_positions].astype(np.int64)
    bad = (local < 0) | (local >= faces["num_verts"][owner_of_index])
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        face = int(owner_of_index[k])
        raise BspError(f"{_lump(name, MESH_VERTS)}: record {int(index_positions[k])}: index {int(local[k])} of face "
                       f"{face} is outside its {int(faces['num_verts'][face])} vertices")

    patch = kind == FACE_PATCH
    width, height = faces["patch_width"].astype(np.int64), faces["patch_height"].astype(np.int64)
    for field, side in (("patch width", width), ("patch height", height)):
        _first_bad(name, FACES, field, side, patch & ((side < 3) | (side > MAX_PATCH_SIDE) | (side % 2 == 0)),
                   f"is not an odd number in [3, {MAX_PATCH_SIDE}] (patch control grid)")
    _first_bad(name, FACES, "num verts", faces["num_verts"], patch & (width * height != faces["num_verts"]),
               "is not patch width x height")


def _check_tree(name: str, nodes: np.ndarray, leafs: np.ndarray, planes: int, leaf_surfaces: int,
                leaf_brushes: int, clusters: int) -> None:
    _check_indices(name, NODES, "plane", nodes["plane"], planes)
    children = nodes["children"].astype(np.int64)
    bad = np.where(children >= 0, children >= len(nodes), -(children + 1) >= len(leafs))
    _first_bad(name, NODES, "children", nodes["children"], bad.any(axis=1),
               f"addresses a node >= {len(nodes):,} or a leaf >= {len(leafs):,}")
    _check_spans(name, LEAFS, "leaf surfaces", leafs["first_leaf_surface"], leafs["num_leaf_surfaces"], leaf_surfaces)
    _check_spans(name, LEAFS, "leaf brushes", leafs["first_leaf_brush"], leafs["num_leaf_brushes"], leaf_brushes)
    if clusters:
        _first_bad(name, LEAFS, "cluster", leafs["cluster"], leafs["cluster"] >= clusters,
                   f"is not below the {clusters:,} clusters of the visibility lump")


# -------------------------------------------------------------------------------------- light grid

def _light_grid_layout(name: str, entities: list[dict[str, str]], models: np.ndarray) -> LightGridLayout:
    """Grid placement as the renderer computes it (tr_bsp.c R_LoadLightGrid), from model 0's bounds."""
    worldspawn = entities[0] if entities else {}
    size = np.array(DEFAULT_GRID_SIZE)
    if "gridsize" in worldspawn:
        size = np.array(parse_vector(worldspawn["gridsize"], 3, f"{name}: worldspawn key 'gridsize'"))
        if (size <= 0).any():
            raise BspError(f"{name}: worldspawn key 'gridsize' = {worldspawn['gridsize']!r}: every size must be > 0")
    mins = models["mins"][0].astype(np.float64)
    maxs = models["maxs"][0].astype(np.float64)
    origin = size * np.ceil(mins / size)
    top = size * np.floor(maxs / size)
    dims = np.floor((top - origin) / size).astype(np.int64) + 1
    if (dims < 1).any() or math.prod(int(d) for d in dims) > MAX_LIGHT_GRID_POINTS:
        raise BspError(f"{name}: light grid of {'x'.join(str(int(d)) for d in dims)} points from world bounds "
                       f"{_fmt(mins)} .. {_fmt(maxs)} and gridsize {_fmt(size)} is empty or absurdly large")
    return LightGridLayout(origin=origin, cell_size=size, dims=dims)

