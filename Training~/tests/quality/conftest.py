"""Shared fixtures of the quality tests: small synthetic rooms (lpnn.core.analytic_scene), built once."""

from __future__ import annotations

from pathlib import Path

import pytest

from lpnn.core.capture import Capture
from lpnn.core.capture_file import write_capture
from lpnn.quality.metric.metric import ReferenceField

from quality_support import MEDIUM_ROOM, room_capture


@pytest.fixture(scope="session")
def small_captures() -> dict[int, Capture]:
    return {seed: room_capture(seed) for seed in (1, 2, 3)}


@pytest.fixture(scope="session")
def small_field(small_captures: dict[int, Capture]) -> ReferenceField:
    return ReferenceField.from_capture(small_captures[1])


@pytest.fixture(scope="session")
def medium_capture() -> Capture:
    return room_capture(3, MEDIUM_ROOM, 0.4)


@pytest.fixture()
def capture_files(tmp_path: Path, small_captures: dict[int, Capture]) -> list[Path]:
    paths = []
    for seed, capture in small_captures.items():
        path = tmp_path / f"room{seed}.lpnncap"
        write_capture(path, capture)
        paths.append(path)
    return paths
