"""Training data: captures -> clouds (one capture = one cloud), checks, split by capture, statistics.

Scenes are never concatenated: every capture stays its own cloud, so the network's global pooling
only ever sees one scene (or a crop of one). Errors name the capture and say what to do.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from ..errors import UserError
from ..core.capture import Capture
from ..core.capture_file import dataset_files, read_capture
from .modelcard import schema_mismatch


@dataclass(frozen=True)
class Cloud:
    """One labelled capture, reduced to what training needs."""

    name: str  # stable display name (path relative to the dataset's common folder, '/'-separated)
    ids: np.ndarray  # (N, 3) int32 lattice ids, used for axis-aligned crops
    features: np.ndarray  # (N, F) float32
    labels: np.ndarray  # (N,) uint8 in {0, 1}
    schema: str
    feature_names: tuple[str, ...]
    label_source: str
    capture: Capture | None = None  # the full capture (positions, SH...), for metrics such as placement error

    @property
    def point_count(self) -> int:
        return int(self.labels.shape[0])

    @property
    def positives(self) -> int:
        return int(np.count_nonzero(self.labels))

    @property
    def has_both_classes(self) -> bool:
        return 0 < self.positives < self.point_count


@dataclass(frozen=True)
class Split:
    train: list[Cloud]
    validation: list[Cloud]


@dataclass(frozen=True)
class Normalisation:
    """Per-feature (x - mean) / std from the training split; constant features get std = 1."""

    mean: np.ndarray  # (F,) float32
    std: np.ndarray  # (F,) float32, > 0
    constant_features: tuple[str, ...]


def display_names(paths: Sequence[Path]) -> list[str]:
    """Paths relative to their deepest common folder ('/'-separated): short, machine-independent."""
    resolved = [p.resolve() for p in paths]
    if not resolved:
        return []
    common = Path(os.path.commonpath([p.parent for p in resolved]))
    return [p.relative_to(common).as_posix() for p in resolved]


def capture_files(paths: Iterable[str | os.PathLike]) -> list[Path]:
    """The dataset's capture files (folders searched recursively); UserError when there are none."""
    path_list = [Path(p) for p in paths]
    files = dataset_files(path_list)
    if not files:
        where = ", ".join(str(p) for p in path_list) or "(no paths given)"
        raise UserError(f"no captures (*.lpnncap) found in {where}; export or convert captures first")
    return files


def cloud_from_capture(capture: Capture, name: str) -> Cloud:
    """Checks one capture is usable for training (labels, finite features) and keeps its essentials."""
    if capture.labels is None:
        raise UserError(
            f"{name}: has no labels; training needs labelled captures "
            "(add a 'labels' section with its label_source, e.g. from a reference placement)"
        )
    features = np.ascontiguousarray(capture.features, dtype=np.float32)
    bad_rows, bad_cols = np.nonzero(~np.isfinite(features))
    if bad_rows.size:
        row, col = int(bad_rows[0]), int(bad_cols[0])
        raise UserError(
            f"{name}: record {row} (id {','.join(str(int(v)) for v in capture.ids[row])}): feature "
            f"'{capture.feature_names[col]}' is {float(features[row, col])}; {bad_rows.size} non-finite value(s) "
            "in total; re-extract the features of this capture"
        )
    labels = np.asarray(capture.labels, dtype=np.uint8)
    if labels.size and labels.max() > 1:
        raise UserError(f"{name}: labels must be 0 or 1, found {int(labels.max())}")
    return Cloud(
        name=name,
        ids=np.ascontiguousarray(capture.ids, dtype=np.int32),
        features=features,
        labels=labels,
        schema=capture.schema,
        feature_names=tuple(capture.feature_names),
        label_source=capture.label_source or "",
        capture=capture,
    )


def check_consistent(clouds: Sequence[Cloud]) -> None:
    """All clouds share one schema and feature list; the labels hold both classes overall."""
    if not clouds:
        raise UserError("no captures to train on")
    first = clouds[0]
    for cloud in clouds[1:]:
        problem = schema_mismatch(first.name, first.schema, first.feature_names,
                                  cloud.name, cloud.schema, cloud.feature_names)
        if problem:
            raise UserError(f"mixed features: {problem}; train on captures of one schema at a time")
    check_both_classes(clouds, "the dataset")


def check_both_classes(clouds: Sequence[Cloud], what: str) -> None:
    points = sum(c.point_count for c in clouds)
    positives = sum(c.positives for c in clouds)
    names = ", ".join(c.name for c in clouds)
    if positives == 0:
        raise UserError(f"{what} ({names}) has no positive labels among {points:,} points: nothing to learn; check the label source")
    if positives == points:
        raise UserError(f"{what} ({names}) has only positive labels ({points:,} points): a single class; check the label source")


def load_clouds(files: Sequence[Path]) -> list[Cloud]:
    """Reads and checks the given capture files (in order); one cloud per capture."""
    names = display_names(files)
    clouds = [cloud_from_capture(read_capture(path), name) for path, name in zip(files, names)]
    check_consistent(clouds)
    return clouds


def split_by_capture(clouds: Sequence[Cloud], seed: int, val_fraction: float,
                     validation_names: Sequence[str] = ()) -> Split:
    """Held-out captures: the named ones, else a seeded random fraction (at least one)."""
    if validation_names:
        wanted = set(validation_names)
        unknown = sorted(wanted - {c.name for c in clouds})
        if unknown:
            raise UserError(f"validation capture(s) {unknown} are not in the dataset ({[c.name for c in clouds]})")
        validation = [c for c in clouds if c.name in wanted]
        train = [c for c in clouds if c.name not in wanted]
    else:
        if len(clouds) < 2:
            raise UserError(
                f"only one capture ({clouds[0].name if clouds else 'none'}): validation holds out whole captures, "
                "so add another capture or pass one with --val"
            )
        count = min(len(clouds) - 1, max(1, math.ceil(val_fraction * len(clouds))))
        # The order of the names (not of the files on disk) decides the split, so it only depends on the seed.
        order = sorted(range(len(clouds)), key=lambda i: clouds[i].name)
        chosen = set(np.random.default_rng([seed, 0x5EED]).permutation(order)[:count].tolist())
        validation = [c for i, c in enumerate(clouds) if i in chosen]
        train = [c for i, c in enumerate(clouds) if i not in chosen]
    if not train:
        raise UserError("every capture is held out for validation; leave at least one for training")
    check_both_classes(train, "the training split")
    if not any(c.has_both_classes for c in validation):
        raise UserError(
            f"no validation capture ({', '.join(c.name for c in validation)}) has both positive and negative labels, "
            "so ROC/PR-AUC are undefined; pass other captures with --val or change --seed"
        )
    return Split(train=train, validation=validation)


def normalisation_from(clouds: Sequence[Cloud]) -> Normalisation:
    """Pooled per-feature mean and std (float64 accumulation) over every point of `clouds`."""
    stacked = np.concatenate([c.features for c in clouds], axis=0).astype(np.float64)
    if stacked.shape[0] == 0:
        raise UserError("cannot compute the input normalisation of an empty training split")
    mean = stacked.mean(axis=0)
    std = stacked.std(axis=0)
    # Exactly constant columns (all values equal) carry no information; std 1 keeps them finite (0).
    constant = stacked.max(axis=0) == stacked.min(axis=0)
    std = np.where(constant | ~(std > 0), 1.0, std)
    names = clouds[0].feature_names
    return Normalisation(
        mean=mean.astype(np.float32),
        std=std.astype(np.float32),
        constant_features=tuple(names[i] for i in np.flatnonzero(constant)),
    )


def positive_weight(clouds: Sequence[Cloud]) -> float:
    """negatives / positives over the training split: the BCE weight that balances the classes."""
    positives = sum(c.positives for c in clouds)
    negatives = sum(c.point_count for c in clouds) - positives
    if positives == 0 or negatives == 0:
        raise UserError("the training split needs both positive and negative labels")
    return negatives / positives


def load_split(dataset_paths: Sequence[str | os.PathLike], validation_paths: Sequence[str | os.PathLike],
               seed: int, val_fraction: float) -> Split:
    """Loads the dataset (plus explicit validation captures, which may live elsewhere) and splits it."""
    dataset = capture_files(dataset_paths)
    explicit = capture_files(validation_paths) if validation_paths else []
    files = list(dict.fromkeys(p.resolve() for p in dataset + explicit))
    clouds = load_clouds(files)
    explicit_resolved = {p.resolve() for p in explicit}
    validation_names = [c.name for c, path in zip(clouds, files) if path in explicit_resolved]
    return split_by_capture(clouds, seed, val_fraction, validation_names)
