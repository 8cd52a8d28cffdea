"""The forward model: closed-form radiance, shadow rays, and the analytic gradient against finite differences."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights.model import LINEAR_SCALE, MIN_DISTANCE, ForwardModel, Lights
from gradient_checks import finite_difference
from synthetic_room import TRUE_LIGHTS, lit_room, room_geometry, room_target, wall_albedo


@pytest.fixture(scope="module")
def room() -> ForwardModel:
    return lit_room(TRUE_LIGHTS)[0]


def test_one_light_matches_the_q3map2_luxel_formula() -> None:
    vertices, normals, triangles = room_geometry(divisions=4, pillar=False)
    albedo = wall_albedo(vertices)
    model = ForwardModel(room_target(vertices, normals, triangles, np.zeros_like(vertices), albedo), raycaster=None)
    light = Lights(np.array([[100.0, 140.0, 180.0]]), np.array([[1.0, 0.5, 0.25]]), np.array([300.0]),
                   ambient=np.array([12.0, 6.0, 3.0]))
    radiance = model.radiance_of(light, model.visibility(light))
    offset = light.positions[0] - vertices
    distance = np.linalg.norm(offset, axis=1)
    cosine = np.maximum(0.0, np.einsum("ij,ij->i", offset, normals) / distance)
    # ambient + 7500 I cos / max(r, 16)^2 bytes (quake3-bsp.md §5), scaled down to a largest channel
    # of 255 keeping the hue, at 4/255 of full brightness a byte
    luxel = light.ambient + light.colours[0] * (7500 * 300 * cosine / np.maximum(distance, MIN_DISTANCE) ** 2)[:, None]
    saturated = luxel[:, 0] > 255  # red is the largest channel of this light and this ambient
    assert saturated.any() and (~saturated).any()
    luxel[saturated] *= 255 / luxel[saturated, :1]
    np.testing.assert_allclose(radiance, albedo * luxel * 4 / 255, rtol=1e-12)
    assert LINEAR_SCALE == pytest.approx(7500 * 4 / 255)


def test_the_pillar_casts_a_shadow(room: ForwardModel) -> None:
    light = Lights(np.array([[40.0, 128.0, 80.0]]), np.ones((1, 3)), np.array([300.0]))
    visible = room.visibility(light)[:, 0]
    floor_behind = (room.points[:, 2] == 0) & (room.points[:, 0] > 160) & (np.abs(room.points[:, 1] - 128) < 10)
    # not the floor's edge at x = 0: its vertex shares the wall, whose own ray starts on the floor
    floor_in_front = (room.points[:, 2] == 0) & (room.points[:, 0] > 10) & (room.points[:, 0] < 100) & (np.abs(room.points[:, 1] - 128) < 10)
    assert floor_behind.any() and floor_in_front.any()
    assert not visible[floor_behind].any()
    assert visible[floor_in_front].all()


def test_the_byte_clamp_saturates_near_a_light(room: ForwardModel) -> None:
    visible = room.visibility(TRUE_LIGHTS)
    light = room.radiance_of(TRUE_LIGHTS, visible) / room.albedo / (4 / 255)
    assert light.max() == pytest.approx(255.0)
    assert np.count_nonzero(np.isclose(light.max(axis=1), 255.0)) >= 4  # the ceiling above the first light


@pytest.mark.parametrize("near", [False, True], ids=["far", "within 16 units"])
def test_gradient_matches_finite_differences(room: ForwardModel, near: bool) -> None:
    rng = np.random.default_rng(3)
    positions = TRUE_LIGHTS.positions + rng.normal(0.0, 12.0, (2, 3))
    if near:  # one light 10 units off the ceiling: the distance clamp's branch of the gradient
        positions[0, 2] = 256.0 - 10.0
    lights = Lights(positions, np.array([[0.9, 0.7, 0.5], [0.6, 0.6, 0.9]]), np.array([220.0, 170.0]),
                    ambient=np.array([9.0, 7.0, 5.0]))
    visible = room.visibility(lights)
    assert room.objective(lights, visible).value > 0.01
    analytic = room.objective(lights, visible)
    numeric = finite_difference(room, lights, visible,
                                dict.fromkeys(("positions", "colours", "intensities", "ambient"), 1e-4))
    for name, value in (("positions", analytic.positions), ("colours", analytic.colours),
                        ("intensities", analytic.intensities), ("ambient", analytic.ambient)):
        scale = np.max(np.abs(numeric[name]))
        assert scale > 0, name
        assert np.max(np.abs(value - numeric[name])) <= 1e-5 * scale, name


def test_objective_is_zero_at_the_true_lights_and_one_without_light(room: ForwardModel) -> None:
    visible = room.visibility(TRUE_LIGHTS)
    assert room.objective(TRUE_LIGHTS, visible).value == pytest.approx(0.0, abs=1e-20)
    dark = Lights(TRUE_LIGHTS.positions, TRUE_LIGHTS.colours, np.zeros(2), ambient=np.zeros(3))
    assert room.objective(dark, visible).value == pytest.approx(1.0)


def test_visibility_is_bounded_by_the_light_range() -> None:
    vertices, normals, triangles = room_geometry(divisions=2, pillar=False)
    model = ForwardModel(room_target(vertices * 40, normals, triangles, np.zeros_like(vertices), wall_albedo(vertices)),
                         raycaster=None)  # a 10,240-unit room: far walls are beyond q3map2's 1-byte envelope
    light = Lights(np.array([[5120.0, 5120.0, 200.0]]), np.ones((1, 3)), np.array([10.0]))
    visible = model.visibility(light)[:, 0]
    reach = np.linalg.norm(model.points - light.positions[0], axis=1)
    assert visible.any() and not visible[reach > np.sqrt(7500 * 4 * 300)].any()


def test_pair_chunks_do_not_change_the_result(room: ForwardModel, monkeypatch: pytest.MonkeyPatch) -> None:
    import lpnn.lights.model as model_module

    visible = room.visibility(TRUE_LIGHTS)
    moved = Lights(TRUE_LIGHTS.positions + 5.0, TRUE_LIGHTS.colours, TRUE_LIGHTS.intensities, TRUE_LIGHTS.ambient)
    whole = room.objective_numpy(moved, visible)
    monkeypatch.setattr(model_module, "PAIRS_PER_CHUNK", 7)  # many chunks, cut at point boundaries
    chunked = lit_room(TRUE_LIGHTS)[0]
    assert len(chunked._chunks(visible)) > 50
    split = chunked.objective_numpy(moved, visible)
    assert split.value == pytest.approx(whole.value, rel=1e-12)
    np.testing.assert_allclose(split.positions, whole.positions, rtol=1e-10, atol=1e-18)
    np.testing.assert_allclose(chunked.radiance_of(moved, visible), room.radiance_of(moved, visible), rtol=1e-12)
