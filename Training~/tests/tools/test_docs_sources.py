"""The project's docs and code cite real sources, never a folder outside the repository."""

from __future__ import annotations

from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
OUTSIDE = "../shared"


def test_no_file_cites_a_folder_outside_the_repository() -> None:
    files = [*REPO.glob("*.md"), *(REPO / "Documentation~").rglob("*.md"), *(REPO / "Training~" / "lpnn").rglob("*.py"),
             *(REPO / "Packages").rglob("*.cs"), *(REPO / "Packages").rglob("*.md")]
    citing = [str(f.relative_to(REPO)) for f in files if OUTSIDE in f.read_text(encoding="utf-8", errors="replace")]
    assert citing == []
