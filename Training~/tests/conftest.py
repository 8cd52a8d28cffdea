"""Fixtures shared by every test folder: the OpenArena pak (real levels; skipped when not installed)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from lpnn.scenes.levels import DEBIAN_PAK, INSTALL_HINT, PAK_ENV


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
