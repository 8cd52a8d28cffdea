"""Shared fixtures for the core tests (the golden-file fixtures are in tests/conftest.py)."""

from __future__ import annotations

from typing import Callable

import numpy as np
import pytest


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
