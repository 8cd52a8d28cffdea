#!/usr/bin/env python3
"""Writes Tests/Data/pins_golden.json by construction, without the code it checks (standard library only).

Documentation~/pins.md: a pin stands for its nearest evaluation point (within half a cell diagonal) and blocks every
point closer than the minimum distance (default one cell; compared with a slack of 1e-3 cells). The grid is a whole
box of the lattice (ids i, j, k in ranges; grid order: i fastest, then j, then k), so the nearest point of a position
inside the box is the lattice point of its rounded coordinates, id = round(p / h) per axis; positions are chosen at
least 0.05 cells from any rounding tie. Blocked points are found by brute force over every point (distances in
double from the float32 positions, as both languages compute them). Error cases name the phrase the message must hold.
Run: python3 "Tools~/golden/make_pins_golden.py"
"""
from __future__ import annotations

import json
import math
import struct
from pathlib import Path

OUT = Path(__file__).resolve().parents[2] / "Tests" / "Data" / "pins_golden.json"
SLACK = 1e-3  # cells
SNAP = math.sqrt(3.0) / 2.0  # cells


def f32(x: float) -> float:
    return struct.unpack("f", struct.pack("f", x))[0]


def box_ids(lo: tuple[int, int, int], hi: tuple[int, int, int]) -> list[list[int]]:
    return [[i, j, k] for k in range(lo[2], hi[2] + 1) for j in range(lo[1], hi[1] + 1) for i in range(lo[0], hi[0] + 1)]


def case(name: str, h: float, lo, hi, pins: list[list[float]], min_distance: float | None) -> dict:
    ids = box_ids(lo, hi)
    world = [[f32(h * c) for c in row] for row in ids]
    indices = []
    for p in pins:
        rounded = [round(c / h) for c in p]
        assert all(abs(c / h - r) <= 0.45 for c, r in zip(p, rounded)), f"{name}: {p} is near a rounding tie"
        assert all(lo[a] <= rounded[a] <= hi[a] for a in range(3)), f"{name}: {p} snaps outside the box"
        index = ids.index(rounded)
        assert math.dist(p, world[index]) <= SNAP * h
        indices.append(index)
    assert len(set(indices)) == len(indices)
    distance = h if min_distance is None else min_distance
    blocked = sorted(set(indices) | {n for n, w in enumerate(world)
                                     if min(math.dist(w, p) for p in pins) < distance - SLACK * h})
    return {"name": name, "cell_size": h, "ids": ids, "pins": pins, "min_distance": min_distance,
            "indices": indices, "blocked": blocked}


def failing(name: str, h: float, lo, hi, pins: list[list[float]], error: str) -> dict:
    return {"name": name, "cell_size": h, "ids": box_ids(lo, hi), "pins": pins, "min_distance": None, "error": error}


def main() -> None:
    cases = [
        # One pin on the grid (blocks only its own point: its neighbours are exactly one cell away), one off it.
        case("on and off the grid", 0.5, (-2, 0, -1), (3, 2, 2), [[0.5, 0.5, 0.5], [1.1, 0.2, -0.3]], None),
        # A level's cell size, far from the origin: float32 positions, several off-grid pins.
        case("level cell far out", 1.6256, (40, -3, 60), (45, 1, 64),
             [[round(1.6256 * c, 4) for c in off] for off in ((41.2, -2.3, 61.1), (44.6, 0.35, 63.8), (42.0, -1.0, 62.0))], None),
        case("a larger minimum distance", 0.5, (-2, 0, -1), (3, 2, 2), [[0.62, 0.41, 0.55]], 1.2),
        case("no minimum distance", 0.5, (-2, 0, -1), (3, 2, 2), [[0.62, 0.41, 0.55], [-0.9, 1.1, 0.1]], 0.0),
        failing("a pin outside the points", 0.5, (-2, 0, -1), (3, 2, 2), [[0.5, 0.5, 0.5], [9.0, 0.0, 0.0]],
                "outside the volume's points"),
        failing("a duplicate pin", 0.5, (-2, 0, -1), (3, 2, 2), [[0.5, 0.5, 0.5], [1.0, 0.0, 0.0], [0.5, 0.5, 0.5]],
                "pinned probes 0 and 2 are both at"),
        failing("two pins for one point", 0.5, (-2, 0, -1), (3, 2, 2), [[0.5, 0.5, 0.5], [0.55, 0.45, 0.5]],
                "both stand for evaluation point"),
        failing("no pins", 0.5, (-2, 0, -1), (3, 2, 2), [], "no pinned positions"),
    ]
    document = {"format": "lpnn.pins-golden", "version": 1, "snap_radius_cells": SNAP, "min_distance_cells": 1.0,
                "slack_cells": SLACK, "cases": cases}
    OUT.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {OUT} ({len(cases)} cases)")


if __name__ == "__main__":
    main()
