"""Tools~/experiments/benchmarks.sh (benchmarks.md "Real levels as captures", "References and scale-out", "The network", "The default model on its held-out levels") on tiny inputs: every part runs and prints its figures."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tools_support import run_experiment

pytestmark = [pytest.mark.openarena, pytest.mark.slow]


def test_every_part_on_tiny_inputs(openarena_pak: Path, tmp_path: Path) -> None:
    done = run_experiment("benchmarks.sh", env={
        "LPNN_OPENARENA_PAK": str(openarena_pak), "OUT": str(tmp_path), "SCENES": "oa_dm1", "ROOM_CELL": "1.0",
        "REFERENCE_LEVELS": "oa_dm1:4", "WORKERS": "1 2",
        "MODEL_BENCH_OPTIONS": "--sizes 1000 --repeats 1 --train-steps 1 --no-thesis"})
    out, err = done.stdout, done.stderr
    assert "oa_dm1.lpnncap: 607 points" in out  # scenes: the level at the default cell, its points in use
    for capture in ("room", "oa_dm1@4"):  # reference: one process, then two (the second receives the field)
        for workers in (1, 2):
            assert re.search(rf"^{re.escape(capture)}: fast reference, {workers} process\(es\), read to write: [0-9.]+ s",
                             err, re.M), err
    assert "onnxruntime scoring" in out and re.search(r"training: [0-9,]+ real points/s", out)  # model
    assert "the held-out table agrees with lpnn_default.card.json" in out  # report
