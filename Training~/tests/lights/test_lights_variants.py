"""Relit variants of a rig (lpnn.lights.variants): seeded, within their stated ranges."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.lights import variants
from lpnn.lights.rig import Rig
from lpnn.lights.variants import relit_variant


def sample_rig(count: int = 12) -> Rig:
    rng = np.random.default_rng(5)
    colours = rng.uniform(0.2, 1.0, (count, 3))
    colours /= colours.max(axis=1, keepdims=True)
    spread = np.stack([np.arange(count) * 10.0, np.zeros(count), np.zeros(count)], axis=1)  # 10 m apart
    return Rig(positions=spread, colours=colours, intensities=rng.uniform(100, 900, count),
               ambient=np.array([20.0, 30.0, 250.0]), level="x", scheme="mixed")


def test_the_same_seed_gives_the_same_variant_and_another_seed_another() -> None:
    rig = sample_rig()
    first, again, other = relit_variant(rig, 7), relit_variant(rig, 7), relit_variant(rig, 8)
    for key in ("positions", "colours", "intensities", "ambient"):
        assert np.array_equal(getattr(first, key), getattr(again, key))
    assert first.count != other.count or not np.array_equal(first.intensities, other.intensities)
    assert first.extra["variant_seed"] == 7 and first.scheme == "relit variant"


def test_variants_stay_within_the_stated_ranges() -> None:
    rig = sample_rig(40)
    for seed in range(20):
        variant = relit_variant(rig, seed)
        off = variant.extra["lights_off"]
        assert variant.count == rig.count - off >= 1
        assert np.allclose(variant.colours.max(axis=1), 1.0) and np.all(variant.colours >= 0)
        assert np.all(variant.ambient <= 255.0) and np.all(variant.ambient >= 0)
        # kept lights in order: match them back by the smallest move (<= MOVE_RADIUS)
        distance = np.linalg.norm(variant.positions[:, None] - rig.positions[None], axis=2)
        source = distance.argmin(axis=1)
        assert np.all(distance.min(axis=1) <= variants.MOVE_RADIUS + 1e-9)
        assert np.count_nonzero(distance.min(axis=1) > 0) <= variants.MOVED_LIGHTS
        ratio = variant.intensities / rig.intensities[source]
        assert np.all(ratio >= variants.INTENSITY_RANGE[0] * variants.COLOUR_RANGE[0] - 1e-9)
        assert np.all(ratio <= variants.INTENSITY_RANGE[1] + 1e-9)
    off_share = np.mean([relit_variant(rig, s).extra["lights_off"] / rig.count for s in range(50)])
    assert 0.08 < off_share < 0.22  # OFF_PROBABILITY = 0.15


def test_moves_into_solid_are_refused_and_a_one_light_rig_keeps_its_light() -> None:
    rig = sample_rig()
    nowhere = relit_variant(rig, 3, is_open=lambda p: np.zeros(len(p), dtype=bool))
    distance = np.linalg.norm(nowhere.positions[:, None] - rig.positions[None], axis=2).min(axis=1)
    assert np.all(distance == 0.0)
    single = Rig(positions=np.zeros((1, 3)), colours=np.ones((1, 3)), intensities=np.array([300.0]))
    assert all(relit_variant(single, seed).count == 1 for seed in range(30))
    with pytest.raises(ValueError, match="no relit variant"):
        relit_variant(Rig(positions=np.zeros((0, 3)), colours=np.zeros((0, 3)), intensities=np.zeros(0)), 1)


def test_a_variant_keeps_each_kept_light_s_spotlight_cone() -> None:
    rig = sample_rig()
    rig.radius_by_dist = np.where(np.arange(rig.count) % 2 == 0, 0.5, 0.0)
    rig.spot_directions = np.tile([0.0, -1.0, 0.0], (rig.count, 1)) * (rig.radius_by_dist > 0)[:, None]
    variant = relit_variant(rig, 3)
    assert variant.count < rig.count  # some lights were switched off
    kept = [int(np.flatnonzero(np.isclose(rig.positions[:, 0], x, atol=1.6))[0]) for x in variant.positions[:, 0]]
    np.testing.assert_array_equal(variant.radius_by_dist, rig.radius_by_dist[kept])
    np.testing.assert_array_equal(variant.spot_directions, rig.spot_directions[kept])
