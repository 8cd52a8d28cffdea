"""`lpnn scene import LEVEL --lighting rig:RIG.json`: captures baked from a rig, on the synthetic lit level."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

from lit_bsp import lit_level
from lpnn.cli.main import main
from lpnn.core.capture_file import read_capture
from lpnn.lights.relight import RigLighting, lighting_of
from lpnn.lights.rig import Rig, write_rig
from lpnn.scenes.levels import load_level


@pytest.fixture
def lit_bsp(tmp_path: Path) -> Path:
    path = tmp_path / "lit.bsp"
    path.write_bytes(lit_level().to_bytes())
    return path


def write_test_rig(path: Path, bsp_sha256: str) -> Path:
    rig = Rig.from_quake(np.array([[128.0, 128.0, 200.0]]), np.array([[1.0, 0.8, 0.6]]), np.array([400.0]),
                         ambient=np.array([6.0, 5.0, 4.0]), level="lit", bsp_sha256=bsp_sha256, scheme="test")
    return write_rig(path, rig)


def import_capture(bsp: Path, out: Path, *extra: str):
    assert main(["scene", "import", str(bsp), "--out", str(out), "--reproducible", "--quiet", *extra]) == 0
    return read_capture(out)


def test_a_rig_lights_the_capture_and_the_capture_records_it(lit_bsp: Path, tmp_path: Path) -> None:
    level = load_level(str(lit_bsp))
    rig_path = write_test_rig(tmp_path / "rig.json", level.sha256)
    grid = import_capture(lit_bsp, tmp_path / "grid.lpnncap")
    baked = import_capture(lit_bsp, tmp_path / "rig.lpnncap", "--lighting", f"rig:{rig_path}")
    assert grid.source["lighting"] == "grid" and lighting_of(grid.source) == "grid"
    assert lighting_of(baked.source) == "rig"
    assert baked.source["rig"] == "rig.json" and baked.source["rig_lights"] == 1
    assert baked.source["rig_sha256"] == hashlib.sha256(rig_path.read_bytes()).hexdigest()
    assert baked.source["bake_bounce"] is True and baked.source["bake_directions"] == 128
    assert np.array_equal(grid.positions, baked.positions) and not np.array_equal(grid.sh, baked.sh)
    expected, lit = RigLighting.read(rig_path).sh_at(level, baked.positions.astype(np.float64))
    assert np.array_equal(baked.sh, expected.astype(np.float32)) and lit.all()
    # every point sees at least the ambient, 6 bytes of red
    assert np.all(baked.sh[:, 0] >= np.float32(6 * 4 / 255) - 1e-7)
    # the features follow the lighting: they are computed from the baked SH
    assert not np.array_equal(grid.features, baked.features)


def test_older_captures_without_the_key_read_as_grid() -> None:
    assert lighting_of({"backend": "openarena", "level": "oa_dm1"}) == "grid"


def test_shared_points_of_two_cell_sizes_get_the_same_baked_sh(lit_bsp: Path, tmp_path: Path) -> None:
    rig_path = write_test_rig(tmp_path / "rig.json", load_level(str(lit_bsp)).sha256)
    coarse = import_capture(lit_bsp, tmp_path / "coarse.lpnncap", "--lighting", f"rig:{rig_path}", "--cell", "1.6256")
    fine = import_capture(lit_bsp, tmp_path / "fine.lpnncap", "--lighting", f"rig:{rig_path}", "--cell", "0.8128")
    key = lambda p: tuple(np.rint(p / 0.0254).astype(int))  # noqa: E731  Quake units on both lattices
    fine_sh = {key(p): s for p, s in zip(fine.positions.astype(np.float64), fine.sh)}
    shared = [(s, fine_sh[key(p)]) for p, s in zip(coarse.positions.astype(np.float64), coarse.sh) if key(p) in fine_sh]
    assert len(shared) >= 10
    for a, b in shared:
        np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-7)


def test_bad_lighting_and_a_rig_of_another_level_are_refused(lit_bsp: Path, tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "x.lpnncap"
    assert main(["scene", "import", str(lit_bsp), "--out", str(out), "--quiet", "--lighting", "sun"]) == 1
    assert "--lighting 'sun' must be 'grid' or 'rig:RIG.json'" in capsys.readouterr().err
    assert main(["scene", "import", str(lit_bsp), "--out", str(out), "--quiet", "--lighting",
                 f"rig:{tmp_path / 'missing.json'}"]) == 1
    assert "missing.json: cannot read the rig" in capsys.readouterr().err
    other = write_test_rig(tmp_path / "other.json", "0" * 64)
    assert main(["scene", "import", str(lit_bsp), "--out", str(out), "--quiet", "--lighting", f"rig:{other}"]) == 1
    error = capsys.readouterr().err
    assert "rig other.json was recovered from a level whose BSP hash is 000000000000" in error
    assert "lpnn scene lights lit --out RIG.json" in error and "Traceback" not in error
    assert not out.exists()
