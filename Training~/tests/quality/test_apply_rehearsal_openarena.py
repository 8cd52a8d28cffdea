"""The editor-free rehearsal of the whole Apply on a real level (issue 31, Deliver 4; Documentation~/ci.md "Apply rehearsal").

Imports oa_dm1 (openarena-081-maps, never committed) at a 0.85 m cell (about 10^4 points), writes the capture,
`lpnn place --method insertion-refined --tolerance 0.05 --leaks ignore`'s answer and Python's whole insertion order to a temporary
folder, and runs the C# fixture Tests/Core/ApplyRehearsalTests.cs on it under Mono through nunit-console, with
Python's tetrahedralisation served by rehearsal_tetrahedralizer.py: the same tetrahedra, so the same order and probes
(quality.md §1 "Ties", §5.1 "Equal errors"). Leak-blind on both sides: the rehearsal has no level geometry to cast through
(a volume's default, which avoids leaks with physics casts, is rehearsed on the walled room of
Tests/Core/LeakAwareRefinementTests.cs). The default nunit-console run of Tools~/test.sh excludes that fixture's category: this
test is where `make test` runs it.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from lpnn.cli.main import main as lpnn_main
from lpnn.core.capture_file import write_capture
from lpnn.core.grid import EvaluationGrid
from lpnn.core.validity import valid_points, without_invalid
from lpnn.quality.placement.insertion import insertion_ranking
from lpnn.quality.metric.metric import ReferenceField
from lpnn.scenes.importer import import_level
from lpnn.scenes.levels import load_pak_member

pytestmark = pytest.mark.openarena

REPO = Path(__file__).resolve().parents[3]
TESTS_DLL = REPO / "Build~" / "Lpnn.Probes.Core.Tests.dll"
FIXTURE = "Lpnn.Probes.Core.Tests.ApplyRehearsalTests"
FOLDER_VARIABLE = "LPNN_REHEARSAL_DIR"  # ApplyRehearsalTests.FolderVariable
CELL = 0.85  # metres: oa_dm1 holds about 10^4 open points at this cell
TOLERANCE = 0.05
NUNIT_SECONDS = 300


def _rehearsal_folder(pak: Path, folder: Path) -> int:
    capture = import_level(load_pak_member(pak, "maps/oa_dm1.bsp"), cell_size=CELL, timings_in_source=False).capture
    capture = without_invalid(capture, valid_points(capture))  # what `lpnn place` places on; the editor's grid alike
    write_capture(folder / "level.lpnncap", capture)
    assert lpnn_main(["place", str(folder / "level.lpnncap"), "--method", "insertion-refined", "--tolerance", str(TOLERANCE),
                      "--leaks", "ignore", "--out", str(folder / "place.probes.json")]) == 0
    (folder / "tolerance.txt").write_text(f"{TOLERANCE}\n", encoding="utf-8")
    ranking = insertion_ranking(ReferenceField.from_capture(capture), EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids))
    (folder / "insertion_order.txt").write_text("".join(f"{p}\n" for p in ranking.tolist()), encoding="utf-8")
    server = Path(__file__).with_name("rehearsal_tetrahedralizer.py")
    (folder / "tetrahedralizer.sh").write_text(
        f"#!/bin/sh\nPYTHONPATH='{REPO / 'Training~'}' exec '{sys.executable}' '{server}' '{folder / 'level.lpnncap'}'\n",
        encoding="utf-8")
    return capture.point_count


def test_the_whole_apply_rehearsed_under_mono_matches_lpnn_place(openarena_pak: Path, tmp_path: Path) -> None:
    if shutil.which("nunit-console") is None or shutil.which("mono") is None:
        pytest.skip("Mono and nunit-console are not installed (Tools~/install-system.sh)")
    if not TESTS_DLL.is_file():
        subprocess.run(["bash", str(REPO / "Tools~" / "build-csharp.sh")], check=True)
    points = _rehearsal_folder(openarena_pak, tmp_path)
    assert 10_000 <= points <= 100_000
    result = subprocess.run(["nunit-console", "-nologo", f"-run={FIXTURE}", f"-xml={tmp_path / 'nunit.xml'}", TESTS_DLL.name],
                            cwd=TESTS_DLL.parent, env={**os.environ, FOLDER_VARIABLE: str(tmp_path)},
                            capture_output=True, text=True, timeout=NUNIT_SECONDS)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Tests run: 3, Errors: 0, Failures: 0" in result.stdout, result.stdout
    assert "nothing written" in result.stdout and "mean error: rehearsal" in result.stdout, result.stdout
