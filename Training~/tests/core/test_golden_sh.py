"""Tests/Data/sh_golden.json: Unity SphericalHarmonicsL2 convention (Documentation~/sh.md)."""

from __future__ import annotations

import numpy as np

from lpnn.core import sh as shmath

GOLDEN = "sh_golden.json"


def test_evaluate(golden, assert_within):
    data = golden(GOLDEN)
    for case in data["evaluate"]:
        rgb = shmath.evaluate(np.asarray([case["sh"]], dtype=np.float32), np.asarray(case["directions"]))[0]
        assert_within(rgb, case["rgb"], data["tolerance"], f"evaluate {case['name']}")


def test_directional_and_ambient_plus_directed(golden, assert_within):
    data = golden(GOLDEN)
    for n, case in enumerate(data["directional"]):
        sh = shmath.directional(np.asarray(case["direction"]), np.asarray(case["color"]), case["intensity"])
        assert_within(sh, case["sh"], data["tolerance"], f"directional {n}")
    for n, case in enumerate(data["ambient_plus_directed"]):
        sh = shmath.ambient_plus_directed(np.asarray(case["ambient"]), np.asarray(case["directed"]),
                                          np.asarray(case["direction"]))
        assert_within(sh, case["sh"], data["tolerance"], f"ambient_plus_directed {n}")


def test_luminance_and_ycocg(golden, assert_within):
    data = golden(GOLDEN)
    for n, case in enumerate(data["luminance"]):
        assert_within(shmath.luminance(np.asarray(case["rgb"])), case["y"], data["tolerance"], f"luminance {n}")
    for n, case in enumerate(data["ycocg"]):
        assert_within(shmath.rgb_to_ycocg(np.asarray(case["rgb"])), case["ycocg"], data["tolerance"], f"ycocg {n}")
        assert_within(shmath.ycocg_to_rgb(np.asarray(case["ycocg"])), case["rgb"], data["tolerance"], f"ycocg inverse {n}")
