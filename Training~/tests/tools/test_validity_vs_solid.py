"""Tools~/experiments/validity-vs-solid.py (openarena.md "Probe validity in the importer") on one real level at a coarse
cell: the three classes add up to the lattice, and each ray length's line counts within them."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tools_support import run_experiment

pytestmark = pytest.mark.openarena


def test_classes_and_rates_on_a_real_level(openarena_pak: Path) -> None:
    out = run_experiment("validity-vs-solid.py", str(openarena_pak), "oa_dm1", "--cell", "4").stdout
    classes = re.search(r"oa_dm1: (\d+) points: open (\d+), in solid brush (\d+), void (\d+)", out)
    assert classes, out
    points, open_, solid, void = (int(g) for g in classes.groups())
    assert points == open_ + solid + void and open_ > 0 and solid > 0
    for length in ("long", "feature"):
        rates = re.search(rf"{length} +rays: open flagged (\d+) .*solid caught (\d+) .*void caught (\d+) .*"
                          r"agreement ([0-9.]+)", out)
        assert rates, out
        flagged, caught, void_caught, agreement = (float(g) for g in rates.groups())
        assert flagged <= open_ and 0 < caught <= solid and void_caught <= void and 0 < agreement <= 1
