"""Tools~/experiments/leak-variants.py: the leak-aware variants' rows and table, on an analytic room with a wall."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AnalyticScene, AxisBox
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.metric.leaks import leak_report, near_surface_mask
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.placement.refined_insertion import refined_insertion
from tools_support import load_tool

SCRIPT = "leak-variants.py"


def _walled_room() -> tuple[AnalyticScene, AnalyticBoxRaycaster]:
    """The analytic random room with a wall across it (lattice x = ..., 0, 0.5, ...: the wall holds no point)."""
    room = AnalyticScene.random(3, cell_size=0.5, room_size=(4.0, 2.5, 3.0))
    wall = AxisBox(min=[0.1, -10.0, -10.0], max=[0.4, 10.0, 10.0])
    rays = AnalyticBoxRaycaster(room.raycaster.room, room.raycaster.obstacles + (wall,))
    return AnalyticScene(cell_size=room.cell_size, boxes=room.boxes, light_field=room.light_field, raycaster=rays), rays


def test_one_row_per_variant_with_the_report_figures(capsys: pytest.CaptureFixture[str]) -> None:
    scene, rays = _walled_room()
    capture = scene.capture(name="walled")
    tool = load_tool(SCRIPT)
    rows = tool.measure("walled", "train", capture, rays, 0.05, ["default", "repair3", "aware4"])
    assert [row["variant"] for row in rows] == ["default", "repair3", "aware4"]
    printed = [json.loads(line) for line in capsys.readouterr().out.splitlines() if line.startswith("{")]
    assert [row["variant"] for row in printed] == ["default", "repair3", "aware4"]
    # The default's row, recomputed independently.
    field = ReferenceField.from_capture(capture)
    probes = refined_insertion(field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids),
                               tolerance=0.05).indices
    report = leak_report(field, probes, rays, near_surface=near_surface_mask(capture.feature_names, capture.features))
    assert rows[0]["probes"] == probes.shape[0] and rows[0]["added"] == 0.0
    assert rows[0]["leaking"] == pytest.approx(report.leaking_share)
    assert rows[0]["near"] == pytest.approx(report.near_surface_error)
    assert rows[1]["probes"] >= rows[0]["probes"] and rows[1]["leaking"] <= rows[0]["leaking"]  # repair only adds
    assert rows[2]["added"] == pytest.approx((rows[2]["probes"] - rows[0]["probes"]) / rows[0]["probes"])
    assert all(row["mean"] <= 0.05 + 1e-12 and row["seconds"] > 0 for row in rows)
    table = tool.table(rows).splitlines()
    assert len(table) == 2 + len(rows) and table[2].startswith("| walled (train) |")


def test_unknown_variants_are_refused() -> None:
    with pytest.raises(SystemExit, match="unknown variant"):
        load_tool(SCRIPT).main(["kaos", "--variants", "default,nonsense"])


def test_levels_get_the_recipes_roles(tmp_path) -> None:
    import zipfile
    pak = tmp_path / "pak.pk3"
    names = [f"maps/level{i:02d}.bsp" for i in range(20)] + ["maps/oa_ctf2.bsp", "textures/x.jpg"]
    with zipfile.ZipFile(pak, "w") as archive:
        for name in names:
            archive.writestr(name, b"")
    roles = load_tool(SCRIPT).level_roles(pak)
    assert set(roles) == {f"level{i:02d}" for i in range(20)} | {"oa_ctf2"}
    assert roles["level02"] == "held_out" and roles["level07"] == "held_out"  # every 5th from the 3rd
    assert np.count_nonzero([role == "validation" for role in roles.values()]) >= 1
