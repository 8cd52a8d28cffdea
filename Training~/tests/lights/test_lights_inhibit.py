"""q3map2's inhibit radius on a lightmap sample's trace (emitters.SURFACE_INHIBIT_RADIUS, lights.md §3): an occluder
within 1.5 units of a shadow ray's origin is no hit (light_trace.c TraceTriangle: `depth <= trace->inhibitRadius`;
light_ydnar.c IlluminateRawLightmap sets q3map2.h's DEFAULT_INHIBIT_RADIUS), so a target point on the edge where a
wall meets its face sees the lights in front of it, and an occluder farther than that still shadows."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights import emitters as emitters_module
from lpnn.lights import model as model_module
from lpnn.lights.emitters import RAY_OFFSET, SURFACE_INHIBIT_RADIUS, AreaLights, Emitters, Suns, emitter_bytes
from lpnn.lights.model import ForwardModel, Lights
from lpnn.scenes.raycast import EmbreeRaycaster

from synthetic_room import ROOM_SIDE, room_geometry, room_target, wall_albedo

LIGHT = Lights(np.array([[100.0, 140.0, 180.0]]), np.ones((1, 3)), np.array([300.0]))
SKY_HEIGHT = 1000.0


def room_model() -> ForwardModel:
    """The closed box room of synthetic_room (no pillar), its own walls as the shadow casters."""
    vertices, normals, triangles = room_geometry(divisions=4, pillar=False)
    target = room_target(vertices, normals, triangles, np.zeros_like(vertices), wall_albedo(vertices))
    return ForwardModel(target, EmbreeRaycaster(vertices, triangles, threads=1))


def on_an_edge(points: np.ndarray) -> np.ndarray:
    """Points on two or more of the room's six walls: where a wall meets the face they belong to."""
    return (np.isclose(points, 0.0) | np.isclose(points, ROOM_SIDE)).sum(axis=1) >= 2


def facing(model: ForwardModel, position: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->i", position - model.points, model.normals) > 0


def without_inhibit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(model_module, "SURFACE_INHIBIT_RADIUS", 0.0)
    monkeypatch.setattr(emitters_module, "SURFACE_INHIBIT_RADIUS", 0.0)


def test_the_radius_is_q3map2s() -> None:
    assert SURFACE_INHIBIT_RADIUS == 1.5  # q3map2.h DEFAULT_INHIBIT_RADIUS


def test_every_point_of_a_closed_room_sees_a_light_in_front_of_it_edges_included() -> None:
    """Nothing stands between any wall and a light inside the room: the fitted lights' rays (both selections) and the
    fixed emitters' rays (a backsplash light is a point light among them) find every point in front of it lit."""
    model = room_model()
    in_front = facing(model, LIGHT.positions[0])
    edge = on_an_edge(model.points)
    assert (edge & in_front).sum() >= 20 and (~edge & in_front).sum() >= 20
    np.testing.assert_array_equal(model.visibility(LIGHT)[:, 0], in_front)
    np.testing.assert_array_equal(model.visibility_numpy(LIGHT)[:, 0], in_front)
    fixed = Emitters(splash_positions=LIGHT.positions, splash_colours=LIGHT.colours,
                     splash_intensities=LIGHT.intensities)
    lit = emitter_bytes(model.points, model.normals, fixed, model.raycaster)
    np.testing.assert_array_equal(lit, emitter_bytes(model.points, model.normals, fixed, None))
    assert np.all(lit[in_front] > 0)


def test_without_the_inhibit_radius_the_edges_are_in_shadow(monkeypatch: pytest.MonkeyPatch) -> None:
    """What the model did before: an edge point's ray starts 0.5 units off its face, on the plane of the wall it
    meets, and hits that wall at distance 0 — the dark quarter of kaos (lights.md §7). The faces' inner points are
    unaffected."""
    without_inhibit(monkeypatch)
    model = room_model()
    in_front = facing(model, LIGHT.positions[0])
    edge = on_an_edge(model.points)
    visible = model.visibility(LIGHT)[:, 0]
    assert visible[in_front & ~edge].all()
    assert visible[in_front & edge].mean() < 0.2


@pytest.mark.parametrize("depth, shadowed", [(1.0, False), (2.0, True)])
def test_an_occluder_is_no_hit_within_the_radius_and_shadows_beyond_it(depth: float, shadowed: bool) -> None:
    """A floor point under a small occluding quad `depth` units above its ray's origin (RAY_OFFSET off the floor), a
    light and an area light above both: TraceTriangle ignores the quad at 1 unit, not at 2."""
    floor = np.array([[-32.0, -32.0, 0.0], [32.0, -32.0, 0.0], [32.0, 32.0, 0.0], [-32.0, 32.0, 0.0], [0.0, 0.0, 0.0]])
    fan = np.array([[4, 0, 1], [4, 1, 2], [4, 2, 3], [4, 3, 0]])
    height = RAY_OFFSET + depth
    quad = np.array([[-4.0, -4.0, height], [4.0, -4.0, height], [4.0, 4.0, height], [-4.0, 4.0, height]])
    casters = EmbreeRaycaster(np.concatenate([floor, quad]),
                              np.concatenate([fan, np.array([[5, 6, 7], [5, 7, 8]])]), threads=1)
    normals = np.tile([0.0, 0.0, 1.0], (5, 1))
    model = ForwardModel(room_target(floor, normals, fan, np.zeros_like(floor), np.full((5, 3), 0.5)), casters)
    light = Lights(np.array([[0.0, 0.0, 100.0]]), np.ones((1, 3)), np.array([300.0]))
    centre = 4
    assert model.visibility(light)[centre, 0] == (not shadowed)
    panel = np.array([[8.0, -8.0, 100.0], [8.0, 8.0, 100.0], [-8.0, 8.0, 100.0]])  # wound to face down
    area = AreaLights(corners=panel[None], normals=np.array([[0.0, 0.0, -1.0]]), origins=np.array([[0.0, 0.0, 99.0]]),
                      areas=np.array([128.0]), add=np.array([750.0]), colours=np.ones((1, 3)),
                      two_sided=np.zeros(1, bool), shader=np.zeros(1, np.int64))
    lit = emitter_bytes(floor, normals, Emitters(areas=area), casters)[centre]
    assert (lit.max() == 0.0) == shadowed
    assert emitter_bytes(floor, normals, Emitters(areas=area), None)[centre].max() > 0.0


def test_a_sun_lights_the_foot_of_a_wall(monkeypatch: pytest.MonkeyPatch) -> None:
    """A floor (z = 0) meeting a wall (x = 0) under a sky, the sun up and away from the wall: the floor's points on the
    wall's line see the sky (fitted suns and fixed suns alike); without the radius their rays started on the wall."""
    floor = np.array([[0.0, 0.0, 0.0], [64.0, 0.0, 0.0], [64.0, 64.0, 0.0], [0.0, 64.0, 0.0]])
    wall = np.array([[0.0, 0.0, 0.0], [0.0, 64.0, 0.0], [0.0, 64.0, 64.0], [0.0, 0.0, 64.0]])
    two = np.array([[0, 1, 2], [0, 2, 3]])
    casters = EmbreeRaycaster(np.concatenate([floor, wall]), np.concatenate([two, two + 4]), threads=1)
    sky = EmbreeRaycaster(np.array([[-4000.0, -4000.0, SKY_HEIGHT], [4000.0, -4000.0, SKY_HEIGHT],
                                    [4000.0, 4000.0, SKY_HEIGHT], [-4000.0, 4000.0, SKY_HEIGHT]]), two, threads=1)
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    direction = np.array([0.5, 0.0, np.sqrt(0.75)])
    foot = floor[:, 0] == 0.0
    lights = Lights(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), sun_directions=direction[None],
                    sun_colours=np.ones((1, 3)), sun_intensities=np.array([100.0]))
    suns = Suns(directions=direction[None], colours=np.ones((1, 3)), photons=np.array([100.0]),
                shader=np.zeros(1, np.int64), sky=sky)

    def lit_points() -> tuple[np.ndarray, np.ndarray]:
        model = ForwardModel(room_target(floor, normals, two, np.zeros_like(floor), np.full((4, 3), 0.5)), casters)
        model.sky = sky
        fixed = emitter_bytes(floor, normals, Emitters(suns=suns), casters)
        return model.sun_visibility(lights)[:, 0], fixed.max(axis=1) > 0

    fitted, fixed = lit_points()
    assert foot.sum() == 2 and fitted.all() and fixed.all()
    without_inhibit(monkeypatch)
    fitted, fixed = lit_points()
    assert not fitted[foot].any() and not fixed[foot].any()
    assert fitted[~foot].all() and fixed[~foot].all()
