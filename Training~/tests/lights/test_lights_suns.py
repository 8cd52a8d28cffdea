"""Suns in rigs and fits (lights.md §3-5): the rig format's version 3 `suns`, a sun's light against hand-computed
values, its gradient against finite differences and the numpy reference, a fit that recovers a sun, the grid
re-lit from a rig's sun, the real-rig export and the probe baker's sun."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from lpnn.lights.compare import relight_grid
from lpnn.lights.emitters import Emitters, Suns
from lpnn.lights.model import ForwardModel, Lights
from lpnn.lights.optimise import Fitter, initial_intensity
from lpnn.lights.pipeline import real_rig, rig_suns
from lpnn.lights.relight import RigLighting
from lpnn.lights.bake import BakeScene, BakeSettings, bake_sh
from lpnn.lights.rig import Rig, RigError, Sun, SurfaceLight, entity_lights, read_rig, write_rig
from lpnn.lights.settings import SCHEMES
from lpnn.lights.shadows import shadow_raycaster
from lpnn.scenes.bsp import read_bsp
from lpnn.scenes.coords import quake_to_unity
from lpnn.scenes.lightgrid import LINEAR_PER_BYTE
from lpnn.scenes.raycast import EmbreeRaycaster
from rig_files import edited_rig
from gradient_checks import assert_close, finite_difference
from synthetic_bsp import make_level
from synthetic_room import box_walls, room_target

SKY_HEIGHT = 1000.0
YARD = 512.0


def sun_direction(azimuth: float, elevation: float) -> np.ndarray:
    """q3map_sun's direction toward the sun (shaders.c): (cos a cos e, sin a cos e, sin e), degrees."""
    a, e = math.radians(azimuth), math.radians(elevation)
    return np.array([math.cos(a) * math.cos(e), math.sin(a) * math.cos(e), math.sin(e)])


def yard(divisions: int = 24) -> tuple[np.ndarray, np.ndarray, np.ndarray, EmbreeRaycaster, EmbreeRaycaster]:
    """A ground of YARD x YARD units at z = 0 (normals up) with a 64 x 64 x 160 pillar in its middle (normals out),
    under a sky quad at SKY_HEIGHT: vertices, normals, triangles, the shadow casters and the sky."""
    t = np.linspace(0.0, YARD, divisions + 1)
    x, y = np.meshgrid(t, t, indexing="ij")
    ground = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    cells = np.array([(i * (divisions + 1) + j, (i + 1) * (divisions + 1) + j, (i + 1) * (divisions + 1) + j + 1,
                       i * (divisions + 1) + j + 1) for i in range(divisions) for j in range(divisions)])
    triangles = np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])
    pv, pn, pt = box_walls(np.array([224.0, 224.0, 0.0]), np.array([288.0, 288.0, 160.0]), 4, inward=False)
    vertices = np.concatenate([ground, pv])
    normals = np.concatenate([np.tile([0.0, 0.0, 1.0], (len(ground), 1)), pn])
    triangles = np.concatenate([triangles, pt + len(ground)])
    casters = EmbreeRaycaster(vertices, triangles, threads=1)
    sky_corners = np.array([[-4000.0, -4000.0, SKY_HEIGHT], [4000.0, -4000.0, SKY_HEIGHT], [4000.0, 4000.0, SKY_HEIGHT],
                            [-4000.0, 4000.0, SKY_HEIGHT]])
    sky = EmbreeRaycaster(sky_corners, np.array([[0, 1, 2], [0, 2, 3]]), threads=1)
    return vertices, normals, triangles, casters, sky


def sunny(direction: np.ndarray, colour=(1.0, 0.9, 0.7), intensity: float = 120.0, ambient=(10.0, 10.0, 10.0)) -> Lights:
    """No point light: one sun and the ambient."""
    return Lights(positions=np.zeros((0, 3)), colours=np.zeros((0, 3)), intensities=np.zeros(0),
                  ambient=np.array(ambient, dtype=float), sun_directions=np.array([direction], dtype=float),
                  sun_colours=np.array([colour], dtype=float), sun_intensities=np.array([intensity]))


def yard_model(lights: Lights) -> ForwardModel:
    """The yard's forward model whose target is the radiance of `lights` (sky rays and shadows included)."""
    vertices, normals, triangles, casters, sky = yard()
    albedo = 0.4 + 0.2 * vertices / YARD * np.array([1.0, 0.5, 0.25])
    blank = ForwardModel(room_target(vertices, normals, triangles, np.zeros_like(vertices), albedo), casters)
    blank.sky = sky
    radiance = blank.radiance_of(lights, blank.visibility(lights))
    model = ForwardModel(room_target(vertices, normals, triangles, radiance, albedo), casters)
    model.sky = sky
    return model


TRUE_SUN = sun_direction(30.0, 50.0)


def test_a_sun_lights_a_point_as_hand_computed() -> None:
    """LightContributionToSample, EMIT_SUN: colour x intensity x cos bytes where the sky is seen, on top of the
    ambient, times albedo x 4/255; nothing in the pillar's shadow or facing away."""
    model = yard_model(sunny(TRUE_SUN))
    lights = sunny(TRUE_SUN)
    radiance = model.radiance_of(lights, model.visibility(lights))
    open_ground = np.flatnonzero(np.all(model.points == [0.0, 0.0, 0.0], axis=1))[0]
    expected = model.albedo[open_ground] * LINEAR_PER_BYTE * (
        10.0 + np.array([1.0, 0.9, 0.7]) * 120.0 * math.sin(math.radians(50.0)))
    np.testing.assert_allclose(radiance[open_ground], expected, rtol=1e-12)
    # behind the pillar from the sun (the sun is toward +x +y): the ground at (208, 208) is in its shadow
    shadowed = np.flatnonzero(np.all(np.abs(model.points - [213.33333333, 213.33333333, 0.0]) < 1e-6, axis=1))[0]
    np.testing.assert_allclose(radiance[shadowed], model.albedo[shadowed] * LINEAR_PER_BYTE * 10.0, rtol=1e-12)
    # the pillar's side facing -x faces away from the sun
    away = np.flatnonzero((model.normals[:, 0] == -1.0))[0]
    np.testing.assert_allclose(radiance[away], model.albedo[away] * LINEAR_PER_BYTE * 10.0, rtol=1e-12)
    # the same model without a sky: a sun lights nothing
    model.sky = None
    dark = model.radiance_of(lights, model.visibility(lights))
    np.testing.assert_allclose(dark, model.albedo * LINEAR_PER_BYTE * 10.0, rtol=1e-12)


def test_the_suns_gradient_matches_finite_differences_and_the_numpy_reference() -> None:
    model = yard_model(sunny(TRUE_SUN))
    start = sunny(sun_direction(60.0, 70.0), colour=(0.8, 1.0, 0.9), intensity=90.0, ambient=(14.0, 12.0, 9.0))
    visible = model.visibility(start)
    analytic = model.objective(start, visible)
    assert_close(analytic, model.objective_numpy(start, visible), 1e-12,
                 ("sun_directions", "sun_colours", "sun_intensities", "ambient"))
    numeric = finite_difference(model, start, visible, {"sun_directions": 1e-6, "sun_colours": 1e-6,
                                                        "sun_intensities": 1e-4, "ambient": 1e-4})
    for name, values in numeric.items():
        got = getattr(analytic, name)
        assert np.max(np.abs(got - values)) <= 1e-5 * np.max(np.abs(values)), name


def test_a_fit_recovers_the_suns_direction_and_intensity() -> None:
    """A sun at azimuth 30, elevation 50 (its shadow and the cosine on the ground and the pillar say where it is)
    fitted from the best start of the closed-form fit over a few directions (optimise.sun_start_directions)."""
    truth = sunny(TRUE_SUN)
    model = yard_model(truth)
    start = initial_intensity(model, np.zeros((0, 3)), sun=True)
    assert start.sun_intensities[0] > 0
    assert math.degrees(math.acos(float(start.sun_directions[0] @ TRUE_SUN))) > 5.0  # the fit has to move it
    fitter = Fitter(model, (np.full(3, -100.0), np.full(3, 1000.0)), lambda p: np.ones(len(p), bool), model.points)
    result = fitter.fit(start, SCHEMES["mixed"])
    found = result.lights
    assert result.objective < 1e-6
    angle = math.degrees(math.acos(min(1.0, float(found.sun_directions[0] @ TRUE_SUN))))
    assert angle < 0.5
    emitted = found.sun_colours[0] * found.sun_intensities[0]
    np.testing.assert_allclose(emitted, np.array([1.0, 0.9, 0.7]) * 120.0, rtol=1e-3)
    np.testing.assert_allclose(found.ambient, [10.0, 10.0, 10.0], atol=0.05)


def sample_rig() -> Rig:
    rig = Rig.from_quake(np.array([[64.0, 32.0, 128.0]]), np.array([[1.0, 1.0, 1.0]]), np.array([300.0]),
                         ambient=np.array([4.0, 5.0, 6.0]), level="room", bsp_sha256="ab" * 32, scheme="mixed")
    rig.suns = [Sun.from_quake(sun_direction(30.0, 60.0), np.array([1.0, 1.0, 0.5]) / 1.5, 150.0)]
    return rig


def test_a_sun_from_a_q3map_sun_line_and_the_rig_round_trip(tmp_path: Path) -> None:
    """q3map_sun 1 1 0.5 150 30 60: the unit-length colour's largest component moves into the intensity, the
    direction goes to Unity axes; a version 3 file keeps both."""
    sun = sample_rig().suns[0]
    np.testing.assert_allclose(sun.colour, [1.0, 1.0, 0.5])
    assert sun.intensity == pytest.approx(150.0 / 1.5)
    np.testing.assert_allclose(sun.direction, quake_to_unity(sun_direction(30.0, 60.0)[None], scale=1.0)[0])
    np.testing.assert_allclose(sun.quake_direction(), sun_direction(30.0, 60.0), atol=1e-12)
    path = write_rig(tmp_path / "rig.json", sample_rig())
    document = json.loads(path.read_text())
    assert document["version"] == 4 and len(document["suns"]) == 1
    back = read_rig(path)
    np.testing.assert_allclose(back.suns[0].direction, sun.direction, atol=1e-6)
    np.testing.assert_allclose(back.suns[0].colour, [1.0, 1.0, 0.5])
    assert back.suns[0].intensity == pytest.approx(100.0, abs=1e-4) and not back.point_lights_only
    only = Rig(positions=np.zeros((0, 3)), colours=np.zeros((0, 3)), intensities=np.zeros(0), suns=back.suns)
    assert len(read_rig(write_rig(tmp_path / "only.json", only)).suns) == 1  # a rig of a sun only is a rig


def test_a_version_2_rig_is_still_read_and_its_suns_key_is_not_its_own(tmp_path: Path) -> None:
    document = json.loads(write_rig(tmp_path / "rig.json", sample_rig()).read_text())
    document["version"] = 2
    (tmp_path / "v2.json").write_text(json.dumps(document))
    rig = read_rig(tmp_path / "v2.json")
    assert rig.suns == [] and rig.count == 1


@pytest.mark.parametrize("change, message", [
    (lambda d: d["suns"][0].update(direction=[0.0, 2.0, 0.0]),
     r"rig\.json: sun 0: direction \[0\.0, 2\.0, 0\.0\] must be a unit vector"),
    (lambda d: d["suns"][0].update(direction=[0.0, "up", 0.0]), r"rig\.json: sun 0: 'direction' = \[0\.0, 'up', 0\.0\] is not 3"),
    (lambda d: d["suns"][0].update(color=[1.0, 1.5, 0.0]), r"rig\.json: sun 0: color \[1\.0, 1\.5, 0\.0\] must be 3 numbers in \[0, 1\]"),
    (lambda d: d["suns"][0].update(intensity=-3.0), r"rig\.json: sun 0: intensity -3\.0 must be a finite number >= 0"),
    (lambda d: d["suns"][0].pop("intensity"), r"rig\.json: sun 0: 'intensity' = \[None\] is not 1 number"),
    (lambda d: d.update(suns=[5]), r"rig\.json: sun 0 = 5 is not an object with direction, color and intensity"),
    (lambda d: d.update(suns={"direction": [0, 1, 0]}), r"rig\.json: 'suns' = .* must be a list of suns"),
    (lambda d: d.update(lights=[], suns=[]), r"'lights' must be a list of lights, non-empty unless .* 'suns' has suns"),
], ids=["direction", "direction type", "colour", "intensity", "missing", "not an object", "not a list", "empty"])
def test_hostile_suns_are_rejected_with_file_index_key_and_value(tmp_path: Path, change, message: str) -> None:
    with pytest.raises(RigError, match=message):
        read_rig(edited_rig(tmp_path, sample_rig(), change))


def test_the_grid_is_relit_from_a_rigs_sun_through_the_levels_sky() -> None:
    """The synthetic level's sky quad (z = 200) over an opaque quad (z = 128, x 64..192): a node beside the quad sees
    the sun overhead (colour x intensity, no cosine, along the sun), a node under it does not."""
    bsp = read_bsp(make_level().to_bytes(), "sky.bsp")
    rig = Rig(positions=np.zeros((0, 3)), colours=np.zeros((0, 3)), intensities=np.zeros(0), ambient=np.zeros(3),
              suns=[Sun.from_quake(np.array([0.0, 0.0, 1.0]), np.array([0.5, 1.0, 1.0]), 80.0)])
    suns = rig_suns(bsp, rig)
    assert suns.count == 1 and suns.sky is not None
    nodes = np.array([[230.0, 128.0, 150.0], [128.0, 128.0, 100.0]])
    grid = relight_grid(nodes, rig, shadow_raycaster(bsp), Emitters(suns=suns))
    lit = np.array([0.5, 1.0, 1.0]) * 80.0
    np.testing.assert_allclose(grid.directed[0], lit)  # one light: D = c, A = 0.125 D
    np.testing.assert_allclose(grid.ambient[0], 0.125 * lit)
    np.testing.assert_allclose(grid.direction[0], [0.0, 0.0, 1.0])
    np.testing.assert_allclose(grid.directed[1], 0.0)


def test_the_real_rig_export_holds_the_levels_suns(tmp_path: Path) -> None:
    level_bytes = make_level().to_bytes()
    from lpnn.scenes.levels import Level
    level = Level(name="sky", location="sky.bsp", pak=None, data=level_bytes, bsp=read_bsp(level_bytes, "sky.bsp"))
    real = entity_lights(level.bsp.entities, level.name)
    emitters = Emitters(suns=Suns(directions=np.array([sun_direction(0.0, 90.0)]), colours=np.array([[0.6, 0.8, 0.0]]),
                                  photons=np.array([155.0]), shader=np.array([1])))
    rig = read_rig(write_rig(tmp_path / "real.json", real_rig(level, real, emitters)))
    assert rig.count == 1 and rig.bsp_sha256 == level.sha256
    np.testing.assert_allclose(rig.suns[0].colour, [0.75, 1.0, 0.0])
    assert rig.suns[0].intensity == pytest.approx(155.0 * 0.8)
    np.testing.assert_allclose(rig.suns[0].quake_direction(), [0.0, 0.0, 1.0], atol=1e-6)


def test_the_probe_baker_bakes_a_sun_as_the_point_light_along_it_and_refuses_surface_lights(tmp_path: Path) -> None:
    """A sun's lobe at a probe is that of a point light straight along the sun's direction giving the same bytes
    (LightContributionToPoint, EMIT_SUN: no falloff); in the pillar's shadow it gives nothing. A rig with surface
    lights is refused, naming the file and what to do."""
    vertices, normals, triangles, casters, sky = yard(8)
    target = room_target(vertices, normals, triangles, np.zeros_like(vertices), np.full_like(vertices, 0.5))
    scene = BakeScene.build(target, triangles, casters, sky=sky)
    direction = TRUE_SUN
    rig = Rig(positions=np.zeros((0, 3)), colours=np.zeros((0, 3)), intensities=np.zeros(0), ambient=np.zeros(3),
              suns=[Sun.from_quake(direction, np.array([1.0, 0.9, 0.7]), 120.0)])
    open_point, shadowed = np.array([40.0, 40.0, 40.0]), np.array([200.0, 200.0, 40.0])  # the pillar is toward the sun
    baked = bake_sh(scene, rig, quake_to_unity(np.stack([open_point, shadowed])), BakeSettings(bounce=False)).sh
    distance = 500.0  # the point light 500 units along the sun's direction: 7500 I / r^2 = 120 bytes
    lamp = Rig.from_quake((open_point + distance * direction)[None], np.array([[1.0, 0.9, 0.7]]),
                          np.array([120.0 * distance ** 2 / 7500.0]), ambient=np.zeros(3))
    expected = bake_sh(scene, lamp, quake_to_unity(open_point[None]), BakeSettings(bounce=False)).sh[0]
    assert np.abs(expected).max() > 0
    np.testing.assert_allclose(baked[0], expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(baked[1], 0.0)
    with_surfaces = sample_rig()
    with_surfaces.surfaces = [SurfaceLight("textures/base_light/ceil1_22a", 2500.0, np.ones(3))]
    path = write_rig(tmp_path / "lamps.json", with_surfaces)
    with pytest.raises(RigError, match=r"lamps\.json: .*has 1 surface light\(s\) \(textures/base_light/ceil1_22a.*recover it "
                                       r"without --surfaces"):
        RigLighting.read(path)
    assert RigLighting.read(write_rig(tmp_path / "sunny.json", sample_rig())).rig.suns  # suns are baked
