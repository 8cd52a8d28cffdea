"""The recipe's crops follow the in-use rule (RecipeConfig.in_use, `lpnn recipe run --in-use`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from lpnn.recipe.config import QUICK
from lpnn.recipe.crops import crops_of_level
from lpnn.scenes.levels import load_pak_member


def test_crops_record_the_rule_and_reachable_crops_hold_only_points_in_use(openarena_pak: Path) -> None:
    level = load_pak_member(openarena_pak, "maps/dm6ish.bsp")
    config = replace(QUICK, crops_per_level=1, crop_points=(100, 700))
    (every,) = crops_of_level(level, 1.6256, config)
    assert every.capture.source["in_use"] == "all" and QUICK.in_use == "all"  # the shipped model's rule
    marked = every.capture.extra_sections["in_use"]  # kept through the crop's own capture
    assert marked.shape == (every.capture.point_count,) and 0 < marked.sum() < every.capture.point_count
    (walked,) = crops_of_level(level, 1.6256, replace(config, in_use="reachable"))
    low, high = config.crop_points
    assert walked.capture.source["in_use"] == "reachable" and low <= walked.capture.point_count <= high
    assert "in_use" not in walked.capture.extra_sections
    assert walked.capture.source["points_before_in_use"] > walked.capture.point_count
    assert np.isfinite(walked.capture.features).all()
