"""Fixtures of the scene importer tests: a synthetic level (no game data); the OpenArena pak is in ../conftest.py."""

from __future__ import annotations

from pathlib import Path

import pytest

from synthetic_bsp import make_level


@pytest.fixture
def level_bytes() -> bytes:
    return make_level().to_bytes()


@pytest.fixture
def bsp_path(tmp_path: Path, level_bytes: bytes) -> Path:
    path = tmp_path / "synthetic.bsp"
    path.write_bytes(level_bytes)
    return path
