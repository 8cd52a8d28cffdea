"""End to end on the synthetic level: import, capture content, determinism, CLI, pack check."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.main import main
from lpnn.core.capture_encoder import encode_capture
from lpnn.core.capture_file import read_capture
from lpnn.core.grid import GridError
from lpnn.core.grid_box import Box
from lpnn.scenes.coords import METRES_PER_UNIT, quake_to_unity, unity_to_quake
from lpnn.scenes.errors import BspError
from lpnn.scenes.defaults import DEFAULT_CELL
from lpnn.scenes.importer import import_level
from lpnn.scenes.levels import load_level
from lpnn.scenes.lightgrid import LightGrid
from lpnn.scenes.pack import check_pack
from synthetic_bsp import make_level, write_pk3

# Auto bounds = the grid's extent (0..256 Quake units a side) = 5 x 5 x 5 lattice points at 64 units.
# Removed: the 8 on or in the cube brush [0,64]^3, and the 50 with x >= 192 (outside the map).
LATTICE, REMOVED = 125, 58


def test_default_cell_is_64_units() -> None:
    assert DEFAULT_CELL == pytest.approx(1.6256)


# 26 feature rays per point, and the in-use report rule's floor rays: reachable's (its one seed attaches to nothing),
# then band's, one per point each.
RAYS = 67 * 26 + 2 * 67


def test_import_removes_solid_and_samples_the_grid(bsp_path: Path) -> None:
    result = import_level(str(bsp_path), timings_in_source=False)
    capture = result.capture
    assert (result.lattice_points, result.removed_solid, capture.point_count) == (LATTICE, REMOVED, LATTICE - REMOVED)
    quake = np.rint(unity_to_quake(capture.positions.astype(np.float64))).astype(int)
    assert not ((quake <= 64).all(axis=1)).any()  # nothing left in or on the cube
    assert (quake[:, 0] < 192).all()  # nothing outside the map
    assert {tuple(p) for p in quake} >= {(128, 128, 128), (0, 0, 128), (128, 0, 0)}
    level = load_level(str(bsp_path))
    expected, lit = LightGrid.from_bsp(level.bsp).sh_at(capture.positions)
    assert np.array_equal(capture.sh, expected.astype(np.float32)) and lit.all()
    assert capture.units == "m" and capture.cell_size == DEFAULT_CELL and capture.schema == "lpnn.features.v1"
    assert capture.features.shape == (67, 19) and np.isfinite(capture.features).all()
    assert capture.source == {
        "backend": "openarena", "level": "synthetic", "bsp_sha256": level.sha256, "importer": "lpnn 0.1.0",
        "bounds": "auto", "patch_level": 8, "rays": RAYS, "validity": "bsp", "removed_solid": REMOVED,
        "removed_invalid": 0, "unlit_points": 0, "removed_unlit": 0, "lighting": "grid", "in_use": "all",
        "in_use_band_height": 3.0, "in_use_slope_limit": 45.0, "in_use_step_height": 0.5, "in_use_seeds": 1,
        "points_before_in_use": 67, "in_use_report_rule": "band",
    }
    # The level's one spawn attaches to no point within the band (reachable fails), so the report mask is the band's.
    assert capture.extra_sections["in_use"].dtype == np.uint8 and 0 < capture.extra_sections["in_use"].sum() < 67
    assert result.rays == RAYS


def test_same_level_and_cell_give_identical_bytes(bsp_path: Path) -> None:
    first = encode_capture(import_level(str(bsp_path), timings_in_source=False).capture)
    second = encode_capture(import_level(str(bsp_path), timings_in_source=False).capture)
    assert first == second
    timed = import_level(str(bsp_path)).capture
    assert set(timed.source) - set(import_level(str(bsp_path), timings_in_source=False).capture.source) == {"feature_seconds"}


def test_unlit_points_are_black_or_dropped(tmp_path: Path) -> None:
    level = make_level()
    cells = bytearray(level.light_grid)
    cells[8 * 50:] = bytes(8 * 25)  # the top layer of the grid (Quake z = 256) is all zero
    level.light_grid = bytes(cells)
    path = tmp_path / "dark_top.bsp"
    path.write_bytes(level.to_bytes())
    kept = import_level(str(path))
    top = np.isclose(kept.capture.positions[:, 1], 256 * METRES_PER_UNIT)  # Unity y = Quake z
    assert kept.unlit_points == 15 == top.sum() and kept.capture.source["unlit_points"] == 15
    assert np.all(kept.capture.sh[top] == 0) and np.all(kept.capture.sh[~top, 0] > 0)
    dropped = import_level(str(path), drop_unlit=True)
    assert (dropped.capture.point_count, dropped.removed_unlit, dropped.unlit_points) == (67 - 15, 15, 0)
    assert dropped.capture.source["removed_unlit"] == 15 and np.all(dropped.capture.sh[:, 0] > 0)


def test_user_bounds_and_their_errors(bsp_path: Path) -> None:
    centre = quake_to_unity(np.array([128.0, 128.0, 128.0]))
    box = Box.axis_aligned(centre - 0.01, centre + 0.01)
    result = import_level(str(bsp_path), boxes=[box], bounds_label="box")
    assert result.capture.point_count == 1 and result.capture.source["bounds"] == "box"
    inside_cube = quake_to_unity(np.array([32.0, 32.0, 32.0]))  # half a cell: touches the 8 cube corners
    with pytest.raises(BspError, match="all 8 evaluation points of the bounds are in solid"):
        import_level(str(bsp_path), boxes=[Box.axis_aligned(inside_cube, inside_cube)])
    with pytest.raises(BspError, match="67 evaluation points remain .* more than the point limit 50"):
        import_level(str(bsp_path), point_limit=50)
    with pytest.raises(GridError, match="before removing points in solid .* point limit 10.*125 evaluation points"):
        import_level(str(bsp_path), point_limit=10)


def test_cli_import_info_and_errors(bsp_path: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "room.lpnncap"
    assert main(["scene", "import", str(bsp_path), "--out", str(out), "--quiet", "--reproducible", "--in-use", "all"]) == 0
    printed = capsys.readouterr().out
    assert "67 points of 125 (58 in solid or outside removed, 0 unlit removed, 0 unlit kept)" in printed
    assert read_capture(out).point_count == 67
    # The default on a level without spawns or items: the band rule, said so; fewer points than all of them.
    assert main(["scene", "import", str(bsp_path), "--out", str(out), "--quiet", "--reproducible"]) == 0
    printed = capsys.readouterr().out
    band = read_capture(out)
    assert "the points in use are the band's instead" in printed and band.source["in_use"] == "band"
    assert 0 < band.point_count < 67 and band.source["points_before_in_use"] == 67
    assert main(["scene", "import", str(bsp_path), "--out", str(out), "--quiet", "--in-use", "reachable"]) == 1
    assert "seed" in capsys.readouterr().err

    folder = tmp_path / "dataset"
    for _ in range(2):
        assert main(["scene", "import", str(bsp_path), "--append-to", str(folder), "--quiet"]) == 0
    assert sorted(p.name for p in folder.iterdir()) == ["synthetic-2.lpnncap", "synthetic.lpnncap"]

    assert main(["scene", "info", str(bsp_path)]) == 0
    info = capsys.readouterr().out
    assert "5x5x3 = 75 points, cell 64 x 64 x 128 units" in info and "entities       4 (2 lights)" in info
    assert "130 triangles" in info

    broken = tmp_path / "broken.bsp"
    broken.write_bytes(b"VBSP" + bsp_path.read_bytes()[4:])
    assert main(["scene", "import", str(broken), "--out", str(out), "--quiet"]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("lpnn scene: error:") and "magic is b'VBSP'" in error and "\n" not in error
    assert main(["scene", "import", str(bsp_path), "--out", str(out), "--bounds", "1,2,3"]) == 1
    assert "six finite numbers" in capsys.readouterr().err
    assert main(["scene", "import", str(bsp_path), "--out", str(out), "--cell", "0"]) == 1
    assert "--cell 0.0 must be" in capsys.readouterr().err


def test_pack_check_reports_every_failing_level(tmp_path: Path, level_bytes: bytes,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    no_grid = make_level()
    no_grid.light_grid = b""
    pak = write_pk3(tmp_path / "test.pk3", {
        "maps/good.bsp": level_bytes,
        "maps/cut.bsp": level_bytes[:300],
        "maps/dark.bsp": no_grid.to_bytes(),
    })
    results = {Path(r.member).stem: r for r in check_pack(pak)}
    assert results["good"].ok and results["good"].points == 67
    assert not results["cut"].ok and "test.pk3:maps/cut.bsp" in results["cut"].reason and "truncated" in results["cut"].reason
    assert not results["dark"].ok and "compiled without light" in results["dark"].reason

    assert main(["scene", "check-pack", str(pak), "--levels", "good", "--out", str(tmp_path / "caps")]) == 0
    assert (tmp_path / "caps" / "good.lpnncap").is_file()
    assert main(["scene", "check-pack", str(pak)]) == 1
    summary = capsys.readouterr().out
    assert "1 of 3 levels imported" in summary and "2 failed" in summary and "dark:" in summary
    assert main(["scene", "check-pack", str(pak), "--levels", "nope"]) == 1


@pytest.mark.parametrize("validity", ["bsp", "rays", "both"])
def test_validity_modes_remove_what_each_test_finds(bsp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                    validity: str) -> None:
    # The ray rule is stubbed to flag every point below z = 100 Quake units, so the test sees exactly where the
    # importer applies it (the rule itself: tests/core/test_validity_*.py).
    judged: list[int] = []

    def below_100_units(positions: np.ndarray, raycaster: object) -> np.ndarray:
        judged.append(len(positions))
        return np.where(unity_to_quake(positions)[:, 2] < 100, 1.0, 0.0)

    monkeypatch.setattr("lpnn.scenes.importer.back_face_fractions", below_100_units)
    result = import_level(str(bsp_path), timings_in_source=False, validity=validity)
    quake = unity_to_quake(result.capture.positions.astype(np.float64))
    low = 2 * 25  # lattice points at z = 0 and 64 units: two layers of 5 x 5
    low_open = low - 8 - 2 * 10  # minus the cube's 8 corners and the 2 x 10 low points with x >= 192
    expected = {"bsp": (REMOVED, 0), "rays": (0, low), "both": (REMOVED, low_open)}[validity]
    assert (result.removed_solid, result.removed_invalid) == expected
    assert result.capture.point_count == LATTICE - sum(expected)
    assert result.capture.source["validity"] == validity
    assert result.capture.source["removed_invalid"] == expected[1]
    if validity == "bsp":
        assert judged == []
    else:
        assert not (quake[:, 2] < 100).any()
        assert judged == [LATTICE if validity == "rays" else LATTICE - REMOVED]


def test_unknown_validity_mode_is_refused(bsp_path: Path) -> None:
    with pytest.raises(ValueError, match="validity 'walls' must be one of bsp, rays, both"):
        import_level(str(bsp_path), validity="walls")
