"""Volume-sized training scenes from whole levels.

A network scores one LPNN volume at a time, and artists draw volumes of a room or a corridor, not of a
whole level; the reference placement also has to run on every training scene. So the recipe cuts
levels into **crops**: axis-aligned boxes around open space, each imported by the real importer
(`lpnn.scenes.importer.import_level` with the box as bounds). A crop's features are therefore exactly
those Unity computes for a volume of that box: neighbours outside the box are missing, the scene scale
is the box's own.

Open space is found by a coarse **survey** import of the whole level (cells `survey_cell_factor` times
the crop cell); crop centres are survey points, chosen with a seeded generator.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from ..core.capture import Capture
from ..core.grid import GridError
from ..core.grid_box import Box
from ..core.in_use import InUseError
from ..scenes.bsp import BspError
from ..scenes.importer import import_level
from ..scenes.levels import Level
from .config import RecipeConfig


@dataclass(frozen=True)
class Crop:
    level: str
    cell_size: float
    number: int
    box: Box
    capture: Capture

    @property
    def name(self) -> str:
        return f"{self.level}@{self.cell_size:.4g}m__{self.number}"


def crop_rng(config: RecipeConfig, level: str, cell_size: float) -> np.random.Generator:
    """A generator that depends only on the seed, the level and the cell size (not on run order)."""
    key = hashlib.sha256(f"{config.seed}:{level}:{cell_size!r}".encode()).digest()
    return np.random.default_rng(int.from_bytes(key[:8], "little"))


def survey_points(level: Level, cell_size: float, config: RecipeConfig) -> np.ndarray:
    """(M, 3) float64 positions of open, lit space in the level at the survey's coarse cell size."""
    result = import_level(level, cell_size=cell_size * config.survey_cell_factor, drop_unlit=True,
                          timings_in_source=False, point_limit=3_000_000)
    return result.capture.positions.astype(np.float64)


def crops_of_level(level: Level, cell_size: float, config: RecipeConfig) -> list[Crop]:
    """Up to `crops_per_level` crops whose point counts fall in `crop_points`; a level too small for a
    crop of the minimum size yields none (it is reported by the caller)."""
    low, high = config.crop_points
    rng = crop_rng(config, level.name, cell_size)
    centres = survey_points(level, cell_size, config)
    crops: list[Crop] = []
    for _ in range(config.crop_attempts):
        if len(crops) == config.crops_per_level:
            break
        centre = centres[rng.integers(centres.shape[0])]
        half = rng.integers(config.crop_half_cells[0], config.crop_half_cells[1] + 1, size=3) * cell_size
        box = Box.axis_aligned(centre - half, centre + half)
        try:
            result = import_level(level, cell_size=cell_size, boxes=[box], bounds_label="crop", drop_unlit=True,
                                  timings_in_source=True, point_limit=high, in_use=config.in_use)
        except (BspError, GridError, InUseError):
            continue  # all in solid, more than `high` points, or none in use: draw another box
        if result.capture.point_count < low:
            continue
        capture = result.capture
        source = dict(capture.source)
        source.update({"crop": len(crops), "crop_center": [round(float(v), 6) for v in centre],
                       "crop_half_size": [round(float(v), 6) for v in half]})
        capture = Capture(ids=capture.ids, positions=capture.positions, sh=capture.sh, features=capture.features,
                          schema=capture.schema, feature_names=capture.feature_names, cell_size=capture.cell_size,
                          lighting_scale=capture.lighting_scale, units=capture.units, source=source,
                          extra_sections=capture.extra_sections)
        crops.append(Crop(level=level.name, cell_size=cell_size, number=len(crops), box=box, capture=capture))
    return crops
