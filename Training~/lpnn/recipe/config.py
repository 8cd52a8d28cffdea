"""Options of the default-model recipe; every random choice derives from `seed`."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..scenes.importer import DEFAULT_CELL
from ..train.config import TrainConfig


@dataclass(frozen=True)
class RecipeConfig:
    seed: int = 0
    # Held-out test levels: every `held_out_every`-th level in alphabetical order, starting at
    # `held_out_offset` (10 of the 49 importable levels of openarena-081-maps). Chosen by rule,
    # before any training, and never used for training or model selection.
    held_out_every: int = 5
    held_out_offset: int = 2
    # Validation levels (early stopping): every `validation_every`-th of the remaining levels.
    validation_every: int = 8
    validation_offset: int = 3
    cell_sizes: tuple[float, ...] = (DEFAULT_CELL,)
    survey_cell_factor: float = 2.0  # the survey that finds open space uses cells this much coarser
    crops_per_level: int = 4
    crop_points: tuple[int, int] = (700, 1600)  # a crop is kept when its point count is in this range
    crop_half_cells: tuple[int, int] = (3, 10)  # crop box half-size, in cells, drawn per axis
    crop_attempts: int = 40
    label_budget: float = 0.2  # positive = kept by the fast reference at this fraction of the points
    # Which points of a crop are imported, labelled and trained on (Documentation~/in-use.md): "all" (what the shipped
    # model was trained on) or "band" / "reachable" (the points where players go; crops without any are redrawn).
    in_use: str = "all"
    workers: int = 2  # processes for importing and labelling
    # Relit variants (lights.md §9): this many re-lit captures of every *training* crop, from seeded
    # perturbations of the level's recovered rig (never for validation or held-out levels); 0 = none.
    variants_per_crop: int = 0
    variant_rig_scheme: str = "mixed"  # the `lpnn scene lights` scheme that recovers each training level's rig
    levels: tuple[str, ...] | None = None  # None: every level of the pak
    train: TrainConfig = field(default_factory=lambda: TrainConfig(epochs=100, patience=20, steps_per_epoch=60))


QUICK = RecipeConfig(
    levels=("aggressor", "oa_dm1", "oa_dm2", "oa_dm4", "oa_dm5", "oa_dm6"),
    held_out_every=3,
    held_out_offset=1,
    validation_every=4,
    validation_offset=0,
    crops_per_level=1,
    crop_points=(250, 700),
    crop_half_cells=(2, 6),
    train=TrainConfig(epochs=6, patience=3, steps_per_epoch=8, batch_clouds=4),
)
