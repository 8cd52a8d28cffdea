"""The IBSP reader on in-memory files: what it reads, and every way it refuses a damaged file."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

from lpnn.scenes.bsp import read_bsp
from lpnn.scenes.entities import light_entities, parse_entities
from lpnn.scenes.errors import BspError
from lpnn.scenes import levels
from lpnn.scenes.levels import PAK_ENV, load_level
from synthetic_bsp import make_level, set_lump, write_pk3

NAME = "synthetic.bsp"
FACES, VERTICES, VISIBILITY, LIGHT_GRID, MODELS = 13, 10, 16, 15, 7


def refuse(data: bytes, *fragments: str) -> str:
    with pytest.raises(BspError) as caught:
        read_bsp(data, NAME)
    message = str(caught.value)
    assert message.startswith(NAME), message
    for fragment in fragments:
        assert fragment in message, message
    return message


# ---------------------------------------------------------------------------------------- reading

def test_reads_every_lump_of_a_valid_level(level_bytes: bytes) -> None:
    bsp = read_bsp(level_bytes, NAME)
    assert [bsp.shader_name(i) for i in range(3)] == ["textures/test/wall", "textures/test/sky", "textures/test/glass"]
    assert bsp.shaders["surface_flags"].tolist() == [0, 4, 0]
    assert len(bsp.planes) == 7 and bsp.planes["dist"][6] == 192
    assert bsp.nodes["children"].tolist() == [[-2, -1]]
    assert bsp.leafs["cluster"].tolist() == [0, -1]
    assert bsp.brushes.tolist() == [(0, 6, 0)]
    assert bsp.faces["type"].tolist() == [1, 1, 1, 2, 4]
    patch = bsp.faces[3]
    assert (patch["first_vert"], patch["num_verts"], patch["patch_width"], patch["patch_height"]) == (12, 9, 3, 3)
    assert bsp.vertices["position"][12 + 8].tolist() == [64.0, 64.0, 160.0]
    assert bsp.mesh_verts.tolist()[:6] == [0, 1, 2, 0, 2, 3]
    assert bsp.world_mins.tolist() == [0, 0, 0] and bsp.world_maxs.tolist() == [256, 256, 256]
    assert bsp.cluster_count == 1


def test_light_grid_layout_follows_world_bounds_and_gridsize(level_bytes: bytes) -> None:
    layout = read_bsp(level_bytes, NAME).light_grid_layout
    assert layout.dims.tolist() == [5, 5, 3]
    assert layout.origin.tolist() == [0, 0, 0]
    assert layout.cell_size.tolist() == [64, 64, 128]
    assert layout.maxs.tolist() == [256, 256, 256]


def test_gridsize_key_changes_the_grid() -> None:
    level = make_level()
    level.entities = level.entities.replace('"gridsize" "64 64 128"', '"gridsize" "128 128 256"')
    level.light_grid = bytes(8 * 3 * 3 * 2)  # origin 0, top 256: 3 x 3 x 2 cells
    bsp = read_bsp(level.to_bytes(), NAME)
    assert bsp.light_grid_layout.dims.tolist() == [3, 3, 2]
    assert bsp.light_grid.shape == (18, 8)


def test_entities_and_lights(level_bytes: bytes) -> None:
    bsp = read_bsp(level_bytes, NAME)
    assert bsp.worldspawn["message"] == "synthetic // not a comment"
    lights = light_entities(bsp.entities)
    assert [e["classname"] for e in lights] == ["light", "lightJunior"]
    assert lights[0]["origin"] == "100 100 100"


@pytest.mark.parametrize("text, fragment", [
    ('{ "classname" "worldspawn" ', "not closed"),
    ('{ "classname" "worldspawn" } }', "without an open entity"),
    ('{ "classname" "worldspawn" { }', "inside entity 0"),
    ('{ "classname" }', "has no value"),
    ('{ "classname" "world', "unterminated"),
    ('"key" "value"', "outside an entity"),
])
def test_malformed_entities_are_refused(text: str, fragment: str) -> None:
    with pytest.raises(BspError, match=fragment):
        parse_entities(text, NAME)


def test_a_level_without_light_grid_still_reads() -> None:
    level = make_level()
    level.light_grid = b""
    assert read_bsp(level.to_bytes(), NAME).light_grid is None


# --------------------------------------------------------------------------------- header errors

def test_truncated_header(level_bytes: bytes) -> None:
    refuse(level_bytes[:100], "100 bytes", "shorter than the 144-byte IBSP header")


def test_truncated_body(level_bytes: bytes) -> None:
    refuse(level_bytes[: len(level_bytes) // 2], "run past the end", "truncated?")


def test_wrong_magic() -> None:
    level = make_level()
    level.magic = b"VBSP"
    refuse(level.to_bytes(), "magic is b'VBSP'", "not a Quake III BSP")


def test_zip_given_as_bsp(level_bytes: bytes) -> None:
    refuse(b"PK\x03\x04" + level_bytes[4:], "magic is b'PK\\x03\\x04'")


def test_wrong_version() -> None:
    level = make_level()
    level.version = 47
    refuse(level.to_bytes(), "byte 4: BSP version 47, expected 46")


def test_lump_outside_the_file(level_bytes: bytes) -> None:
    refuse(set_lump(level_bytes, FACES, offset=len(level_bytes)), "lump 13 (surfaces)", "run past the end")


def test_negative_lump_length(level_bytes: bytes) -> None:
    refuse(set_lump(level_bytes, VERTICES, length=-44), "lump 10 (drawverts)", "negative")


def test_lump_overlapping_the_header(level_bytes: bytes) -> None:
    refuse(set_lump(level_bytes, FACES, offset=16), "lump 13 (surfaces)", "overlaps the 144-byte header")


def test_lump_length_not_a_record_multiple(level_bytes: bytes) -> None:
    refuse(set_lump(level_bytes, FACES, length=105), "lump 13 (surfaces)", "length 105", "104-byte record")


def test_empty_required_lump(level_bytes: bytes) -> None:
    refuse(set_lump(level_bytes, MODELS, length=0), "lump 7 (models)", "is empty")


# --------------------------------------------------------------------------------- record errors

def test_absurd_vertex_count() -> None:
    level = make_level()
    level.faces[0]["num_verts"] = 10**9
    refuse(level.to_bytes(), "lump 13 (surfaces)", "record 0", "first verts")


def test_negative_index_count() -> None:
    level = make_level()
    level.faces[1]["num_indexes"] = -6
    refuse(level.to_bytes(), "lump 13 (surfaces)", "record 1", "num indexes", "negative")


def test_index_count_not_triangles() -> None:
    level = make_level()
    level.faces[0]["num_indexes"] = 5
    refuse(level.to_bytes(), "record 0", "num indexes", "multiple of 3")


def test_mesh_index_outside_its_face() -> None:
    level = make_level()
    level.mesh_verts[4] = 7  # face 0 has 4 vertices
    refuse(level.to_bytes(), "lump 11 (drawindexes)", "record 4", "index 7 of face 0", "4 vertices")


def test_bad_face_type_and_shader() -> None:
    level = make_level()
    level.faces[2]["type"] = 9
    refuse(level.to_bytes(), "record 2", "field 'type' = 9")
    level = make_level()
    level.faces[2]["shader"] = 3
    refuse(level.to_bytes(), "record 2", "field 'shader' = 3", "outside [0, 3)")


def test_absurd_patch_dimensions() -> None:
    level = make_level()
    level.faces[3]["patch_width"] = 1001
    refuse(level.to_bytes(), "record 3", "patch width", "1001", "odd number in [3, 65]")
    level = make_level()
    level.faces[3]["patch_height"] = 5
    refuse(level.to_bytes(), "record 3", "num verts", "patch width x height")


def test_node_child_outside_the_leaves() -> None:
    level = make_level()
    level.nodes = [(6, -5, -1)]
    refuse(level.to_bytes(), "lump 3 (nodes)", "record 0", "children")


def test_node_plane_out_of_range() -> None:
    level = make_level()
    level.nodes = [(70, -2, -1)]
    refuse(level.to_bytes(), "lump 3 (nodes)", "field 'plane' = 70", "outside [0, 7)")


def test_leaf_brush_range_and_index() -> None:
    level = make_level()
    level.leafs[0]["num_brushes"] = 4
    refuse(level.to_bytes(), "lump 4 (leafs)", "leaf brushes")
    level = make_level()
    level.leaf_brushes = [5]
    refuse(level.to_bytes(), "lump 6 (leafbrushes)", "field 'brush' = 5")


def test_brush_side_plane_out_of_range() -> None:
    level = make_level()
    level.brush_sides[2] = (99, 0)
    refuse(level.to_bytes(), "lump 9 (brushsides)", "record 2", "plane' = 99")


def test_leaf_cluster_beyond_visibility() -> None:
    level = make_level()
    level.leafs[0]["cluster"] = 3
    refuse(level.to_bytes(), "lump 4 (leafs)", "cluster", "1 clusters")


def test_absurd_visibility_header() -> None:
    level = make_level()
    level.visibility = (1, 8)
    data = bytearray(level.to_bytes())
    offset = int.from_bytes(data[8 + 8 * VISIBILITY: 12 + 8 * VISIBILITY], "little")
    data[offset:offset + 4] = (10**6).to_bytes(4, "little")
    refuse(bytes(data), "lump 16 (visibility)", "1,000,000 clusters")


def test_non_finite_vertex() -> None:
    level = make_level()
    level.vertices[2] = (float("nan"), 0.0, 0.0)
    refuse(level.to_bytes(), "lump 10 (drawverts)", "record 2", "not finite")


def test_light_grid_size_mismatch() -> None:
    level = make_level()
    level.light_grid = level.light_grid[:-8]
    refuse(level.to_bytes(), "lump 15 (lightgrid)", "592 bytes", "5x5x3", "600 bytes")


@pytest.mark.parametrize("value", ['"0 64 128"', '"64 64"', '"a b c"', '"64 64 nan"'])
def test_bad_gridsize(value: str) -> None:
    level = make_level()
    level.entities = level.entities.replace('"64 64 128"', value)
    refuse(level.to_bytes(), "gridsize")


def test_absurd_light_grid_from_world_bounds() -> None:
    level = make_level()
    level.models = [(0, 0, 0, 1e9, 1e9, 1e9, 0, 5, 0, 1)]
    refuse(level.to_bytes(), "light grid of", "absurdly large")


# ------------------------------------------------------------------------------------ locations

def test_loads_a_loose_bsp(bsp_path: Path) -> None:
    level = load_level(str(bsp_path))
    assert level.name == "synthetic" and level.pak is None
    assert len(level.sha256) == 64


def test_loads_a_pk3_member_and_a_map_name(tmp_path: Path, level_bytes: bytes, monkeypatch: pytest.MonkeyPatch) -> None:
    pak = write_pk3(tmp_path / "test.pk3", {"maps/Room.bsp": level_bytes, "maps/readme.txt": b"x"})
    level = load_level(f"{pak}:maps/room.bsp")  # member names match case-insensitively
    assert (level.name, level.location, level.pak) == ("Room", "test.pk3:maps/Room.bsp", pak)
    assert np.array_equal(level.bsp.light_grid, read_bsp(level_bytes, "x").light_grid)
    monkeypatch.setenv(PAK_ENV, str(pak))
    assert load_level("room").name == "Room"


def test_missing_member_lists_the_levels(tmp_path: Path, level_bytes: bytes) -> None:
    pak = write_pk3(tmp_path / "test.pk3", {"maps/a.bsp": level_bytes, "maps/b.bsp": level_bytes})
    with pytest.raises(BspError, match=r"has no member 'maps/c.bsp'; its levels are: a, b"):
        load_level(f"{pak}:maps/c.bsp")


def test_missing_and_broken_paks(tmp_path: Path) -> None:
    with pytest.raises(BspError, match="no such pak"):
        load_level(f"{tmp_path}/nothing.pk3:maps/a.bsp")
    broken = tmp_path / "broken.pk3"
    broken.write_bytes(b"not a zip")
    with pytest.raises(BspError, match="not a readable pk3"):
        load_level(f"{broken}:maps/a.bsp")
    with pytest.raises(BspError, match="cannot read the level"):
        load_level(str(tmp_path / "absent.bsp"))


def _deflated_pk3(path: Path, member: str, data: bytes) -> Path:
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        archive.writestr(member, data)
    return path


def test_a_member_declaring_more_than_the_cap_is_refused_unread(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A zip bomb: a small pk3 whose member inflates far beyond any real level is refused from its header."""
    monkeypatch.setattr(levels, "MAX_LEVEL_BYTES", 1 << 16)
    pak = _deflated_pk3(tmp_path / "bomb.pk3", "maps/x.bsp", bytes(1 << 20))
    assert pak.stat().st_size < 1 << 16  # the archive itself is small
    with pytest.raises(BspError, match=r"bomb.pk3:maps/x.bsp: declares 1,048,576 bytes, more than the 65,536 bytes"):
        load_level(f"{pak}:maps/x.bsp")
    loose = tmp_path / "big.bsp"
    loose.write_bytes(bytes((1 << 16) + 1))
    with pytest.raises(BspError, match=r"big.bsp: is 65,537 bytes, more than the 65,536 bytes"):
        load_level(str(loose))


def test_inflating_stops_at_the_cap_whatever_the_header_declares(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    pak = _deflated_pk3(tmp_path / "bomb.pk3", "maps/x.bsp", bytes(1 << 20))
    monkeypatch.setattr(levels, "MAX_LEVEL_BYTES", 1 << 16)
    with zipfile.ZipFile(pak) as archive:
        with pytest.raises(BspError, match=r"inflates to more than the 65,536 bytes .* declares 1,048,576"):
            levels._read_member_capped(archive, "maps/x.bsp", "bomb.pk3:maps/x.bsp")
