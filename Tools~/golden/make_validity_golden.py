#!/usr/bin/env python3
"""Writes Tests/Data/validity_golden.json by construction, without the code it checks (standard library only).

Each case is a point's rays (unit directions), whether each ray hit, and the hit surface's oriented normal
(the side its winding calls front). The expected back-face fraction is the number of rays the case was built
to hit a back face (normal pointing along the ray) divided by the number of rays; a point is invalid when the
fraction exceeds 0.25 (Documentation~/features.md "Probe validity"). Run: python3 "Tools~/golden/make_validity_golden.py"
"""
from __future__ import annotations

import json
import math
from pathlib import Path

OUT = Path(__file__).resolve().parents[2] / "Tests" / "Data" / "validity_golden.json"


def directions() -> list[list[float]]:
    """26 unit directions: the 6 axes, the 8 cube diagonals, the 12 cube edges (any fixed set serves)."""
    result: list[list[float]] = []
    for axis in range(3):
        for sign in (1.0, -1.0):
            v = [0.0, 0.0, 0.0]
            v[axis] = sign
            result.append(v)
    s3 = 1.0 / math.sqrt(3.0)
    for x in (1.0, -1.0):
        for y in (1.0, -1.0):
            for z in (1.0, -1.0):
                result.append([x * s3, y * s3, z * s3])
    s2 = 1.0 / math.sqrt(2.0)
    for a, b in ((0, 1), (0, 2), (1, 2)):
        for sa in (1.0, -1.0):
            for sb in (1.0, -1.0):
                v = [0.0, 0.0, 0.0]
                v[a], v[b] = sa * s2, sb * s2
                result.append(v)
    return result


def case(name: str, back: int, front: int, grazing: int = 0) -> dict:
    """`back` rays hit a back face (normal = the direction), `front` a front face (normal = minus the direction),
    `grazing` a face seen edge-on (normal perpendicular: not a back face); the rest miss."""
    dirs = directions()
    hits, normals = [], []
    for index, d in enumerate(dirs):
        if index < back:
            hits.append(True); normals.append(list(d))
        elif index < back + front:
            hits.append(True); normals.append([-c for c in d])
        elif index < back + front + grazing:
            # a unit vector perpendicular to d: d x (an axis not parallel to d), normalised
            axis = [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0]
            p = [d[1] * axis[2] - d[2] * axis[1], d[2] * axis[0] - d[0] * axis[2], d[0] * axis[1] - d[1] * axis[0]]
            length = math.sqrt(sum(c * c for c in p))
            hits.append(True); normals.append([c / length for c in p])
        else:
            hits.append(False); normals.append([0.0, 0.0, 0.0])
    fraction = back / len(dirs)
    return {"name": name, "directions": dirs, "hits": hits, "normals": normals,
            "back_face_fraction": fraction, "invalid": fraction > 0.25}


def main() -> None:
    cases = [
        case("inside a closed box: every ray meets the inside of a wall's back", back=26, front=0),
        case("open room: every ray meets a wall facing the point", back=0, front=26),
        case("7 of 26 back faces (0.269, just above the threshold)", back=7, front=19),
        case("6 of 26 back faces (0.231, just below the threshold)", back=6, front=20),
        case("nothing hit (open sky)", back=0, front=0),
        case("grazing hits are not back faces", back=0, front=10, grazing=16),
        case("13 back faces and 13 misses: the fraction is over all rays", back=13, front=0),
    ]
    # How far the validity rays reach (metres) and the capture section that carries the fractions: constants of the
    # contract that both languages must share, not outputs of the rule.
    document = {"contract": "Documentation~/features.md, Probe validity", "threshold": 0.25,
                "ray_length": 10000.0, "capture_section": "back_face_fraction",
                "written_by": "Tools~/golden/make_validity_golden.py (by construction)", "cases": cases}
    OUT.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
