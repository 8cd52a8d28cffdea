"""Relit variants of training crops (recipe option `variants_per_crop`): made for training levels only."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lpnn.core.capture_file import read_capture, write_capture
from lpnn.recipe.config import RecipeConfig
from lpnn.recipe.crops import crops_of_level
from lpnn.recipe.levels import LevelSplit
from lpnn.recipe.relit import variant_name, variants_of_crop
from lpnn.recipe.run import RecipePaths, make_variants
from lpnn.scenes.defaults import DEFAULT_CELL
from lpnn.scenes.levels import load_pak_member

SPLIT = LevelSplit(train=("oa_dm4",), validation=("oa_dm2",), held_out=("oa_dm1",))
CONFIG = RecipeConfig(crops_per_level=1, crop_points=(250, 700), crop_half_cells=(2, 6), variants_per_crop=2,
                      variant_rig_scheme="quick", workers=1)


@pytest.mark.parametrize("role", ["validation", "held_out"])
def test_crops_of_validation_and_held_out_levels_are_refused(role: str) -> None:
    with pytest.raises(ValueError, match=f"training crops only: x@1.626m__0 belongs to a {role} level"):
        variants_of_crop(None, "x@1.626m__0", None, None, role, CONFIG)  # refused before anything is read


@pytest.mark.openarena
@pytest.mark.slow
def test_a_training_crop_gets_seeded_relit_variants_and_a_held_out_one_none(tmp_path: Path,
                                                                             openarena_pak: Path) -> None:
    paths = RecipePaths(tmp_path)
    paths.crops.mkdir(parents=True)
    level = load_pak_member(openarena_pak, "maps/oa_dm4.bsp")
    (crop,) = crops_of_level(level, DEFAULT_CELL, CONFIG)
    write_capture(paths.crops / f"{crop.name}.lpnncap", crop.capture)
    made = make_variants(paths, openarena_pak, [crop.name], SPLIT, CONFIG, log=lambda _: None)
    assert made and set(made) <= {variant_name(crop.name, 1), variant_name(crop.name, 2)}
    assert (paths.rigs / "oa_dm4.json").exists()
    captures = [read_capture(paths.crops / f"{name}.lpnncap") for name in made]
    for number, capture in zip([int(n[-1]) for n in made], captures):
        assert capture.source["lighting"] == "rig" and capture.source["variant"] == number
        assert capture.source["crop_center"] == crop.capture.source["crop_center"]
        assert capture.source["rig"] == variant_name(crop.name, number)
        assert capture.cell_size == crop.capture.cell_size
        assert not np.array_equal(capture.sh[: min(len(capture.sh), len(crop.capture.sh))],
                                  crop.capture.sh[: min(len(capture.sh), len(crop.capture.sh))])
    if len(captures) == 2:
        assert captures[0].source["rig_sha256"] != captures[1].source["rig_sha256"]
    stamps = [(paths.crops / f"{name}.lpnncap").stat().st_mtime_ns for name in made]
    assert make_variants(paths, openarena_pak, [crop.name], SPLIT, CONFIG, log=lambda _: None) == made  # resumed
    assert [(paths.crops / f"{name}.lpnncap").stat().st_mtime_ns for name in made] == stamps
    with pytest.raises(ValueError, match="training crops only: level oa_dm1 belongs to a held_out level"):
        make_variants(paths, openarena_pak, ["oa_dm1@1.626m__0"], SPLIT, CONFIG, log=lambda _: None)
    assert not (paths.rigs / "oa_dm1.json").exists()
