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


def _polynomials(n: np.ndarray) -> np.ndarray:
    x, y, z = n[:, 0], n[:, 1], n[:, 2]
    return np.stack([np.ones_like(x), y, z, x, x * y, y * z, 3 * z * z - 1, x * z, x * x - y * y], axis=1)


def test_directional_golden_means_k_toward_the_light_and_k_over_17_away(golden):
    """Checked against what the formula must mean, not against the code that wrote the file."""
    for case in golden(GOLDEN)["directional"]:
        d = np.asarray(case["direction"])
        k = 2.0 * case["intensity"] * np.asarray(case["color"], dtype=np.float64)
        coefficients = np.asarray(case["sh"]).reshape(3, 9)
        toward, away = coefficients @ _polynomials(np.stack([d, -d]))[0], coefficients @ _polynomials(np.stack([d, -d]))[1]
        np.testing.assert_allclose(toward, k, rtol=1e-6)
        np.testing.assert_allclose(away, k / 17, rtol=1e-6)


def test_ambient_plus_directed_golden_is_the_least_squares_fit_over_the_sphere(golden):
    """The stored coefficients are the L2 projection of a + d*max(0, n.l) onto the nine polynomials: fit it
    numerically on 200,000 near-uniform directions (a Fibonacci sphere) and compare."""
    count = 200_000
    k = np.arange(count) + 0.5
    z = 1 - 2 * k / count
    phi = np.pi * (1 + 5**0.5) * k
    r = np.sqrt(1 - z * z)
    n = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    basis = _polynomials(n)
    for case in golden(GOLDEN)["ambient_plus_directed"]:
        lobe = np.maximum(0.0, n @ np.asarray(case["direction"]))
        for c in range(3):
            target = case["ambient"][c] + case["directed"][c] * lobe
            fitted, *_ = np.linalg.lstsq(basis, target, rcond=None)
            np.testing.assert_allclose(case["sh"][9 * c:9 * c + 9], fitted, atol=2e-4)
