"""The leak-aware default of `lpnn place` and `lpnn bench` (leaks.md "A leak-aware default"): `--leaks avoid` (the
default) places leak-aware where the capture's geometry is known, says in one stderr line when it is not (and places
leak-blind), and `--leaks ignore` is the leak-blind placement. The geometry is a wall across a synthetic room, given
through capture_raycaster as an OpenArena import's level would be."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import lpnn.quality.metric.leaks as leaks_module
from lpnn.cli.main import main
from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AxisBox
from lpnn.core.capture import Capture
from lpnn.core.capture_file import write_capture
from lpnn.quality.bench.results import BenchConfig
from lpnn.quality.bench.run import bench_capture
from lpnn.quality.placement.leak_aware import NO_GEOMETRY

from quality_support import MEDIUM_ROOM, room_capture

NO_GEOMETRY_START = NO_GEOMETRY.split("(")[0].strip()


@pytest.fixture(scope="module")
def room() -> Capture:
    return room_capture(3, MEDIUM_ROOM, 0.4)


def _wall(capture: Capture) -> AnalyticBoxRaycaster:
    """A slab across the whole room, between the two lattice columns nearest its middle (no point inside it)."""
    xs = np.unique(capture.positions[:, 0].astype(np.float64))
    middle = xs[xs.shape[0] // 2]
    gap = float(xs[1] - xs[0])
    return AnalyticBoxRaycaster(obstacles=(AxisBox(min=np.array([middle + 0.3 * gap, -100.0, -100.0]),
                                                   max=np.array([middle + 0.7 * gap, 100.0, 100.0])),))


def _place(path: Path, out: Path, *extra: str) -> dict:
    assert main(["place", str(path), "--tolerance", "0.05", "--out", str(out), *extra]) == 0
    return json.loads(out.read_text(encoding="utf-8"))


def test_place_avoids_leaks_by_default_where_the_geometry_is_known(room: Capture, tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, room)
    wall = _wall(room)
    monkeypatch.setattr(leaks_module, "capture_raycaster", lambda capture, pak=None: (wall, ""))
    default = _place(path, tmp_path / "default.json")
    avoid = _place(path, tmp_path / "avoid.json", "--leaks", "avoid")
    ignore = _place(path, tmp_path / "ignore.json", "--leaks", "ignore")
    assert NO_GEOMETRY_START not in capsys.readouterr().err  # the geometry is known: nothing to warn about
    assert default["positions"] == avoid["positions"]  # avoid is the default
    # The wall makes the leak-blind placement leak; the default leaks less for more probes, within tau.
    assert ignore["source"]["leaking"] > 0
    assert avoid["source"]["leaking"] < ignore["source"]["leaking"]
    assert len(avoid["positions"]) > len(ignore["positions"])
    assert avoid["source"]["mean_error"] <= 0.05


def test_place_without_geometry_says_so_once_and_places_leak_blind(room: Capture, tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, room)  # an analytic capture: the tools cannot load its geometry
    avoid = _place(path, tmp_path / "avoid.json")
    err = capsys.readouterr().err
    assert err.count(NO_GEOMETRY) == 1 and f"room.lpnncap: {NO_GEOMETRY}" in err
    ignore = _place(path, tmp_path / "ignore.json", "--leaks", "ignore")
    assert NO_GEOMETRY_START not in capsys.readouterr().err  # told to ignore leaks: nothing to say
    assert avoid["positions"] == ignore["positions"]
    assert "leaking" not in avoid["source"]  # nothing to check leaks with: not reported either


def test_place_refuses_an_unknown_leaks_choice(room: Capture, tmp_path: Path) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, room)
    with pytest.raises(SystemExit):
        main(["place", str(path), "--leaks", "sometimes", "--tolerance", "0.05", "--out", str(tmp_path / "x.json")])


def test_bench_insertion_refined_row_is_the_default_placement(room: Capture) -> None:
    wall = _wall(room)

    def row(leaks: str, geometry: AnalyticBoxRaycaster | None):
        config = BenchConfig(budgets=(), methods=frozenset({"insertion-refined"}), yardstick="none", repeats=1,
                             leaks=leaks)
        rows = [r for r in bench_capture("room", room, config, geometry=geometry).rows if r.method == "insertion-refined"]
        assert len(rows) == 1
        return rows[0]

    avoid, ignore = row("avoid", wall), row("ignore", wall)
    assert avoid.leaking < ignore.leaking and avoid.probes > ignore.probes and avoid.mean_error <= 0.05
    without = row("avoid", None)  # no geometry: leak-blind (and nothing to report leaks with)
    assert without.probes == ignore.probes and without.leaking != without.leaking


def test_bench_cli_says_when_the_default_row_cannot_avoid_leaks(room: Capture, tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, room)
    common = ["bench", str(path), "--methods", "insertion-refined", "--no-budgets", "--no-reference", "--repeats", "1"]
    assert main([*common, "--out", str(tmp_path / "avoid")]) == 0
    assert f"room: insertion-refined: {NO_GEOMETRY}" in capsys.readouterr().err
    assert main([*common, "--leaks", "ignore", "--out", str(tmp_path / "ignore")]) == 0
    assert NO_GEOMETRY_START not in capsys.readouterr().err


def test_guided_refined_avoids_leaks_as_the_default_does(room: Capture, tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """guided-refined is refined in batches like the default, so it follows --leaks too (as Unity's Guided insertion,
    refined follows Avoid light leaks); with flat scores its guide weighs every point alike."""
    path = tmp_path / "room.lpnncap"
    write_capture(path, room)
    scores = tmp_path / "scores.csv"
    ids = room.ids
    scores.write_text("index,i,j,k,score\n" + "".join(f"{n},{i},{j},{k},0.5\n" for n, (i, j, k) in enumerate(ids)),
                      encoding="utf-8")
    wall = _wall(room)
    monkeypatch.setattr(leaks_module, "capture_raycaster", lambda capture, pak=None: (wall, ""))
    guided = ("--method", "guided-refined", "--scores", str(scores))
    avoid = _place(path, tmp_path / "avoid.json", *guided)
    ignore = _place(path, tmp_path / "ignore.json", *guided, "--leaks", "ignore")
    assert ignore["source"]["leaking"] > 0
    assert avoid["source"]["leaking"] < ignore["source"]["leaking"]
    assert avoid["source"]["mean_error"] <= 0.05


def test_lpnn_placement_takes_leaks_only_with_the_refinement_in_batches(room: Capture) -> None:
    from lpnn.quality.placement.lpnn_placement import lpnn_placement
    from lpnn.quality.placement.policies import PolicyError

    with pytest.raises(PolicyError, match="batched"):
        lpnn_placement(room, scores=np.full(room.point_count, 0.5), tolerance=0.05, guided=True, leaks=_wall(room))


def test_place_leak_aware_reference_leaks_less_than_the_fast_one_within_its_weighted_tau(
        room: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    from lpnn.quality.metric.leaks import leaking_points
    from lpnn.quality.metric.metric import ReferenceField
    from lpnn.quality.placement.leak_aware import LEAK_WEIGHT

    path = tmp_path / "room.lpnncap"
    write_capture(path, room)
    wall = _wall(room)
    monkeypatch.setattr(leaks_module, "capture_raycaster", lambda capture, pak=None: (wall, ""))
    blind = _place(path, tmp_path / "blind.json", "--method", "fast-reference")
    aware = _place(path, tmp_path / "aware.json", "--method", "leak-aware-reference")
    assert aware["source"]["method"] == "leak-aware-reference"
    assert "leak-weighted mean error" in capsys.readouterr().out
    assert blind["source"]["leaking"] > 0 and aware["source"]["leaking"] < blind["source"]["leaking"]
    # Its answer's leak-weighted mean error, evaluated afresh, is within tau; the plain one is what the file reports.
    field = ReferenceField.from_capture(room)
    positions = {tuple(p) for p in np.round(np.asarray(aware["positions"], dtype=np.float64), 4).tolist()}
    probes = np.flatnonzero([tuple(p) in positions for p in np.round(room.positions.astype(np.float64), 4).tolist()])
    assert probes.shape[0] == len(aware["positions"])
    leaking, errors = leaking_points(field, probes, wall)
    assert float(np.mean(np.where(leaking, LEAK_WEIGHT * errors, errors))) <= 0.05 + 1e-12
    assert aware["source"]["mean_error"] == pytest.approx(float(errors.mean()), abs=1e-6)


@pytest.mark.parametrize("extra, message", [((), "use --method fast-reference"),
                                            (("--leaks", "ignore"), "use --method fast-reference"),
                                            (("--workers", "2"), "drop --workers 2")])
def test_place_leak_aware_reference_refuses_what_it_cannot_do(room: Capture, tmp_path: Path,
                                                              monkeypatch: pytest.MonkeyPatch,
                                                              capsys: pytest.CaptureFixture[str], extra,
                                                              message) -> None:
    path = tmp_path / "room.lpnncap"
    write_capture(path, room)  # no geometry, unless the options are refused before it matters
    if extra:
        monkeypatch.setattr(leaks_module, "capture_raycaster", lambda capture, pak=None: (_wall(room), ""))
    code = main(["place", str(path), "--method", "leak-aware-reference", "--tolerance", "0.05", "--out",
                 str(tmp_path / "x.json"), *extra])
    assert code != 0 and message in capsys.readouterr().err
    assert not (tmp_path / "x.json").exists()


def test_bench_measures_the_leak_aware_rows_against_both_references(room: Capture) -> None:
    wall = _wall(room)
    config = BenchConfig(budgets=(0.05, 0.2), tolerance=0.05, repeats=1,
                         methods=frozenset({"insertion-refined", "leak-aware-reference"}))
    rows = bench_capture("room", room, config, geometry=wall).rows
    by = {(r.method, r.policy, r.parameter): r for r in rows}
    for policy, parameter in (("budget", 0.05), ("budget", 0.2), ("tolerance", 0.05)):
        default, aware = by[("insertion-refined", policy, parameter)], by[("leak-aware-reference", policy, parameter)]
        blind = by[("fast-reference", policy, parameter)]
        assert aware.leaking < blind.leaking or (aware.leaking == 0.0 and blind.leaking == 0.0)
        if policy == "budget":  # the same count: each ratio divides by that reference's own row
            assert default.probes == aware.probes == blind.probes
            assert default.error_ratio == pytest.approx(default.mean_error / blind.mean_error)
            assert default.leak_error_ratio == pytest.approx(default.mean_error / aware.mean_error)
        else:
            assert default.probes_ratio == pytest.approx(default.probes / blind.probes)
            assert default.leak_reference_probes == aware.probes and aware.probes > blind.probes
            assert default.leak_probes_ratio == pytest.approx(default.probes / aware.probes)
        assert default.yardstick == "fast-reference" and aware.leak_error_ratio != aware.leak_error_ratio  # NaN
    # Without the geometry, or told to ignore leaks, nothing is leak-aware: no such rows, no such ratios.
    for geometry, leaks in ((None, "avoid"), (wall, "ignore")):
        plain = bench_capture("room", room, BenchConfig(budgets=(0.2,), tolerance=0.05, repeats=1, leaks=leaks,
                                                         methods=config.methods), geometry=geometry).rows
        assert {r.method for r in plain} == {"insertion-refined", "fast-reference"}
        assert all(r.leak_error_ratio != r.leak_error_ratio and r.leak_reference_probes is None for r in plain)
