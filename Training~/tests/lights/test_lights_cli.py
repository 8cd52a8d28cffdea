"""`lpnn scene lights` end to end on the synthetic lit level, and its refusals of hostile input."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from lit_bsp import lit_level
from lpnn.cli.main import main
from lpnn.lights.rig import read_rig
from synthetic_bsp import make_level


@pytest.fixture
def lit_bsp(tmp_path: Path) -> Path:
    path = tmp_path / "lit.bsp"
    path.write_bytes(lit_level().to_bytes())
    return path


def test_recover_then_compare(lit_bsp: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "rig.json"
    assert main(["scene", "lights", str(lit_bsp), "--grid", "2x2x2", "--scheme", "quick", "--no-textures",
                 "--out", str(out), "--quiet"]) == 0
    rig = read_rig(out)
    assert rig.level == "lit" and rig.scheme == "quick" and len(rig.bsp_sha256) == 64
    assert 1 <= rig.count <= 8 and rig.objective is not None and rig.objective < 1.0
    with open(tmp_path / "rig.curve.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert rows[0]["algorithm"] == "start" and rows[-1]["algorithm"] == "final"
    assert float(rows[-1]["objective"]) == pytest.approx(rig.objective, rel=1e-6)
    assert (tmp_path / "rig.curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "lights (of" in capsys.readouterr().out

    assert main(["scene", "lights", str(lit_bsp), "--compare", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "rig vs the level's 1 light entities" in printed  # the lightJunior is left out
    assert "light grid re-lit from the rig vs stored" in printed
    assert "light grid re-lit from the level's own lights, spotlights and surface lights (yardstick) vs stored" in printed


def test_recover_with_surface_lights(lit_bsp: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The synthetic level has no shader script: its one candidate is the sky (SURF_SKY, no script)."""
    out = tmp_path / "rig.json"
    assert main(["scene", "lights", str(lit_bsp), "--grid", "2x2x2", "--scheme", "quick", "--no-textures",
                 "--surfaces", "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "lit: 1 surface-light shaders to recover" in printed
    document = json.loads(out.read_text())
    assert document["version"] == 4 and all(light["type"] == "point" for light in document["lights"])
    assert all(surface["shader"] == "textures/test/sky" and surface["value"] > 0 for surface in document["surfaces"])
    assert main(["scene", "lights", str(lit_bsp), "--compare", str(out)]) == 0
    assert "surface lights recovered" in capsys.readouterr().out


def test_recover_spotlights(lit_bsp: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--spots: a point light and a spotlight start at every cell centre; the spots are written with a unit direction
    (Unity axes) and a cone in the fit's bounds."""
    out = tmp_path / "rig.json"
    assert main(["scene", "lights", str(lit_bsp), "--grid", "2x2x2", "--scheme", "quick", "--no-textures",
                 "--spots", "--out", str(out), "--quiet"]) == 0
    document = json.loads(out.read_text())
    assert document["info"]["spots"] is True and document["info"]["initial_lights"] % 2 == 0
    spots = [light for light in document["lights"] if light["type"] == "spot"]
    assert spots
    for light in spots:
        assert np.linalg.norm(light["direction"]) == pytest.approx(1.0, abs=1e-5)
        assert 0.05 <= light["radius_by_dist"] <= 4.0
    rig = read_rig(out)
    assert rig.spot.sum() == len(spots)
    assert main(["scene", "lights", str(lit_bsp), "--compare", str(out)]) == 0
    assert "light grid re-lit from the rig vs stored" in capsys.readouterr().out


def test_level_without_lightmaps_is_a_clear_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "dark.bsp"
    path.write_bytes(make_level().to_bytes())
    assert main(["scene", "lights", str(path), "--out", str(tmp_path / "rig.json"), "--quiet"]) == 1
    error = capsys.readouterr().err
    assert "dark.bsp: no surface carries baked light" in error and "Traceback" not in error
    assert not (tmp_path / "rig.json").exists()


def test_all_black_lightmaps_are_a_clear_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    level = lit_level(np.zeros((128, 128, 3)))
    level.vertex_extras = [extra[:7] + (0, 0, 0, 255) for extra in level.vertex_extras]  # black vertex colours
    path = tmp_path / "black.bsp"
    path.write_bytes(level.to_bytes())
    assert main(["scene", "lights", str(path), "--out", str(tmp_path / "rig.json"), "--quiet"]) == 1
    assert "black.bsp: no surface carries baked light (every lightmap texel" in capsys.readouterr().err


def test_rig_with_nan_intensity_is_refused(lit_bsp: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"format": "lpnn-light-rig", "version": 1, "ambient": [0, 0, 0], "lights": [
        {"position": [0, 0, 0], "color": [1, 1, 1], "intensity": float("nan")}]}))
    assert main(["scene", "lights", str(lit_bsp), "--compare", str(path)]) == 1
    assert "bad.json: light 0: intensity nan must be a finite number >= 0" in capsys.readouterr().err


@pytest.mark.parametrize("option, value, message", [
    ("--grid", "0x2x2", "--grid '0x2x2' must be three whole numbers"),
    ("--grid", "8x8", "--grid '8x8' must be three whole numbers"),
    ("--max-edge", "-3", "--max-edge '-3' must be a number of Quake units >= 1"),
    ("--refresh", "0", "--refresh 0 must be at least 1"),
])
def test_bad_settings(lit_bsp: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], option: str, value: str,
                      message: str) -> None:
    assert main(["scene", "lights", str(lit_bsp), option, value, "--out", str(tmp_path / "r.json"), "--quiet"]) == 1
    assert message in capsys.readouterr().err


def test_recover_a_sun(lit_bsp: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """By default (and with --suns) one sun is fitted through the level's sky quad; the rig records how many were kept,
    and --compare re-lights the grid with it. --no-suns fits none; a level without sky surfaces fits none by default
    and is refused with --suns, with its name and what to do."""
    out = tmp_path / "rig.json"
    for flag in ([], ["--suns"]):
        assert main(["scene", "lights", str(lit_bsp), "--grid", "2x2x2", "--scheme", "quick", "--no-textures",
                     "--out", str(out), "--quiet", *flag]) == 0
        printed = capsys.readouterr().out
        assert f"{out}: suns" in printed
        document = json.loads(out.read_text())
        assert document["version"] == 4 and document["info"]["suns"] == len(document["suns"])
        for sun in document["suns"]:
            assert abs(np.linalg.norm(sun["direction"]) - 1.0) < 1e-5 and max(sun["color"]) == pytest.approx(1.0)
    assert main(["scene", "lights", str(lit_bsp), "--compare", str(out)]) == 0
    assert "light grid re-lit from the rig vs stored" in capsys.readouterr().out
    assert main(["scene", "lights", str(lit_bsp), "--grid", "2x2x2", "--scheme", "quick", "--no-textures",
                 "--no-suns", "--out", str(out), "--quiet"]) == 0
    document = json.loads(out.read_text())
    assert "suns" not in document["info"] and document["suns"] == []
    skyless = lit_level()
    skyless.shaders = [(name, 0, contents) for name, _, contents in skyless.shaders]
    path = tmp_path / "skyless.bsp"
    path.write_bytes(skyless.to_bytes())
    common = ["scene", "lights", str(path), "--grid", "2x2x2", "--scheme", "quick", "--no-textures", "--quiet"]
    assert main([*common, "--out", str(tmp_path / "default.json")]) == 0
    assert json.loads((tmp_path / "default.json").read_text())["suns"] == []
    assert main([*common, "--suns", "--out", str(tmp_path / "none.json")]) != 0
    assert "skyless: no sky surface (SURF_SKY) for a sun to shine through; fit with --no-suns" in capsys.readouterr().err


def test_scripts_held_or_fitted_on_a_level_without_scripts(lit_bsp: Path, tmp_path: Path) -> None:
    """`--scripts held` (the default) holds only what a shader script gives; the synthetic level ships none, so its
    sun is fitted either way and both settings give the same rig."""
    rigs = []
    for flag in (["--scripts", "held"], ["--scripts", "fitted"]):
        out = tmp_path / f"{flag[1]}.json"
        assert main(["scene", "lights", str(lit_bsp), "--grid", "2x2x2", "--scheme", "quick", "--no-textures",
                     "--out", str(out), "--quiet", *flag]) == 0
        rigs.append(json.loads(out.read_text()))
    assert len(rigs[0]["suns"]) == 1
    assert rigs[0]["lights"] == rigs[1]["lights"] and rigs[0]["suns"] == rigs[1]["suns"]
