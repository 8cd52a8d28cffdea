"""The rig file: round trip, validation of hostile files, and a level's light entities as q3map2 reads them."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lpnn.lights.rig import Rig, RigError, SurfaceLight, entity_lights, read_rig, write_rig
from lpnn.scenes.coords import quake_to_unity
from lpnn.scenes.entities import parse_entities
from rig_files import edited_rig


def sample_rig() -> Rig:
    return Rig.from_quake(np.array([[64.0, 32.0, 128.0], [0.0, -40.0, 8.0]]), np.array([[0.5, 0.25, 0.0], [1.0, 1.0, 1.0]]),
                          np.array([300.0, 50.0]), ambient=np.array([4.0, 5.0, 6.0]), level="room", bsp_sha256="ab" * 32, scheme="mixed", objective=0.0125)


def test_round_trip_normalises_colour_and_converts_to_unity_metres(tmp_path: Path) -> None:
    rig = sample_rig()
    np.testing.assert_allclose(rig.colours[0], [1.0, 0.5, 0.0])  # largest component 1 ...
    assert rig.intensities[0] == pytest.approx(150.0)  # ... its scale moved into the intensity
    path = write_rig(tmp_path / "rig.json", rig)
    back = read_rig(path)
    np.testing.assert_allclose(back.positions, quake_to_unity(np.array([[64.0, 32.0, 128.0], [0.0, -40.0, 8.0]])), atol=1e-6)
    np.testing.assert_allclose(back.quake_positions(), [[64.0, 32.0, 128.0], [0.0, -40.0, 8.0]], atol=1e-4)
    np.testing.assert_allclose(back.intensities, [150.0, 50.0])
    np.testing.assert_allclose(back.ambient, [4.0, 5.0, 6.0])
    assert (back.level, back.scheme, back.objective, back.bsp_sha256) == ("room", "mixed", 0.0125, "ab" * 32)
    document = json.loads(path.read_text())
    assert document["format"] == "lpnn-light-rig" and document["falloff"] == "q3map2-point"


@pytest.mark.parametrize("change, message", [
    (lambda d: d["lights"][1].update(intensity=-5.0), r"light 1: intensity -5\.0 must be a finite number >= 0"),
    (lambda d: d["lights"][0].update(intensity=float("nan")), r"light 0: intensity nan must be a finite number"),
    (lambda d: d["lights"][0].update(color=[1.0, 2.0, 0.0]), r"light 0: color \[1\.0, 2\.0, 0\.0\] must be 3 numbers in \[0, 1\]"),
    (lambda d: d["lights"][0].update(position=[1.0, "x", 0.0]), r"light 0: 'position' = \[1\.0, 'x', 0\.0\] is not 3 number"),
    (lambda d: d["lights"][0].pop("intensity"), r"light 0: 'intensity' = \[None\] is not 1 number"),
    (lambda d: d.update(lights=[]), r"'lights' must be a list of lights, non-empty unless 'surfaces' has"),
    (lambda d: d["lights"][0].update(type="sun"), r"light 0: 'type' = 'sun' is not 'point' or 'spot'"),
    (lambda d: d["lights"][0].update(type="spot"), r"light 0: 'direction' = None is not 3 number"),
    (lambda d: d["lights"][0].update(type="spot", direction=[0.0, 2.0, 0.0], radius_by_dist=0.5),
     r"light 0: direction \[0\.0, 2\.0, 0\.0\] must be a unit vector"),
    (lambda d: d["lights"][0].update(type="spot", direction=[0.0, 1.0, 0.0], radius_by_dist=0.0),
     r"light 0: 'radius_by_dist' = 0\.0 must be > 0 for a spotlight"),
    (lambda d: d.update(surfaces=[{"shader": "textures/a/b", "value": -1.0, "color": [1, 1, 1]}]),
     r"surface light 0 \(textures/a/b\): value -1\.0 must be a finite number >= 0"),
    (lambda d: d.update(surfaces=[{"value": 10.0, "color": [1, 1, 1]}]), r"surface light 0 = .* is not an object with a shader"),
    (lambda d: d.update(surfaces=[{"shader": "s", "value": 10.0, "color": [1, 3, 1]}]),
     r"surface light 0 \(s\): color \[1\.0, 3\.0, 1\.0\] must be 3 numbers in \[0, 1\]"),
    (lambda d: d.update(surfaces=[{"shader": "s", "value": 10.0, "color": [1, 1, 1], "subdivide": 0}]),
     r"surface light 0 \(s\): subdivide 0\.0 must be a finite number > 0"),
    (lambda d: d.update(surfaces=[{"shader": "s", "value": 10.0, "color": [1, 1, 1], "two_sided": "yes"}]),
     r"surface light 0: 'two_sided' = 'yes' must be true or false"),
    (lambda d: d.update(surfaces=[{"shader": "s", "value": 10.0, "color": [1, 1, 1], "backsplash": [-1, 23]}]),
     r"surface light 0 \(s\): backsplash \[-1\.0, 23\.0\] must be 2 finite numbers >= 0"),
    (lambda d: d.update(ambient=[1.0, -2.0, 0.0]), r"ambient \[1\.0, -2\.0, 0\.0\] must be 3 numbers in \[0, 255\]"),
    (lambda d: d.pop("ambient"), r"'ambient' = None is not 3 number"),
    (lambda d: d.update(format="something"), r"not a light rig"),
    (lambda d: d.update(version=9), r"rig version 9 is not supported"),
], ids=["negative", "nan", "colour", "position", "missing", "empty", "type", "spot without direction",
        "spot direction", "spot cone", "surface value", "surface shader", "surface colour", "surface subdivide",
        "surface two-sided", "surface backsplash", "negative ambient",
        "no ambient", "format", "version"])
def test_hostile_rig_files_are_rejected_with_the_value(tmp_path: Path, change, message: str) -> None:
    with pytest.raises(RigError, match=message):
        read_rig(edited_rig(tmp_path, sample_rig(), change))


def test_a_version_1_rig_is_still_read(tmp_path: Path) -> None:
    """Written by hand as version 1 wrote them (lights.md §5 of that version): point lights, no types."""
    path = tmp_path / "old.json"
    path.write_text(json.dumps({
        "format": "lpnn-light-rig", "version": 1, "level": "room", "bsp_sha256": "cd" * 32,
        "units": {"position": "m, Unity axes", "intensity": "q3map2 light"}, "falloff": "q3map2-point",
        "scheme": "mixed", "objective": 0.25, "ambient": [1.0, 2.0, 3.0],
        "lights": [{"position": [0.5, 1.0, -2.0], "color": [1.0, 0.5, 0.25], "intensity": 120.0},
                   {"position": [1.5, 2.0, 2.0], "color": [1.0, 1.0, 1.0], "intensity": 80.0}],
        "info": {"grid": [8, 8, 3]}}))
    rig = read_rig(path)
    assert rig.count == 2 and not rig.spot.any() and rig.surfaces == [] and rig.point_lights_only
    np.testing.assert_allclose(rig.positions[0], [0.5, 1.0, -2.0])
    np.testing.assert_allclose(rig.intensities, [120.0, 80.0])
    again = json.loads(write_rig(tmp_path / "new.json", rig).read_text())
    assert again["version"] == 4 and [light["type"] for light in again["lights"]] == ["point", "point"]


def test_spotlights_and_surface_lights_round_trip(tmp_path: Path) -> None:
    rig = sample_rig()
    rig.spot_directions = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 0.0]])
    rig.radius_by_dist = np.array([0.25, 0.0])
    rig.surfaces = [SurfaceLight("textures/base_light/ceil1_22a", 2500.0, np.array([1.0, 0.9, 0.7]))]
    back = read_rig(write_rig(tmp_path / "rig.json", rig))
    assert back.spot.tolist() == [True, False] and not back.point_lights_only
    np.testing.assert_allclose(back.spot_directions[0], [0.0, -1.0, 0.0])
    assert back.radius_by_dist[0] == pytest.approx(0.25)
    assert [(s.shader, s.value) for s in back.surfaces] == [("textures/base_light/ceil1_22a", 2500.0)]
    np.testing.assert_allclose(back.surfaces[0].colour, [1.0, 0.9, 0.7])
    # a rig of surface lights only is a rig
    only = Rig(positions=np.zeros((0, 3)), colours=np.zeros((0, 3)), intensities=np.zeros(0), surfaces=rig.surfaces)
    assert read_rig(write_rig(tmp_path / "only.json", only)).surfaces[0].value == 2500.0


def test_surface_light_settings_round_trip_and_older_files_read_q3map2s_defaults(tmp_path: Path) -> None:
    """Version 4 keeps q3map2's settings of a surface light besides its value (what its emitters were built with);
    a version 3 file has none, and reads q3map2's defaults (q3map_lightSubdivide 999, one-sided, backsplash 5 % at 23
    units) even where a later key is present."""
    rig = sample_rig()
    rig.surfaces = [SurfaceLight("textures/sfx/flame2", 3787.0, np.array([1.0, 0.45, 0.08]), subdivide=256.0,
                                 two_sided=True, backsplash_fraction=0.1, backsplash_distance=8.0)]
    path = write_rig(tmp_path / "rig.json", rig)
    back = read_rig(path).surfaces[0]
    assert (back.subdivide, back.two_sided, back.backsplash_fraction, back.backsplash_distance) == (256.0, True, 0.1, 8.0)
    document = json.loads(path.read_text())
    document["version"] = 3
    path.write_text(json.dumps(document))
    old = read_rig(path).surfaces[0]
    assert (old.value, old.subdivide, old.two_sided, old.backsplash_fraction, old.backsplash_distance) == \
        (3787.0, 999.0, False, 0.05, 23.0)


def test_unreadable_rig_files(tmp_path: Path) -> None:
    (tmp_path / "bad.json").write_text("{ not json")
    with pytest.raises(RigError, match=r"bad\.json: not JSON"):
        read_rig(tmp_path / "bad.json")
    with pytest.raises(RigError, match=r"absent\.json: cannot read the rig"):
        read_rig(tmp_path / "absent.json")


def test_writing_an_invalid_rig_is_refused_and_leaves_no_file(tmp_path: Path) -> None:
    rig = sample_rig()
    rig.intensities[0] = np.nan
    with pytest.raises(RigError, match="intensity nan"):
        write_rig(tmp_path / "rig.json", rig)
    assert not (tmp_path / "rig.json").exists()


def test_light_entities_as_q3map2_reads_them() -> None:
    text = ('{\n"classname" "worldspawn"\n"_ambient" "0"\n"ambient" "20"\n"_color" "1 0.5 0"\n}\n'
            '{\n"classname" "light"\n"origin" "10 20 30"\n}\n'  # no intensity: 300
            '{\n"classname" "light"\n"origin" "0 0 64"\n"_light" "200"\n"light" "999"\n"scale" "1.5"\n"_color" "0.5 0.25 0"\n"spawnflags" "1"\n}\n'
            '{\n"classname" "light"\n"origin" "0 0 0"\n"light" "-100"\n}\n'  # subtractive
            '{\n"classname" "light"\n"origin" "0 0 0"\n"_sun" "1"\n"target" "t"\n}\n'
            '{\n"classname" "lightJunior"\n"origin" "5 5 5"\n"light" "100"\n}\n'
            '{\n"classname" "light"\n"origin" "1 2 3"\n"light" "0"\n"scale" "-1"\n}\n')
    found = entity_lights(parse_entities(text, "t.bsp"), "t")
    np.testing.assert_allclose(found.rig.intensities, [300.0, 300.0])  # _light first, x scale
    np.testing.assert_allclose(found.rig.colours[1], [1.0, 0.5, 0.0])
    np.testing.assert_allclose(found.rig.quake_positions()[0], [10, 20, 30], atol=1e-9)
    assert found.linear.tolist() == [False, True]
    np.testing.assert_allclose(found.rig.ambient, [20, 10, 0])  # `ambient` as `_ambient` is 0, x _color
    assert found.skipped == {"sun": 1, "negative or zero": 2, "no origin": 0, "grid only (lightJunior)": 1}


def test_a_spotlight_entity_keeps_its_cone_in_unity_axes() -> None:
    text = ('{\n"classname" "worldspawn"\n}\n'
            '{\n"classname" "light"\n"origin" "0 0 128"\n"target" "t1"\n"radius" "48"\n}\n'
            '{\n"classname" "target_position"\n"targetname" "t1"\n"origin" "0 100 128"\n}\n')
    found = entity_lights(parse_entities(text, "t.bsp"), "t")
    assert found.rig.spot.tolist() == [True]
    # Quake +y is Unity -x (scenes/coords.py); radiusByDist = (48 + 16) / 100
    np.testing.assert_allclose(found.rig.spot_directions[0], [-1.0, 0.0, 0.0], atol=1e-12)
    assert found.rig.radius_by_dist[0] == pytest.approx(0.64)
