"""Writes Tests/Data/sh_golden.json from the formulas of Documentation~/sh.md, in float64.

Run through Tools~/regenerate-golden.sh. The C# core (ShGoldenTests) and the Python port
(tests/core/test_golden_sh.py) must both reproduce these numbers.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from lpnn.core import sh


def unit(v) -> list[float]:
    a = np.asarray(v, dtype=np.float64)
    return (a / np.linalg.norm(a)).tolist()


def main(out: Path) -> None:
    rng = np.random.default_rng(20261122)
    directions = [unit(d) for d in ([1, 0, 0], [0, -1, 0], [0, 0, 1], [1, 1, 1], [-0.3, 0.8, -0.2], [0.1, -0.2, -0.97])]
    evaluate = []
    for name, scale in (("unit coefficients", 1.0), ("HDR 1e-6", 1e-6), ("HDR 1e6", 1e6)):
        coefficients = (rng.uniform(-1.0, 1.0, 27) * scale).astype(np.float32)
        rgb = sh.evaluate(coefficients[None, :], np.array(directions))[0]
        evaluate.append({"name": name, "sh": coefficients.astype(np.float64).tolist(), "directions": directions, "rgb": rgb.tolist()})
    directional = []
    for direction, color, intensity in (([0, 0, 1], [1, 1, 1], 1.0), ([1, 2, -0.5], [0.8, 0.4, 0.2], 1.5), ([-1, 0.2, 0.3], [0.1, 0.9, 0.3], 0.25)):
        d = unit(direction)
        directional.append({"direction": d, "color": color, "intensity": intensity,
                            "sh": sh.directional(np.array(d), np.array(color), intensity).tolist()})
    ambient_plus_directed = []
    for ambient, directed, direction in (([0.1, 0.2, 0.3], [1.0, 0.5, 0.25], [0.2, 0.9, -0.4]), ([0.0, 0.0, 0.0], [2.0, 2.0, 2.0], [0, 0, -1])):
        d = unit(direction)
        ambient_plus_directed.append({"ambient": ambient, "directed": directed, "direction": d,
                                      "sh": sh.ambient_plus_directed(np.array(ambient), np.array(directed), np.array(d)).tolist()})
    colours = [[1.0, 0.0, 0.0], [0.2, 0.7, 0.1], [3.0, 1.0, 0.5], [1e-6, 2e-6, 3e-6]]
    golden = {
        "description": "SphericalHarmonicsL2 convention (Documentation~/sh.md), float64 from the formulas. Written by Tools~/golden/make_sh_golden.py.",
        "tolerance": {"abs": 1e-5, "rel": 1e-5},
        "evaluate": evaluate,
        "directional": directional,
        "ambient_plus_directed": ambient_plus_directed,
        "luminance": [{"rgb": c, "y": float(sh.luminance(np.array(c)))} for c in colours],
        "ycocg": [{"rgb": c, "ycocg": sh.rgb_to_ycocg(np.array(c)).tolist()} for c in colours],
    }
    out.write_text(json.dumps(golden, indent=2) + "\n", encoding="utf-8")
    print(f"wrote {out}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) / "sh_golden.json")
