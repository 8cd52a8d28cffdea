"""Relit variants of training crops (`variants_per_crop`, Documentation~/training.md, lights.md §9).

For every training level the recipe recovers a light rig once (`lpnn scene lights` with
`variant_rig_scheme`, kept in WORK/rigs/LEVEL.json); every training crop then gets
`variants_per_crop` new captures of the same box and cell, lit by seeded perturbations of that rig
(lights/variants.py) through the probe baker (lights/bake.py). The seed depends only on the recipe's
seed, the crop's name and the variant's number. Crops of validation and held-out levels never get
variants: `variants_of_crop` refuses them, whatever the caller passes.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from ..core.capture import Capture
from ..core.grid import GridError
from ..core.grid_box import Box
from ..core.in_use import InUseError
from ..lights.relight import RigLighting
from ..lights.rig import Rig, read_rig, write_rig
from ..lights.variants import relit_variant
from ..scenes.bsp import BspError
from ..scenes.coords import unity_to_quake
from ..scenes.importer import import_level
from ..scenes.levels import Level
from ..scenes.solid import SolidTester
from .config import RecipeConfig

VARIANT_MARK = "~relit"


def variant_name(crop: str, number: int) -> str:
    return f"{crop}{VARIANT_MARK}{number}"


def variant_seed(config: RecipeConfig, crop: str, number: int) -> int:
    key = hashlib.sha256(f"{config.seed}:{crop}:relit{number}".encode()).digest()
    return int.from_bytes(key[:8], "little")


def require_training(what: str, role: str) -> None:
    """Relit variants are training data only: a validation or held-out level's crop is refused."""
    if role != "train":
        raise ValueError(f"relit variants are made for training crops only: {what} belongs to a {role} level")


def level_rig(level: Level, rig_file: Path, scheme: str) -> Rig:
    """The level's recovered rig, fitted once and kept in `rig_file`."""
    if rig_file.exists():
        return read_rig(rig_file)
    from ..lights.pipeline import fit_scene, load_scene, rig_of
    from ..lights.settings import DEFAULT_GRID

    scene = load_scene(level)
    # no spotlights: the probe baker (lights/bake.py rig_lights) bakes a rig's lights as point lights, without cones
    rig = rig_of(scene, fit_scene(scene, DEFAULT_GRID, scheme, spots=False), DEFAULT_GRID, scheme)
    write_rig(rig_file, rig)
    return rig


def variants_of_crop(level: Level, crop_name: str, crop: Capture, rig: Rig, role: str,
                     config: RecipeConfig) -> list[tuple[str, Capture]]:
    """(name, capture) of the crop's relit variants; a variant whose box no longer holds between the
    crop's minimum and twice its maximum point count (unlit points differ between lightings) is skipped."""
    require_training(crop_name, role)
    source = crop.source
    centre, half = np.array(source["crop_center"], dtype=float), np.array(source["crop_half_size"], dtype=float)
    box = Box.axis_aligned(centre - half, centre + half)
    solid = SolidTester(level.bsp)

    def is_open(unity_positions: np.ndarray) -> np.ndarray:
        return ~solid.solid_or_outside(unity_to_quake(unity_positions))

    low, high = config.crop_points
    variants = []
    for number in range(1, config.variants_per_crop + 1):
        name = variant_name(crop_name, number)
        lighting = RigLighting.of_rig(relit_variant(rig, variant_seed(config, crop_name, number), is_open), name)
        try:
            result = import_level(level, cell_size=crop.cell_size, boxes=[box], bounds_label="crop", drop_unlit=True,
                                  point_limit=2 * high, lighting=lighting, in_use=config.in_use)
        except (BspError, GridError, InUseError):
            continue
        if result.capture.point_count < low:
            continue
        captured = result.capture
        captured_source = dict(captured.source)
        captured_source.update({key: source[key] for key in ("crop", "crop_center", "crop_half_size")})
        captured_source["variant"] = number
        variants.append((name, Capture(ids=captured.ids, positions=captured.positions, sh=captured.sh,
                                       features=captured.features, schema=captured.schema,
                                       feature_names=captured.feature_names, cell_size=captured.cell_size,
                                       lighting_scale=captured.lighting_scale, units=captured.units,
                                       source=captured_source, extra_sections=captured.extra_sections)))
    return variants
