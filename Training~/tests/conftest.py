"""Fixtures shared by every test folder: the golden files of Tests/Data, the OpenArena pak (real levels;
skipped when not installed)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Callable

import pytest

from lpnn.scenes.levels import DEBIAN_PAK, INSTALL_HINT, PAK_ENV

REPO_ROOT = Path(__file__).resolve().parents[2]  # tests -> Training~ -> repository root
GOLDEN_DIR = REPO_ROOT / "Tests" / "Data"


def golden_file(name: str) -> Path:
    """Path of a golden file of Tests/Data. A missing one fails the test: the cross-language suites must
    never drop out silently (e.g. after Tests/Data was moved)."""
    path = GOLDEN_DIR / name
    if not path.is_file():
        pytest.fail(f"golden file missing: {path}; restore it or regenerate it with Tools~/regenerate-golden.sh")
    return path


@pytest.fixture(scope="session")
def golden_path() -> Callable[[str], Path]:
    return golden_file


@pytest.fixture(scope="session")
def golden() -> Callable[[str], Any]:
    """Parsed JSON of a golden file (fails when it is missing)."""
    return lambda name: json.loads(golden_file(name).read_text(encoding="utf-8"))


@pytest.fixture(scope="session")
def openarena_pak() -> Path:
    """The pak under test: LPNN_OPENARENA_PAK must exist when set; else the Debian path, or skip."""
    configured = os.environ.get(PAK_ENV)
    if configured:
        if not Path(configured).is_file():
            pytest.fail(f"{PAK_ENV}={configured} but that file does not exist; {INSTALL_HINT}")
        return Path(configured)
    if not DEBIAN_PAK.is_file():
        pytest.skip(f"OpenArena levels not installed ({DEBIAN_PAK} missing); {INSTALL_HINT}")
    return DEBIAN_PAK
