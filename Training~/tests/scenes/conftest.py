"""Fixtures of the scene importer tests: a synthetic level (no game data) and the OpenArena pak."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from lpnn.scenes.levels import DEBIAN_PAK, INSTALL_HINT, PAK_ENV
from synthetic_bsp import make_level


@pytest.fixture
def level_bytes() -> bytes:
    return make_level().to_bytes()


@pytest.fixture
def bsp_path(tmp_path: Path, level_bytes: bytes) -> Path:
    path = tmp_path / "synthetic.bsp"
    path.write_bytes(level_bytes)
    return path


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
