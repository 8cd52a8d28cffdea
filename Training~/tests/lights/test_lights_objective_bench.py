"""objective_bench.py (the measurement lights.md §3 and benchmarks.md "The light rig" cite) runs on the synthetic lit level: it prints
one row per implementation — the compiled pass on 1 and on every thread, numpy, TensorFlow's autodiff — with gradients
that agree with the autodiff, and the visibility refresh's rows."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from lit_bsp import lit_level
from objective_bench import main


def test_the_bench_prints_every_implementation_agreeing_with_autodiff(tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    level = tmp_path / "lit.bsp"
    level.write_bytes(lit_level().to_bytes())
    assert main([str(level)]) in (0, None)
    out = capsys.readouterr().out
    rows = re.findall(r"^(numba analytic, 1 thread \(shipped\)|numba analytic, \d+ threads|numpy analytic|tensorflow "
                      r"autodiff) +[\d.]+ ms per objective \+ gradient; objective [\d.]+; largest difference to autodiff "
                      r"([\d.e+-]+)$", out, flags=re.MULTILINE)
    assert [name.split(",")[0].split(" ")[0] for name, _ in rows] == ["numba", "numba", "numpy", "tensorflow"], out
    assert all(float(difference) <= 1e-9 for _, difference in rows), out
    assert "target points" in out and "visible pairs" in out
