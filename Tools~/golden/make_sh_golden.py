"""Writes Tests/Data/sh_golden.json from the formulas of Documentation~/sh.md, in float64.

The formulas are written out here again, term by term, without importing the package's SH code, so the
golden file is not made by the code it checks. Two of them are checked further against what they must
mean (tests/core/test_golden_sh.py): the directional light evaluates to k toward the light and k/17 away
from it, and ambient + directed is the least-squares fit of a + d*max(0, n.l) over the sphere.
Run through Tools~/regenerate-golden.sh. The C# core (ShGoldenTests) and the Python port
(tests/core/test_golden_sh.py) must both reproduce these numbers.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np


def _polynomials(x: float, y: float, z: float) -> list[float]:
    """P_i(n) of sh.md's layout table: 1, y, z, x, xy, yz, 3z^2-1, xz, x^2-y^2."""
    return [1.0, y, z, x, x * y, y * z, 3.0 * z * z - 1.0, x * z, x * x - y * y]


def _evaluate(coefficients: list[float], direction: list[float]) -> list[float]:
    p = _polynomials(*direction)
    rgb = []
    for c in range(3):
        total = 0.0
        for i in range(9):  # summed in coefficient order, as sh.md says
            total += coefficients[c * 9 + i] * p[i]
        rgb.append(total)  # float64: the golden keeps the exact value, the tolerance covers float32 results
    return rgb


def _directional(d: list[float], color: list[float], intensity: float) -> list[float]:
    x, y, z = d
    weights = [4 / 17, 8 / 17 * y, 8 / 17 * z, 8 / 17 * x, 15 / 17 * x * y, 15 / 17 * y * z, 5 / 68 * (3 * z * z - 1),
               15 / 17 * x * z, 15 / 68 * (x * x - y * y)]
    out = []
    for c in range(3):
        k = float(np.float32(2.0) * np.float32(intensity) * np.float32(color[c]))  # k_c in float32, as Unity
        out += [k * w for w in weights]
    return out


def _ambient_plus_directed(a: list[float], d: list[float], l: list[float]) -> list[float]:
    lx, ly, lz = l
    out = []
    for c in range(3):
        dc = d[c]
        out += [a[c] + dc / 4, dc * ly / 2, dc * lz / 2, dc * lx / 2, 15 / 16 * dc * lx * ly, 15 / 16 * dc * ly * lz,
                5 / 64 * dc * (3 * lz * lz - 1), 15 / 16 * dc * lx * lz, 15 / 64 * dc * (lx * lx - ly * ly)]
    return out


def _luminance(rgb: list[float]) -> float:
    r, g, b = rgb
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def _ycocg(rgb: list[float]) -> list[float]:
    r, g, b = rgb
    return [r / 4 + g / 2 + b / 4, r / 2 - b / 2, -r / 4 + g / 2 - b / 4]


def unit(v) -> list[float]:
    a = np.asarray(v, dtype=np.float64)
    return (a / np.linalg.norm(a)).tolist()


def main(out: Path) -> None:
    rng = np.random.default_rng(20261122)
    directions = [unit(d) for d in ([1, 0, 0], [0, -1, 0], [0, 0, 1], [1, 1, 1], [-0.3, 0.8, -0.2], [0.1, -0.2, -0.97])]
    evaluate = []
    for name, scale in (("unit coefficients", 1.0), ("HDR 1e-6", 1e-6), ("HDR 1e6", 1e6)):
        coefficients = (rng.uniform(-1.0, 1.0, 27) * scale).astype(np.float32)
        stored = coefficients.astype(np.float64).tolist()
        rgb = [_evaluate(stored, direction) for direction in directions]
        evaluate.append({"name": name, "sh": stored, "directions": directions, "rgb": rgb})
    directional = []
    for direction, color, intensity in (([0, 0, 1], [1, 1, 1], 1.0), ([1, 2, -0.5], [0.8, 0.4, 0.2], 1.5), ([-1, 0.2, 0.3], [0.1, 0.9, 0.3], 0.25)):
        d = unit(direction)
        directional.append({"direction": d, "color": color, "intensity": intensity,
                            "sh": _directional(d, color, intensity)})
    ambient_plus_directed = []
    for ambient, directed, direction in (([0.1, 0.2, 0.3], [1.0, 0.5, 0.25], [0.2, 0.9, -0.4]), ([0.0, 0.0, 0.0], [2.0, 2.0, 2.0], [0, 0, -1])):
        d = unit(direction)
        ambient_plus_directed.append({"ambient": ambient, "directed": directed, "direction": d,
                                      "sh": _ambient_plus_directed(ambient, directed, d)})
    colours = [[1.0, 0.0, 0.0], [0.2, 0.7, 0.1], [3.0, 1.0, 0.5], [1e-6, 2e-6, 3e-6]]
    golden = {
        "description": "SphericalHarmonicsL2 convention (Documentation~/sh.md), float64 from the formulas, written out independently of the package code by Tools~/golden/make_sh_golden.py.",
        "tolerance": {"abs": 1e-5, "rel": 1e-5},
        "evaluate": evaluate,
        "directional": directional,
        "ambient_plus_directed": ambient_plus_directed,
        "luminance": [{"rgb": c, "y": _luminance(c)} for c in colours],
        "ycocg": [{"rgb": c, "ycocg": _ycocg(c)} for c in colours],
    }
    out.write_text(json.dumps(golden, indent=2) + "\n", encoding="utf-8")
    print(f"wrote {out}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) / "sh_golden.json")
