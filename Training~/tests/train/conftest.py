"""Shared fixtures of the trainer tests: a tiny synthetic dataset and one model trained via the CLI.

Each capture is a separate scene (its own shift and scale of the features); the label rule
f3 + 0.5 f7 > 1.4 is learnable, so a few hundred gradient steps reach ROC-AUC > 0.9 on held-out
captures. Everything heavy happens once per session.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lpnn.core.capture_file import write_capture
from lpnn.train.synthetic import synthetic_capture

from train_support import CAPTURE_COUNT, TINY_CONFIG, TrainedModel


@pytest.fixture(scope="session")
def dataset_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("dataset")
    for seed in range(CAPTURE_COUNT):
        write_capture(folder / f"scene_{seed}.lpnncap", synthetic_capture(seed))
    return folder


@pytest.fixture(scope="session")
def tiny_config_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("config") / "tiny.json"
    path.write_text(json.dumps(TINY_CONFIG), encoding="utf-8")
    return path


@pytest.fixture(scope="session")
def trained(dataset_dir: Path, tiny_config_file: Path, tmp_path_factory: pytest.TempPathFactory) -> TrainedModel:
    """`lpnn train` on the synthetic dataset (the CLI round trip's first half)."""
    from lpnn.cli.main import main

    out = tmp_path_factory.mktemp("model") / "model.onnx"
    code = main(["train", str(dataset_dir), "--out", str(out), "--config", str(tiny_config_file), "--quiet"])
    assert code == 0
    return TrainedModel(dataset=dataset_dir, model=out, card=out.with_suffix(".card.json"),
                        checkpoint=out.with_suffix(".ckpt.npz"), config=tiny_config_file)
