"""Shared fixtures for the core tests: the golden files of Tests/Data (written by the C# side)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

REPO_ROOT = Path(__file__).resolve().parents[3]  # tests/core -> tests -> Training~ -> repository root
GOLDEN_DIR = REPO_ROOT / "Tests" / "Data"


@pytest.fixture
def golden_path() -> Callable[[str], Path]:
    """Path of a golden file; skips the test while the C# side has not generated it yet."""

    def find(name: str) -> Path:
        path = GOLDEN_DIR / name
        if not path.exists():
            pytest.skip(f"golden file not generated yet: Tests/Data/{name}")
        return path

    return find


@pytest.fixture
def golden(golden_path) -> Callable[[str], Any]:
    """Parsed JSON of a golden file (skips while it does not exist)."""
    return lambda name: json.loads(golden_path(name).read_text(encoding="utf-8"))


@pytest.fixture
def assert_within() -> Callable[..., None]:
    """|actual - expected| <= abs + rel * |expected| elementwise, the README's tolerance rule."""

    def check(actual, expected, tolerance: dict, what: str) -> None:
        a = np.asarray(actual, dtype=np.float64)
        e = np.asarray(expected, dtype=np.float64)
        assert a.shape == e.shape, f"{what}: shape {a.shape} != {e.shape}"
        bad = np.abs(a - e) > tolerance["abs"] + tolerance["rel"] * np.abs(e)
        if np.any(bad):
            first = np.argwhere(bad)[0]
            raise AssertionError(f"{what}: {int(bad.sum())} values off, first at {first.tolist()}: "
                                 f"{a[tuple(first)]!r} vs expected {e[tuple(first)]!r}")

    return check
