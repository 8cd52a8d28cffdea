"""Tests/Data/leaks_golden.json: the leak rule's decisions, made by construction (Tools~/golden/make_leaks_golden.py),
the same in C# (Tests/Core/LeakCheckTests.cs)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AxisBox
from lpnn.core.segments import segments_free
from lpnn.quality.metric.leak_rule import LEAK_MIN_WEIGHT, stencil_leaks

GOLDEN = Path(__file__).resolve().parents[3] / "Tests" / "Data" / "leaks_golden.json"


def test_every_case_leaks_as_built():
    golden = json.loads(GOLDEN.read_text(encoding="utf-8"))
    assert golden["minimum_weight"] == LEAK_MIN_WEIGHT
    rays = AnalyticBoxRaycaster(obstacles=tuple(AxisBox.from_json(b) for b in golden["obstacles"]))
    probes = np.array(golden["probes"])
    cases = golden["cases"]
    points = np.array([c["point"] for c in cases])
    vertices = np.array([c["vertices"] for c in cases])
    leaks = stencil_leaks(points, probes, vertices, np.array([c["weights"] for c in cases]), rays)
    assert leaks.tolist() == [c["leaks"] for c in cases]
    assert 0 < leaks.sum() < len(cases)
    blocked = ~segments_free(rays, np.repeat(points, 4, axis=0), probes[vertices.reshape(-1)])
    assert blocked.reshape(-1, 4).tolist() == [c["blocked"] for c in cases]
