"""Tools~/experiments/lights-pack.sh (benchmarks.md "The light rig") on a synthetic pak: the lit level gets a rig, the level without
baked light is listed with the command's reason, not failed."""

from __future__ import annotations

import json
import sys
import zipfile
from pathlib import Path

from tools_support import REPO, run_experiment

sys.path[:0] = [str(REPO / "Training~" / "tests" / "lights"), str(REPO / "Training~" / "tests" / "scenes")]
from lit_bsp import lit_level  # noqa: E402  (the light-rig tests' synthetic level)
from synthetic_bsp import make_level  # noqa: E402


def test_a_rig_per_lit_level_and_the_unlit_one_listed(tmp_path: Path) -> None:
    pak = tmp_path / "pak.pk3"
    with zipfile.ZipFile(pak, "w") as archive:
        archive.writestr("maps/lit.bsp", lit_level().to_bytes())
        archive.writestr("maps/dark.bsp", make_level().to_bytes())
    out = run_experiment("lights-pack.sh", "quick", str(tmp_path / "rigs"), env={"PAK": str(pak)}).stdout
    assert "1 levels recovered with scheme quick; 1 without baked light; 0 failed" in out
    assert "dark: lpnn scene: error: pak.pk3:maps/dark.bsp: no surface carries baked light" in out
    rig = json.loads((tmp_path / "rigs" / "lit.json").read_text(encoding="utf-8"))
    assert rig["lights"] and not (tmp_path / "rigs" / "dark.json").exists()
