"""Tools~/experiments/lights-backends.py (lights.md §3, benchmarks.md §8) on the synthetic lit level: numpy and
TensorFlow compute the same objective and gradient, Embree casts, and a library that is not installed says so."""

from __future__ import annotations

import re
import sys
from pathlib import Path

from tools_support import REPO, run_experiment

sys.path[:0] = [str(REPO / "Training~" / "tests" / "lights"), str(REPO / "Training~" / "tests" / "scenes")]
from lit_bsp import lit_level  # noqa: E402  (the light-rig tests' synthetic level)


def test_every_backend_on_the_lit_level(tmp_path: Path) -> None:
    level = tmp_path / "lit.bsp"
    level.write_bytes(lit_level().to_bytes())
    out = run_experiment("lights-backends.py", str(level)).stdout
    assert re.search(r"^lit: \d+ target points, \d+ lights, [0-9,]+ visible pairs", out, re.M), out
    assert re.search(r"^numpy analytic \(float64\): +\d+ ms per objective \+ gradient", out, re.M)
    tensorflow = re.search(r"objective ([0-9.]+) vs ([0-9.]+), largest gradient difference ([0-9.e+-]+)", out)
    assert tensorflow and tensorflow.group(1) == tensorflow.group(2) and float(tensorflow.group(3)) < 1e-9
    assert re.search(r"^embree \(embreex, \d+ threads\): +[0-9,]+ rays/s", out, re.M)
    for library in ("drjit llvm_ad_rgb (float32)", "mitsuba"):  # not project dependencies: timed or "not installed"
        assert re.search(rf"^{re.escape(library)}: +(not installed|\d)", out, re.M), out
