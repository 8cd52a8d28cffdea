"""Constants and types shared by the trainer tests (a uniquely named module: other test folders
have their own conftest.py, so tests import from here, never from `conftest`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

CAPTURE_COUNT = 8
TINY_CONFIG = {"epochs": 8, "steps_per_epoch": 12, "batch_clouds": 4, "max_points": 512, "patience": 3}
REPO_ROOT = Path(__file__).resolve().parents[3]


@dataclass(frozen=True)
class TrainedModel:
    dataset: Path
    model: Path
    card: Path
    checkpoint: Path
    config: Path
