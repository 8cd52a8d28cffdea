"""Dataset loading: degenerate datasets fail clearly; split by capture; normalisation; batches."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.errors import UserError
from lpnn.core.capture import Capture
from lpnn.core.capture_file import write_capture
from lpnn.core.schema import THESIS30
from lpnn.train.batches import BatchSampler, pad_clouds, random_crop
from lpnn.train.config import TrainConfig, config_from_dict
from lpnn.train.data import (
    cloud_from_capture, load_clouds, load_split, normalisation_from, positive_weight, split_by_capture,
)
from lpnn.train.synthetic import CONSTANT_FEATURE, synthetic_capture


def write(folder: Path, name: str, capture: Capture) -> Path:
    return write_capture(folder / name, capture)


def clouds_of(count: int, shape: tuple[int, int, int] = (8, 6, 4)):
    return [cloud_from_capture(synthetic_capture(seed, shape=shape), f"scene_{seed}") for seed in range(count)]


# ------------------------------------------------------------------------------------------ errors

def test_empty_dataset_folder(tmp_path: Path) -> None:
    with pytest.raises(UserError, match="no captures"):
        load_split([tmp_path], [], seed=0, val_fraction=0.2)


def test_capture_without_labels_is_named(tmp_path: Path) -> None:
    write(tmp_path, "a.lpnncap", synthetic_capture(0))
    write(tmp_path, "unlabelled.lpnncap", dataclasses.replace(synthetic_capture(1), labels=None, label_source=None))
    with pytest.raises(UserError, match="unlabelled.lpnncap: has no labels"):
        load_split([tmp_path], [], seed=0, val_fraction=0.2)


@pytest.mark.parametrize("value, message", [(0, "no positive labels"), (1, "single class")])
def test_single_class_dataset(tmp_path: Path, value: int, message: str) -> None:
    for seed in range(2):
        capture = synthetic_capture(seed)
        write(tmp_path, f"s{seed}.lpnncap", capture.with_labels(np.full(capture.point_count, value), "constant"))
    with pytest.raises(UserError, match=message):
        load_split([tmp_path], [], seed=0, val_fraction=0.2)


def test_mixed_schemas_name_both(tmp_path: Path) -> None:
    v1 = synthetic_capture(0)
    rng = np.random.default_rng(0)
    legacy = dataclasses.replace(v1, schema=THESIS30.id, feature_names=list(THESIS30.names),
                                 features=rng.normal(size=(v1.point_count, 30)).astype(np.float32))
    write(tmp_path, "a_v1.lpnncap", v1)
    write(tmp_path, "b_legacy.lpnncap", legacy)
    with pytest.raises(UserError, match=r"b_legacy.lpnncap has schema 'lpnn.thesis30' \(30 features\) but a_v1.lpnncap has schema 'lpnn.features.v1'"):
        load_split([tmp_path], [], seed=0, val_fraction=0.2)


def test_mixed_feature_names_of_an_unknown_schema(tmp_path: Path) -> None:
    base = synthetic_capture(0)
    names = [f"f{i}" for i in range(base.feature_count)]
    write(tmp_path, "a.lpnncap", dataclasses.replace(base, schema="custom.v0", feature_names=names))
    renamed = names[:5] + ["other"] + names[6:]
    write(tmp_path, "b.lpnncap", dataclasses.replace(base, schema="custom.v0", feature_names=renamed))
    with pytest.raises(UserError, match="feature 5 is 'other' in b.lpnncap and 'f5' in a.lpnncap"):
        load_split([tmp_path], [], seed=0, val_fraction=0.2)


def test_nan_features_are_named() -> None:
    capture = synthetic_capture(0)
    features = capture.features.copy()
    features[7, 3] = np.nan
    with pytest.raises(UserError, match=r"scene: record 7 .*'directionality' is nan"):
        cloud_from_capture(dataclasses.replace(capture, features=features), "scene")


def test_one_capture_cannot_be_split(tmp_path: Path) -> None:
    write(tmp_path, "only.lpnncap", synthetic_capture(0))
    with pytest.raises(UserError, match="only one capture"):
        load_split([tmp_path], [], seed=0, val_fraction=0.2)


def test_validation_without_both_classes(tmp_path: Path) -> None:
    write(tmp_path, "a.lpnncap", synthetic_capture(0))
    write(tmp_path, "b.lpnncap", synthetic_capture(1))
    empty = synthetic_capture(2)
    write(tmp_path, "c.lpnncap", empty.with_labels(np.zeros(empty.point_count), "none"))
    with pytest.raises(UserError, match="no validation capture"):
        load_split([tmp_path], [tmp_path / "c.lpnncap"], seed=0, val_fraction=0.2)


def test_bad_config_values_are_named() -> None:
    with pytest.raises(UserError, match="'batch_clouds'"):
        config_from_dict({"batch_clouds": 0})
    with pytest.raises(UserError, match=r"unknown option\(s\) \['epoch'\]"):
        config_from_dict({"epoch": 3})
    with pytest.raises(UserError, match="model.pointwise"):
        config_from_dict({"model": {"pointwise": "gemm"}})
    assert config_from_dict({"model": {"trunk": [8, 8]}}).model.trunk == (8, 8)


# ------------------------------------------------------------------------------------------ split

def test_split_is_by_capture_and_seeded() -> None:
    clouds = clouds_of(10)
    first = split_by_capture(clouds, seed=3, val_fraction=0.2)
    again = split_by_capture(list(reversed(clouds)), seed=3, val_fraction=0.2)
    names = lambda clouds: sorted(c.name for c in clouds)  # noqa: E731
    assert names(first.validation) == names(again.validation)  # depends on names + seed, not on order
    assert len(first.validation) == 2 and len(first.train) == 8
    assert not set(names(first.train)) & set(names(first.validation))
    splits = {tuple(names(split_by_capture(clouds, seed, 0.2).validation)) for seed in range(8)}
    assert len(splits) > 1


def test_explicit_validation_paths(tmp_path: Path) -> None:
    for seed in range(3):
        write(tmp_path / "data", f"s{seed}.lpnncap", synthetic_capture(seed))
    held_out = write(tmp_path / "elsewhere", "held.lpnncap", synthetic_capture(7))
    split = load_split([tmp_path / "data"], [held_out], seed=0, val_fraction=0.5)
    assert [c.name for c in split.validation] == ["elsewhere/held.lpnncap"]
    assert sorted(c.name for c in split.train) == ["data/s0.lpnncap", "data/s1.lpnncap", "data/s2.lpnncap"]


# ------------------------------------------------------------------------------------------ statistics

def test_normalisation_guards_constant_features_and_pools_points() -> None:
    clouds = clouds_of(3)
    stats = normalisation_from(clouds)
    stacked = np.concatenate([c.features for c in clouds]).astype(np.float64)
    assert stats.std[CONSTANT_FEATURE] == 1.0
    assert stats.constant_features == (clouds[0].feature_names[CONSTANT_FEATURE],)
    varying = [i for i in range(stacked.shape[1]) if i != CONSTANT_FEATURE]
    np.testing.assert_allclose(stats.mean, stacked.mean(axis=0), rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(stats.std[varying], stacked.std(axis=0)[varying], rtol=1e-6)
    assert np.all(np.isfinite((stacked - stats.mean) / stats.std))


def test_positive_weight_balances_classes() -> None:
    clouds = clouds_of(2)
    positives = sum(c.positives for c in clouds)
    total = sum(c.point_count for c in clouds)
    assert positive_weight(clouds) == pytest.approx((total - positives) / positives)


# ------------------------------------------------------------------------------------------ batches

def test_random_crop_is_an_axis_aligned_box() -> None:
    cloud = clouds_of(1, shape=(10, 9, 8))[0]
    rng = np.random.default_rng(0)
    for _ in range(20):
        crop = random_crop(cloud.ids, rng, min_fraction=0.3)
        low, high = cloud.ids[crop].min(axis=0), cloud.ids[crop].max(axis=0)
        inside = np.flatnonzero(np.all((cloud.ids >= low) & (cloud.ids <= high), axis=1))
        assert np.array_equal(crop, inside)  # exactly the points of its bounding box
        assert np.all(high - low + 1 >= np.floor(0.3 * np.array([10, 9, 8])))


def test_every_batch_row_is_one_capture_and_padding_is_masked() -> None:
    clouds = []
    for index, cloud in enumerate(clouds_of(4, shape=(12, 10, 6))):
        features = cloud.features.copy()
        features[:, 0] = index  # capture identity, to recognise each row's source
        clouds.append(dataclasses.replace(cloud, features=features))
    config = TrainConfig(batch_clouds=5, max_points=300, min_points=20)
    sampler = BatchSampler(clouds, config, seed=1)
    sizes = set()
    for _ in range(12):
        batch = sampler.next_batch()
        for row in range(batch.features.shape[0]):
            real = batch.mask[row] == 1
            count = int(real.sum())
            sizes.add(count)
            assert 1 <= count <= config.max_points
            assert np.all(real[:count]) and not np.any(real[count:])  # real points first, then padding
            sources = np.unique(batch.features[row, real, 0])
            assert sources.size == 1 and clouds[int(sources[0])].name == batch.sources[row]
            assert np.all(batch.features[row, ~real] == 0) and np.all(batch.labels[row, ~real] == 0)
    assert len(sizes) > 5  # crops and subsamples of many sizes


def test_sampler_is_deterministic_per_seed() -> None:
    clouds = clouds_of(3)
    config = TrainConfig(batch_clouds=3, max_points=128, min_points=16)
    a, b, c = (BatchSampler(clouds, config, seed) for seed in (4, 4, 5))
    for _ in range(3):
        first, second, third = a.next_batch(), b.next_batch(), c.next_batch()
        assert np.array_equal(first.features, second.features)
    assert not np.array_equal(first.features, third.features)


def test_pad_clouds_shapes() -> None:
    batch = pad_clouds([(np.ones((3, 2), np.float32), np.ones(3, np.float32)),
                        (np.ones((5, 2), np.float32), np.zeros(5, np.float32))], ["a", "b"])
    assert batch.features.shape == (2, 5, 2) and batch.real_points == 8
    assert batch.mask.tolist() == [[1, 1, 1, 0, 0], [1, 1, 1, 1, 1]]


def test_load_clouds_reads_files_in_given_order(tmp_path: Path) -> None:
    paths = [write(tmp_path, f"s{seed}.lpnncap", synthetic_capture(seed)) for seed in range(2)]
    clouds = load_clouds(paths)
    assert [c.name for c in clouds] == ["s0.lpnncap", "s1.lpnncap"]
    assert clouds[0].positives > 0 and clouds[0].features.dtype == np.float32
