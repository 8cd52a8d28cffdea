#!/usr/bin/env python3
"""Writes Tests/Data/in_use_golden.json by construction, without the code it checks (standard library only).

The scene is a level made of axis-aligned boxes laid out along x (Documentation~/in-use.md, "Definitions"): rooms with
a balcony, a 0.3 m step, a 2.1 m block whose top nobody climbs, a 2.3 m platform with an item on top, a gentle and a steep
staircase of thin boxes, a thin full-height wall, a gap in the floor, a pit deeper than the band and a 0.62 m crate. Every surface
is horizontal or vertical, so the geometry answers each question of the rule in closed form:

- the floor ray from a point meets the highest horizontal face at or below it among the boxes whose (x, z) footprint
  holds it (every face a vertical ray meets is horizontal: |n_y| = 1);
- a segment between two points outside every box is free when it meets no closed box (parametric clipping);
- the walk is a breadth-first search over the moves those answers allow.

Each answer is also checked to stay the same when every box grows or shrinks by the margin (1 cm), and every
distance, rise and seed reach to be at least the margin from its threshold, so an exact box raycaster, Embree and
Unity's physics all agree. `LANDMARKS` are the answers the layout was designed to give; the derivation must give
them too before anything is written. Run: python3 "Tools~/golden/make_in_use_golden.py"
"""
from __future__ import annotations

import json
import math
from collections import deque
from pathlib import Path

OUT = Path(__file__).resolve().parents[2] / "Tests" / "Data" / "in_use_golden.json"
MARGIN = 0.01  # metres, and in cosine
CELL = 0.5
X_IDS, Y_IDS, Z_IDS = range(0, 51), range(0, 9), range(0, 3)  # x 0..25 m, y 0..4 m, z 0..1 m
Z_ALL = (-0.375, 1.375)  # boxes across the whole corridor
Z_SIDE = (-0.375, 0.625)  # boxes leaving a lane at z = 1 m
FLOOR_TOP = -0.2
PIT_TOP = -3.7  # the bottom of the gap and the pit: 3.5 m below the floor


def box(name: str, x: tuple[float, float], y: tuple[float, float], z: tuple[float, float]) -> dict:
    return {"name": name, "min": [x[0], y[0], z[0]], "max": [x[1], y[1], z[1]]}


def layout() -> list[dict]:
    """Every face sits an odd multiple of 0.125 m from the lattice in x and z, so lattice points and the floor-profile
    samples (every 0.25 m at this cell size) stay 0.125 m from the walls, and off the lattice's half-metres in y."""
    boxes = [
        box("floor west (rooms A, B, C, D)", (-0.375, 19.125), (-1.2, FLOOR_TOP), Z_ALL),
        box("floor between the gap and the pit (room E)", (19.375, 21.125), (-1.2, FLOOR_TOP), Z_ALL),
        box("floor east (room F)", (22.875, 25.375), (-1.2, FLOOR_TOP), Z_ALL),
        box("bottom of the gap and the pit", (-0.375, 25.375), (-4.7, PIT_TOP), Z_ALL),
        box("balcony: a 0.25 m slab 1.125 m over the spawn", (-0.375, 1.625), (1.125, 1.375), Z_ALL),
        box("step 0.3 m (lane at z = 1 m)", (2.375, 3.875), (FLOOR_TOP, 0.1), Z_SIDE),
        box("block 2.1 m (lane at z = 1 m)", (4.875, 6.125), (FLOOR_TOP, 1.9), Z_SIDE),
        box("platform 2.3 m, item on top", (7.375, 8.625), (FLOOR_TOP, 2.1), Z_ALL),
    ]
    # Gentle stairs: 0.16 m risers every 0.25 m (33 degrees), one riser per profile interval, up to a landing.
    for k in range(7):
        x0 = 9.625 + 0.25 * k
        boxes.append(box(f"gentle stair {k + 1}", (x0, x0 + 0.25), (FLOOR_TOP, round(-0.04 + 0.16 * k, 6)), Z_ALL))
    boxes.append(box("landing 1.08 m (top of the gentle stairs)", (11.375, 13.125), (FLOOR_TOP, 1.08), Z_ALL))
    # Steep stairs: 0.45 m risers every 0.25 m (61 degrees), up to a ledge, beside the lane at z = 1 m.
    for k in range(3):
        x0 = 14.125 + 0.25 * k
        boxes.append(box(f"steep stair {k + 1}", (x0, x0 + 0.25), (FLOOR_TOP, round(0.25 + 0.45 * k, 6)), Z_SIDE))
    boxes.append(box("ledge 1.6 m (top of the steep stairs)", (14.875, 15.625), (FLOOR_TOP, 1.6), Z_SIDE))
    boxes.append(box("thin wall, full height (rooms C | D)", (17.125, 17.225), (FLOOR_TOP, 4.6), Z_ALL))
    # 0.62 m: climbable under 0.5 + 0.25 tan 45 = 0.75, not under 0.3 + 0.25 tan 50 = 0.598.
    boxes.append(box("crate 0.62 m (lane at z = 1 m)", (24.375, 25.125), (FLOOR_TOP, 0.42), Z_SIDE))
    return boxes


# The gap (x 19.125..19.375) is narrower than a cell: the points on both sides stand on floor, only the profile
# sample at x = 19.25 falls through. The pit (x 21.125..22.875) has three columns of points over it.
SEEDS = [
    {"name": "spawn in room A", "position": [1.0, 0.3125, 0.5]},
    {"name": "item on the platform", "position": [8.0, 2.3125, 0.5]},
    {"name": "spawn in room C beside the thin wall (room D within 2h, behind the wall)", "position": [16.875, 0.3125, 0.5]},
    {"name": "item in room F", "position": [23.5, 0.1875, 0.5]},
]

PARAMETER_SETS = [
    {"name": "default", "band_height": 3.0, "slope_limit_degrees": 45.0, "step_height": 0.5},
    {"name": "strict: 20 degrees, 0.1 m steps", "band_height": 2.85, "slope_limit_degrees": 20.0,
     "step_height": 0.1},
    {"name": "low band: 1.65 m", "band_height": 1.65, "slope_limit_degrees": 45.0, "step_height": 0.5},
    {"name": "tall band reaching the pit, 50 degrees, 0.3 m steps", "band_height": 4.5, "slope_limit_degrees": 50.0,
     "step_height": 0.3},
]

# (parameter set, point id, in band, reachable, why): what the layout was built to show.
LANDMARKS = [
    ("default", (2, 0, 1), True, True, "room A floor by the spawn"),
    ("default", (1, 2, 1), True, True, "under the balcony"),
    ("default", (1, 3, 1), True, False, "on the balcony: its slab blocks the way up, its edge the way from the side"),
    ("default", (6, 1, 0), True, True, "on the 0.3 m step: climbable (rise 0.3 <= 0.5 + 0.25 tan 45)"),
    ("strict: 20 degrees, 0.1 m steps", (6, 1, 0), True, False,
     "on the 0.3 m step: not climbable (0.3 > 0.1 + 0.25 tan 20)"),
    ("strict: 20 degrees, 0.1 m steps", (9, 0, 2), True, True, "past the step along the lane"),
    ("default", (11, 4, 0), True, False, "on the 2.1 m block: in band, not reachable"),
    ("default", (16, 5, 1), True, True, "on the platform, where the item is"),
    ("default", (18, 0, 1), True, True, "room B: reached by dropping off the platform"),
    ("default", (23, 3, 1), True, True, "on the landing, up the gentle stairs"),
    ("strict: 20 degrees, 0.1 m steps", (23, 3, 1), True, True, "gentle stairs: 0.16 < 0.1 + 0.25 tan 20"),
    ("default", (31, 4, 0), True, True, "on the ledge, up the steep stairs (0.45 <= 0.75)"),
    ("strict: 20 degrees, 0.1 m steps", (31, 4, 0), True, False, "steep stairs: 0.45 > 0.19"),
    ("default", (36, 0, 1), True, False, "room D: a seed's reach crosses the thin wall, its segments do not"),
    ("default", (40, 0, 1), True, False, "room E: behind the gap, no seed"),
    ("default", (43, 0, 1), False, False, "over the pit: its bottom is 3.7 m down, deeper than the band"),
    ("tall band reaching the pit, 50 degrees, 0.3 m steps", (43, 0, 1), True, True,
     "over the pit, band 4.5 m: reached by dropping in from room F"),
    ("tall band reaching the pit, 50 degrees, 0.3 m steps", (40, 0, 1), True, False,
     "room E: nobody climbs 3.5 m out of the pit"),
    ("default", (48, 1, 1), True, True, "room F by its item"),
    ("default", (49, 1, 0), True, True, "on the 0.62 m crate: 0.62 <= 0.5 + 0.25 tan 45"),
    ("tall band reaching the pit, 50 degrees, 0.3 m steps", (49, 1, 0), True, False,
     "on the 0.62 m crate: 0.62 > 0.3 + 0.25 tan 50"),
    ("low band: 1.65 m", (16, 5, 1), True, True, "on the platform, where the item is"),
    ("low band: 1.65 m", (18, 0, 1), True, False,
     "room B: the 2.3 m drop off the platform ends above the band (the points beside its top are not in band)"),
    ("low band: 1.65 m", (13, 4, 1), False, False, "2.2 m above room A's floor: above a 1.65 m band"),
    ("default", (4, 6, 2), False, False, "3.2 m above the floor: above the band"),
]


# ------------------------------------------------------------------------------------------ geometry, closed form

def grown(b: dict, by: float) -> tuple[list[float], list[float]]:
    return [v - by for v in b["min"]], [v + by for v in b["max"]]


def robust(question, *args) -> bool:
    """The answer with the boxes as given, refused unless growing and shrinking them by MARGIN gives the same."""
    answers = {question(*args, grow=g) for g in (-MARGIN, 0.0, MARGIN)}
    if len(answers) != 1:
        raise SystemExit(f"a decision sits within {MARGIN} m of a wall: {question.__name__}{args}; move the boxes")
    return answers.pop()


def inside_any(boxes: list[dict], p: tuple[float, float, float], grow: float = 0.0) -> bool:
    for b in boxes:
        lo, hi = grown(b, grow)
        if all(lo[a] <= p[a] <= hi[a] for a in range(3)):
            return True
    return False


def floor_face(boxes: list[dict], p: tuple[float, float, float], grow: float = 0.0) -> float | None:
    """Height of the first face straight below p (the highest top or bottom at or below it whose footprint holds p)."""
    best = None
    for b in boxes:
        lo, hi = grown(b, grow)
        if not (lo[0] <= p[0] <= hi[0] and lo[2] <= p[2] <= hi[2]):
            continue
        for face in (b["min"][1], b["max"][1]):  # faces are judged at their true height; the margin is checked below
            if face <= p[1] and (best is None or face > best):
                best = face
    return best


def segment_meets_box(boxes: list[dict], a: tuple, b: tuple, grow: float = 0.0) -> bool:
    """Whether the closed segment a-b meets some closed box (clipping its parameter to each box's slabs)."""
    for bx in boxes:
        lo, hi = grown(bx, grow)
        t0, t1 = 0.0, 1.0
        for axis in range(3):
            d = b[axis] - a[axis]
            if d == 0.0:
                if not (lo[axis] <= a[axis] <= hi[axis]):
                    break
                continue
            ta, tb = (lo[axis] - a[axis]) / d, (hi[axis] - a[axis]) / d
            t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
            if t0 > t1:
                break
        else:
            return True
    return False


def away(value: float, threshold: float, what: str) -> None:
    if abs(value - threshold) < MARGIN:
        raise SystemExit(f"{what}: {value} is within {MARGIN} of its threshold {threshold}; change the layout")


# ------------------------------------------------------------------------------------------------ the rule

def floor_height(boxes: list[dict], p: tuple, band_height: float) -> float | None:
    face = robust(floor_face, boxes, p)
    if face is None:
        return None
    away(p[1] - face, 0.0, f"height of {p} above its floor")
    away(p[1] - face, band_height, f"floor distance of {p}")
    return face if p[1] - face <= band_height else None


def derive(boxes: list[dict], ids: list[tuple], parameters: dict) -> dict:
    h, H = CELL, parameters["band_height"]
    theta = math.radians(parameters["slope_limit_degrees"])
    away(1.0, math.cos(theta), "a horizontal face's |n_y| against cos(slope limit)")
    intervals = min(64, max(1, math.ceil(h / 0.25)))
    rise_limit = parameters["step_height"] + h / intervals * math.tan(theta)
    position = {i: (i[0] * h, i[1] * h, i[2] * h) for i in ids}
    index = {i: n for n, i in enumerate(ids)}
    floor = [floor_height(boxes, position[i], H) for i in ids]
    band = [f is not None for f in floor]

    def free(a: tuple, b: tuple) -> bool:
        return not robust(segment_meets_box, boxes, a, b)

    starts = set()
    for seed in SEEDS:
        s = tuple(seed["position"])
        if robust(inside_any, boxes, s):
            raise SystemExit(f"seed {seed['name']} lies inside a box; move it")
        for n, i in enumerate(ids):
            if not band[n]:
                continue
            distance = math.dist(s, position[i])
            if distance > 2 * h + 2 * MARGIN:
                continue
            away(distance, 2 * h, f"distance from seed {seed['name']} to {i}")
            if distance <= 2 * h and free(s, position[i]):
                starts.add(n)

    moves: dict[int, list[int]] = {n: [] for n in range(len(ids))}
    for n, i in enumerate(ids):
        for axis in range(3):
            j = list(i)
            j[axis] += 1
            m = index.get(tuple(j))
            if m is None or not (band[n] and band[m]):
                continue
            p, q = position[i], position[ids[m]]
            if not free(p, q):  # the segment is the same both ways: p and q lie outside every box
                continue
            if axis == 1:
                moves[n].append(m)
                moves[m].append(n)
                continue
            profile = [floor[n]]
            for k in range(1, intervals):
                x = tuple(p[a] + k / intervals * (q[a] - p[a]) for a in range(3))
                if robust(inside_any, boxes, x):
                    raise SystemExit(f"profile sample {x} lies inside a box; move the box")
                profile.append(floor_height(boxes, x, H))
            profile.append(floor[m])
            if any(f is None for f in profile):
                continue
            rises = [profile[k + 1] - profile[k] for k in range(intervals)]
            for r in rises:
                away(r, rise_limit, f"rise between {i} and {ids[m]}")
                away(-r, rise_limit, f"rise between {ids[m]} and {i}")
            if all(r <= rise_limit for r in rises):
                moves[n].append(m)
            if all(-r <= rise_limit for r in rises):
                moves[m].append(n)

    reached = [False] * len(ids)
    queue = deque(sorted(starts))
    for n in queue:
        reached[n] = True
    while queue:
        n = queue.popleft()
        for m in moves[n]:
            if not reached[m]:
                reached[m] = True
                queue.append(m)
    return {"in_band": band, "floor_height": floor, "reachable": reached, "start_points": sorted(starts)}


def readable_json(value, depth: int = 0) -> str:
    """Objects one key a line down to the cases, lists and anything deeper on one line: a reviewable diff."""
    if isinstance(value, dict) and depth < 2:
        pad = " " * (depth + 1)
        items = ",\n".join(f"{pad}{json.dumps(k)}: {readable_json(v, depth + 1)}" for k, v in value.items())
        return "{\n" + items + "\n" + " " * depth + "}"
    if isinstance(value, list) and depth < 2 and value and isinstance(value[0], dict):
        pad = " " * (depth + 1)
        return "[\n" + ",\n".join(pad + readable_json(v, depth + 1) for v in value) + "\n" + " " * depth + "]"
    return json.dumps(value, separators=(", ", ": "))


def main() -> None:
    boxes = layout()
    lattice = [(i, j, k) for k in Z_IDS for j in Y_IDS for i in X_IDS]  # grid order: k, then j, then i
    ids = [i for i in lattice if not robust(inside_any, boxes, (i[0] * CELL, i[1] * CELL, i[2] * CELL))]
    cases = []
    for parameters in PARAMETER_SETS:
        derived = derive(boxes, ids, parameters)
        name = parameters["name"]
        for landmark, point, band, reached, why in LANDMARKS:
            if landmark != name:
                continue
            n = ids.index(point)
            got = (derived["in_band"][n], derived["reachable"][n])
            if got != (band, reached):
                raise SystemExit(f"{name}, {point} ({why}): derived in band/reachable {got}, designed {(band, reached)}")
        cases.append({"name": name, "parameters": {k: v for k, v in parameters.items() if k != "name"},
                      "rise_limit": parameters["step_height"] + CELL / min(64, max(1, math.ceil(CELL / 0.25)))
                      * math.tan(math.radians(parameters["slope_limit_degrees"])),
                      "in_band_count": sum(derived["in_band"]), "reachable_count": sum(derived["reachable"]),
                      **derived})
    landmarks = [{"case": c, "id": list(p), "in_band": b, "reachable": r, "why": w} for c, p, b, r, w in LANDMARKS]
    document = {
        "contract": "Documentation~/in-use.md",
        "written_by": "Tools~/golden/make_in_use_golden.py (by construction: closed-form box geometry, not the code "
                      "it checks)",
        "tolerance": {"floor_height": {"abs": 1e-5, "rel": 0.0}, "masks": "exact"},
        "margin": MARGIN,
        "cell_size": CELL,
        "room": None,
        "obstacles": boxes,
        "seeds": SEEDS,
        "ids": [list(i) for i in ids],
        "cases": cases,
        "landmarks": landmarks,
    }
    OUT.write_text(readable_json(document) + "\n", encoding="utf-8")
    for case in cases:
        print(f"{case['name']}: {case['in_band_count']} in band, {case['reachable_count']} reachable "
              f"of {len(ids)} points")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
