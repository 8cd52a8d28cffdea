#!/usr/bin/env python3
"""Writes Tests/Data/leaks_golden.json by construction, without the code it checks (standard library only).

The scene: a wall, the slab -0.1 <= x <= 0.1, with a door 1 m wide (|z| < 0.5) through its whole height: two boxes.
Points and probes are drawn (fixed seed) in two rooms either side, never inside the slab. A segment crosses the wall
when, over the stretch where it lies inside the slab (x from -0.1 to 0.1, along which z is linear), z reaches
|z| >= 0.5 somewhere: the larger |z| at the slab's two faces decides. Cases closer than 1 cm to that edge are
redrawn, so the box raycasters of both languages (float32 in C#) decide alike.

Each case is a point, its stencil (4 probe indices and weights, some zero, some round-off small) and whether it leaks
(Documentation~/leaks.md): a probe of weight > 1e-6 behind the wall. Run: python3 "Tools~/golden/make_leaks_golden.py"
"""
from __future__ import annotations

import json
import random
from pathlib import Path

OUT = Path(__file__).resolve().parents[2] / "Tests" / "Data" / "leaks_golden.json"
HALF_THICKNESS = 0.1
DOOR_HALF_WIDTH = 0.5
EXTENT = 10.0  # the wall boxes reach this far in y and z; every point lies well within
MARGIN = 0.01
MIN_WEIGHT = 1e-6


def wall_boxes() -> list[dict]:
    return [{"min": [-HALF_THICKNESS, -EXTENT, -EXTENT], "max": [HALF_THICKNESS, EXTENT, -DOOR_HALF_WIDTH]},
            {"min": [-HALF_THICKNESS, -EXTENT, DOOR_HALF_WIDTH], "max": [HALF_THICKNESS, EXTENT, EXTENT]}]


def crossing(a: list[float], b: list[float]) -> bool | None:
    """Whether the segment a-b meets a wall box; None when it passes within MARGIN of a door edge (ambiguous)."""
    if (a[0] < 0) == (b[0] < 0):
        return False  # both in one room: never enters the slab (points keep >= 0.2 m from it)
    def z_at(x: float) -> float:
        return a[2] + (b[2] - a[2]) * (x - a[0]) / (b[0] - a[0])
    reach = max(abs(z_at(-HALF_THICKNESS)), abs(z_at(HALF_THICKNESS)))
    if abs(reach - DOOR_HALF_WIDTH) < MARGIN:
        return None
    return reach > DOOR_HALF_WIDTH


def room_point(rng: random.Random, side: float) -> list[float]:
    return [side * rng.uniform(0.3, 3.0), rng.uniform(0.0, 2.5), rng.uniform(-2.0, 2.0)]


def weights(rng: random.Random, kind: str) -> list[float]:
    if kind == "tiny":  # one weight of round-off size, one just above the threshold's order
        return [1.0 - 5e-7 - 5e-6, 5e-7, 5e-6, 0.0]
    if kind == "outside":  # a hull triangle's 3 weights, the fourth zero
        w = [rng.uniform(0.1, 1.0) for _ in range(3)]
        return [v / sum(w) for v in w] + [0.0]
    w = [rng.uniform(0.05, 1.0) for _ in range(4)]
    return [v / sum(w) for v in w]


def main() -> None:
    rng = random.Random(20261126)
    probes = [room_point(rng, -1.0) for _ in range(6)] + [room_point(rng, 1.0) for _ in range(6)]
    cases = []
    kinds = ["full"] * 24 + ["outside"] * 8 + ["tiny"] * 8
    for index, kind in enumerate(kinds):
        while True:
            point = room_point(rng, -1.0 if index % 2 == 0 else 1.0)
            vertices = rng.sample(range(len(probes)), 4)
            w = weights(rng, kind)
            decisions = [crossing(point, probes[v]) for v in vertices]
            if None not in decisions:
                break
        leaks = any(weight > MIN_WEIGHT and blocked for weight, blocked in zip(w, decisions))
        cases.append({"point": point, "vertices": vertices, "weights": w, "blocked": decisions, "leaks": leaks})
    document = {"contract": "Documentation~/leaks.md", "minimum_weight": MIN_WEIGHT, "obstacles": wall_boxes(),
                "probes": probes, "written_by": "Tools~/golden/make_leaks_golden.py (by construction)",
                "cases": cases}
    OUT.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {OUT}: {len(cases)} cases, {sum(c['leaks'] for c in cases)} leaking")


if __name__ == "__main__":
    main()
