"""The project's docs and code cite real sources, never a folder outside the repository, and every `Tools~/...` path they
name exists (a moved script leaves no stale reference)."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
OUTSIDE = "../shared"


def test_no_file_cites_a_folder_outside_the_repository() -> None:
    files = [*REPO.glob("*.md"), *(REPO / "Documentation~").rglob("*.md"), *(REPO / "Training~" / "lpnn").rglob("*.py"),
             *(REPO / "Packages").rglob("*.cs"), *(REPO / "Packages").rglob("*.md")]
    citing = [str(f.relative_to(REPO)) for f in files if OUTSIDE in f.read_text(encoding="utf-8", errors="replace")]
    assert citing == []


def test_every_tools_path_cited_exists() -> None:
    files = [*REPO.glob("*.md"), *(REPO / "Documentation~").rglob("*.md"), *(REPO / "Training~").rglob("*.py"),
             *(REPO / "Training~").rglob("*.md"), *(REPO / "Tools~").rglob("*.py"), *(REPO / "Tools~").rglob("*.sh"),
             *(REPO / "Tools~").rglob("*.md"), *(REPO / "Packages").rglob("*.cs"), *(REPO / "Tests").rglob("*.cs"),
             *(REPO / "Packages").rglob("*.md"), REPO / "Makefile"]
    cited = {(str(f.relative_to(REPO)), path.rstrip(".,:;)"))
             for f in files if f.name != "CHANGELOG.md"
             for path in re.findall(r"Tools~/[A-Za-z0-9_./*-]+", f.read_text(encoding="utf-8", errors="replace"))
             if "NAME" not in path}  # Tools~/experiments/NAME.py: a placeholder
    assert len(cited) > 50  # the docs were read
    missing = sorted((where, path) for where, path in cited if not any(REPO.glob(path)))
    assert missing == []
