"""Tools~/experiments/lights-residual.py (lights.md §7, benchmarks.md "The light rig") on the light-rig tests' synthetic level: it
keeps no light entity and its shaders have no script, so its real rig explains none of the baked light."""

from __future__ import annotations

import sys
from pathlib import Path

from tools_support import REPO, run_experiment

sys.path[:0] = [str(REPO / "Training~" / "tests" / "lights"), str(REPO / "Training~" / "tests" / "scenes")]
from lit_bsp import lit_level  # noqa: E402  (the light-rig tests' synthetic level)


def test_a_level_without_lights_leaves_all_its_light_unexplained(tmp_path: Path) -> None:
    level = tmp_path / "lit.bsp"
    level.write_bytes(lit_level().to_bytes())
    lines = run_experiment("lights-residual.py", str(level)).stdout.splitlines()
    assert [line.split(":")[0] for line in lines] == ["lit without suns", "lit with suns",
                                                      "lit with suns and one bounce"]  # no light, nothing to bounce
    for line in lines:
        assert ("objective 1.0000, modelled / target light 0.00, area almost unlit 100.0% carrying 1.000; "
                "under-lit 1.000, over-lit 0.000; area a sun reaches 0.0%") in line
