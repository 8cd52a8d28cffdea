"""Writes Tests/Data/leak_aware_golden.json (Tests/Data/README.md; contract: Documentation~/leaks.md "A leak-aware
default", quality.md §5.3).

Run through Tools~/regenerate-golden.sh (deliberately; review the diff). The probe sets come from the Python reference
(lpnn.quality.placement.refined_insertion with leaks=, lpnn.quality.placement.leak_aware); the C# port (RefinedSelection with a
LeakWeighting, LeakRepair, BatchedRefinement) is an independent implementation that must keep the same points with its
own tetrahedraliser in the tests (Bowyer-Watson), location, hull projection, segment casts and sorting.

The scene: a walled room. Points in general position (integer ids x 0.25, exact in float32) inside a large
tetrahedron, split by a wall (an obstacle box of the analytic raycaster, AnalyticBoxRaycaster) lying between two id
columns, so no point is inside it; the side below the wall is lit warm, the other dim and cool, each with a random
bump per point. General position keeps every tetrahedralisation unique, which both languages need to agree.

What is checked before writing (less than make_batched_refinement_golden.py certifies: points leave the hull here, so
the intermediate sets are not certified): the tetrahedralisations of the seed, the repaired seed and the three answers
are *the* Delaunay ones, in exact integer arithmetic with a margin (make_insertion_golden.certify_delaunay); every leak
decision is decided by construction (the wall spans the whole scene in y and z and lies 0.3 of a cell from every point
column, so a segment is blocked exactly when its ends lie on either side); the seed leaks, the repair ends leaks, and
the leak-aware answer at tau leaks less than the answer without the option.

The pinned case (leaks.md with pins.md): the PINNED inner points nearest the wall are pinned with a keep distance of
KEEP_DISTANCE_IDS cells. Checked before writing, in exact integer ids (not by pins.py's blocking): every point the
repair adds is at least KEEP_DISTANCE_IDS from every pin; the seed has a leaking point nearer than that to a pin,
which the repair without the pins' blocked points would add (so the case exercises the rule); every set holds every
pin; the budget answer holds exactly the budget's count, pins included; the answer at tau leaks less than the same
pins' answer without the option; the five sets' tetrahedralisations are certified Delaunay as above.

    PYTHONPATH=Training~ python Tools~/golden/make_leak_aware_golden.py Tests/Data
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from lpnn.core.analytic_scene import AnalyticBoxRaycaster, AxisBox
from lpnn.core.atomic import write_text_atomic
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.insertion import TIE, InsertionOrder
from lpnn.quality.placement.pins import pin_probes
from lpnn.quality.placement.leak_aware import LEAK_WEIGHT, REPAIR_ROUNDS, leak_repaired
from lpnn.quality.metric.leaks import leaking_points
from lpnn.quality.metric.metric import ReferenceField, probe_stencil
from lpnn.quality.placement.policies import budget_count
from lpnn.quality.placement.refined_insertion import RECOMMENDED_REFINE, budget_seed_count, refined_insertion
from lpnn.quality.metric.triangulation import tetrahedralize

from make_insertion_golden import CELL, _field, certify_delaunay, exact, grid_order

SEED = 7
POINTS = 160  # inner points: more than MINIMUM_SEED (64), so the seed is a prefix and the repair has points to add
EXTENT = 512  # ids of the enclosing tetrahedron's corners
WALL_ID = 200  # the wall lies between id columns x = 200 and 201
BUDGET = 0.15
TOLERANCE = 0.08
PINNED = 3  # the pinned case pins the inner points nearest the wall (ties: the lower index) ...
KEEP_DISTANCE_IDS = 30  # ... with this keep distance, in cells (ids): it blocks leaking points the repair would add
DARK_LIGHT = 1e-12  # the dark room's light, of the scale: its errors (~1e-10) lie below TIE (dark_room_case)
DARK_ATTEMPTS = 20  # random lights tried for the dark room


def wall() -> AxisBox:
    """A slab across the whole tetrahedron, strictly between two id columns (no point inside, none on a face)."""
    lo, hi = (WALL_ID + 0.3) * CELL, (WALL_ID + 0.7) * CELL
    return AxisBox(min=np.array([lo, -1000.0, -1000.0]), max=np.array([hi, 1000.0, 1000.0]))


def walled_room(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Ids (grid order) and SH. Every point's SH is a multiple of one base: 1.3-1.7x below the wall, 0.3-0.7x beyond it,
    and exactly 1x at the 4 corners. Half the inner points lie on each side, so the median lighting is the corners'
    and insertion starts from them (as in make_insertion_golden.py's enclosed construction): no point is outside the
    probes' hull while insertion ranks, where a projection onto a hull edge would make its cell ambiguous."""
    rng = np.random.default_rng(seed)
    corners = np.array([[0, 0, 0], [EXTENT, 19, 45], [27, EXTENT, 5], [14, 35, EXTENT]], dtype=np.int64)
    inner: list[np.ndarray] = []
    per_side = {True: 0, False: 0}
    while len(inner) < POINTS:
        lam = rng.dirichlet(np.ones(4))
        if lam.min() < 0.02:
            continue
        p = np.rint(lam @ corners).astype(np.int64)
        lit = bool(p[0] <= WALL_ID)
        if per_side[lit] == POINTS // 2 or any(np.array_equal(p, q) for q in inner):
            continue
        per_side[lit] += 1
        inner.append(p)
    ids = grid_order(np.concatenate([corners, np.asarray(inner)]))
    is_corner = np.array([any(np.array_equal(row, c) for c in corners) for row in ids])
    base = np.array([1.0, 0.85, 0.6] * 9) * np.array([1.0 if c % 9 == 0 else 0.1 for c in range(27)])
    factor = np.where(ids[:, 0] <= WALL_ID, 1.5, 0.5) + rng.uniform(-0.2, 0.2, ids.shape[0])
    factor[is_corner] = 1.0
    return ids, base[None, :] * factor[:, None]


def pinned_case(ids: np.ndarray, field, grid, raycaster: AnalyticBoxRaycaster, count: int) -> dict[str, Any]:
    """The pinned case of the module text: its sets, checked as the text says, for the golden."""
    corners = {(0, 0, 0), (EXTENT, 19, 45), (27, EXTENT, 5), (14, 35, EXTENT)}
    inner = [i for i in range(ids.shape[0]) if tuple(int(v) for v in ids[i]) not in corners]
    gap = np.abs(ids[:, 0] - (WALL_ID + 0.5))
    pinned = np.asarray(sorted(inner, key=lambda i: (gap[i], i))[:PINNED], dtype=np.int64)
    pins = pin_probes(field.world[pinned], field.world, CELL, KEEP_DISTANCE_IDS * CELL)
    if pins.indices.tolist() != pinned.tolist():
        raise SystemExit(f"the pins must stand for the points they sit on: {pins.indices} != {pinned}")

    def far_from_pins(point: int) -> bool:  # exact: squared integer distances, the keep distance in ids
        return all(int(((ids[point] - ids[p]) ** 2).sum()) >= KEEP_DISTANCE_IDS ** 2 for p in pinned)

    n = field.point_count
    seed = InsertionOrder(field, grid, pins=pins).selection()(budget_seed_count(RECOMMENDED_REFINE, count, n))
    repaired = leak_repaired(field, seed, raycaster, blocked=pins.blocked)
    unpinned_repair = leak_repaired(field, seed, raycaster)
    budget = refined_insertion(field, grid, budget=BUDGET, leaks=raycaster, pins=pins)
    tolerance = refined_insertion(field, grid, tolerance=TOLERANCE, leaks=raycaster, pins=pins)
    plain = refined_insertion(field, grid, tolerance=TOLERANCE, pins=pins)
    added = np.setdiff1d(repaired, seed)
    if not (added.shape[0] > 0 and all(far_from_pins(int(p)) for p in added)):
        raise SystemExit(f"the pinned repair must add probes, none within {KEEP_DISTANCE_IDS} of a pin: {added}")
    seed_leaks = leaking_points(field, seed, raycaster)[0]
    near_leaks = [int(p) for p in np.flatnonzero(seed_leaks) if not far_from_pins(int(p))]
    if not near_leaks or all(far_from_pins(int(p)) for p in np.setdiff1d(unpinned_repair, seed)):
        raise SystemExit("the pinned case must have a leaking point near a pin that the unpinned repair would add")
    sets = (("pinned seed", seed), ("pinned repaired seed", repaired), ("pinned budget answer", budget.indices),
            ("pinned tolerance answer", tolerance.indices), ("pinned answer without leaks", plain.indices))
    for name, probes in sets:
        if not np.isin(pinned, probes).all():
            raise SystemExit(f"the {name} must hold every pin")
        if not certify_delaunay(ids, probes, tetrahedralize(field.world[probes], field.frame).tets, EXTENT):
            raise SystemExit(f"the {name}'s Delaunay tetrahedralisation is not unique with a margin: choose other pins")
    if budget.indices.shape[0] != count:
        raise SystemExit(f"the pinned budget answer must hold the budget's {count} probes, pins included")
    leaks = {name: int(leaking_points(field, indices, raycaster)[0].sum())
             for name, indices in (("seed", seed), ("repaired", repaired), ("tolerance", tolerance.indices),
                                   ("tolerance_without_leaks", plain.indices))}
    if not leaks["tolerance"] < leaks["tolerance_without_leaks"]:
        raise SystemExit(f"the pinned leak-aware answer must leak less than the plain one: {leaks}")
    return {"pins": pinned.tolist(), "positions": exact(pins.positions), "keep_distance": KEEP_DISTANCE_IDS * CELL,
            "blocked": np.flatnonzero(pins.blocked).tolist(), "leaking_near_pins": near_leaks,
            "seed": seed.tolist(), "repaired_seed": repaired.tolist(),
            "budget_indices": budget.indices.tolist(), "budget_mean_error": budget.mean_error,
            "tolerance_indices": tolerance.indices.tolist(), "tolerance_mean_error": tolerance.mean_error,
            "without_leaks": plain.indices.tolist(), "leaking_points": leaks}


def repair_picks(field, probes: np.ndarray, raycaster: AnalyticBoxRaycaster, band: float) -> np.ndarray:
    """One repair round written out plainly (not through leak_aware.py's kernel): per tetrahedron holding a leaking
    point, the lowest index among its leaking points whose error is within `band` of the cell's largest. band = TIE is
    the rule (leaks.md); band = 0 is the exact comparison the two languages used before (largest error, exact ties
    to the lower index)."""
    leaking, errors = leaking_points(field, probes, raycaster)
    cells = cell_of(field, probes)
    largest: dict[int, float] = {}
    for p in np.flatnonzero(leaking).tolist():
        largest[cells[p]] = max(largest.get(cells[p], -np.inf), float(errors[p]))
    picks: dict[int, int] = {}
    for p in np.flatnonzero(leaking).tolist():  # ascending: the first within the band is the lowest index
        if cells[p] not in picks and errors[p] >= largest[cells[p]] - band:
            picks[cells[p]] = p
    return np.asarray(sorted(picks.values()), dtype=np.int64)


def dark_room_case(ids: np.ndarray, seed: np.ndarray, raycaster: AnalyticBoxRaycaster) -> dict[str, Any]:
    """The walled room nearly black: every point's SH DARK_LIGHT times the corners' base, times a random 1-2, with the
    scene's scale 1 (a dark corner of a level lit elsewhere). Every error is ~1e-10, below TIE, yet points' errors differ
    far above round-off: so a repair round's choice in a tetrahedron hangs on the tie band alone, the same in any
    arithmetic — the lowest-index leaking point with the band (leaks.md "A leak-aware default" 1), the largest error
    compared exactly without it. (On oa_koth1 errors of round-off only, where the light is even, were compared exactly and
    the two languages took different probes: quality.md §5.1.) Checked before writing: the rounds written out plainly
    (repair_picks) give leak_repaired's set; every leaking point's error is below TIE; in some tetrahedron the exact
    comparison takes another point, and wherever it does its largest error leads the next by more than 1e-3 of itself
    (no rounding can swap them, so any language comparing exactly takes that point); each round's set is certified
    Delaunay."""
    for attempt in range(DARK_ATTEMPTS):  # the first random light that exercises the band (most do)
        case = _dark_room(ids, seed, raycaster, np.random.default_rng(SEED + attempt))
        if case is not None:
            return case
    raise SystemExit(f"no dark room of {DARK_ATTEMPTS} random lights has a tetrahedron where the exact comparison takes "
                     "another point")


def _dark_room(ids: np.ndarray, seed: np.ndarray, raycaster: AnalyticBoxRaycaster,
               rng: np.random.Generator) -> dict[str, Any] | None:
    """dark_room_case with one random light, checked as its text says; None when no tetrahedron tells the exact
    comparison from the band."""
    base = np.array([1.0, 0.85, 0.6] * 9) * np.array([1.0 if c % 9 == 0 else 0.1 for c in range(27)])
    sh32 = np.asarray(DARK_LIGHT * base[None, :] * rng.uniform(1.0, 2.0, (ids.shape[0], 1)), dtype=np.float32)
    grid = EvaluationGrid(cell_size=CELL, ids=ids.astype(np.int32))
    field = ReferenceField.from_sh(grid.positions, sh32, 1.0)
    repaired = leak_repaired(field, seed, raycaster)
    current, exact_differs = np.asarray(seed, dtype=np.int64), False
    for _ in range(REPAIR_ROUNDS):
        if not certify_delaunay(ids, current, tetrahedralize(field.world[current], field.frame).tets, EXTENT):
            raise SystemExit("a set of the dark room's repair is not certified Delaunay: choose another SEED")
        leaking, errors = leaking_points(field, current, raycaster)
        if leaking.any() and not float(errors[leaking].max()) < TIE:
            raise SystemExit(f"the dark room's errors must lie below TIE: {float(errors[leaking].max())!r}")
        picks, exact_picks = repair_picks(field, current, raycaster, TIE), repair_picks(field, current, raycaster, 0.0)
        for p in np.setdiff1d(exact_picks, picks).tolist():  # the exact comparison's choice must not hang on rounding
            cells = cell_of(field, current)
            rivals = np.sort(errors[leaking & (cells == cells[p])])[::-1]
            if not rivals[0] - rivals[1] > 1e-3 * rivals[0]:
                raise SystemExit(f"point {p}'s error leads its tetrahedron's next by too little: {rivals[:2]}")
            exact_differs = True
        if picks.shape[0] == 0:
            break
        current = np.union1d(current, picks)
    if not np.array_equal(current, repaired):
        raise SystemExit(f"leak_repaired must give the rounds written out plainly: {repaired} != {current}")
    if not exact_differs:
        return None
    return {"sh": exact(sh32), "lighting_scale": 1.0, "seed": np.asarray(seed).tolist(), "repaired_seed": repaired.tolist()}


def cell_of(field, probes: np.ndarray) -> np.ndarray:
    """(N,) each point's stencil cell under `probes` (-1 at the probes)."""
    _, others, stencil = probe_stencil(field, probes, coherent=True)
    cells = np.full(field.point_count, -1, dtype=np.int64)
    cells[others] = stencil.cell
    return cells


def main(out_dir: str) -> None:
    ids, sh = walled_room(SEED)
    grid, sh32, scale, field = _field(ids, sh)
    raycaster = AnalyticBoxRaycaster(obstacles=(wall(),))
    n = field.point_count
    count = budget_count(BUDGET, n)
    seed = InsertionOrder(field, grid).selection()(budget_seed_count(RECOMMENDED_REFINE, count, n))
    repaired = leak_repaired(field, seed, raycaster)
    budget = refined_insertion(field, grid, budget=BUDGET, leaks=raycaster)
    tolerance = refined_insertion(field, grid, tolerance=TOLERANCE, leaks=raycaster)
    plain = refined_insertion(field, grid, tolerance=TOLERANCE)
    leaks = {name: int(leaking_points(field, indices, raycaster)[0].sum())
             for name, indices in (("seed", seed), ("repaired", repaired), ("tolerance", tolerance.indices),
                                   ("tolerance_without_leaks", plain.indices))}
    if not (repaired.shape[0] > seed.shape[0] and leaks["repaired"] < leaks["seed"]):
        raise SystemExit(f"the repair must add probes and end leaks: {leaks}")
    if not leaks["tolerance"] < leaks["tolerance_without_leaks"]:
        raise SystemExit(f"the leak-aware answer must leak less than the plain one: {leaks}")
    for name, probes in (("seed", seed), ("repaired seed", repaired), ("budget answer", budget.indices),
                         ("tolerance answer", tolerance.indices), ("answer without leaks", plain.indices)):
        if not certify_delaunay(ids, probes, tetrahedralize(field.world[probes], field.frame).tets, EXTENT):
            raise SystemExit(f"the {name}'s Delaunay tetrahedralisation is not unique with a margin: choose another SEED")
    golden: dict[str, Any] = {
        "contract": "Documentation~/leaks.md \"A leak-aware default\" (refined insertion with leaks=, irradiance metric)",
        "tolerance": "exact: probe sets equal; mean errors within 1e-9 relative",
        "note": f"{n} points in general position (seed {SEED}) inside a tetrahedron, a wall between id columns "
                f"x = {WALL_ID} and {WALL_ID + 1}: warm and bright below it, cool and dim beyond it",
        "cell_size": CELL, "ids": ids.tolist(), "positions": exact(grid.positions), "sh": exact(sh32),
        "lighting_scale": scale, "obstacles": [wall().to_json()],
        "leak_weight": LEAK_WEIGHT, "repair_rounds": REPAIR_ROUNDS,
        "budget": {"fraction": BUDGET, "count": count, "seed": seed.tolist(), "repaired_seed": repaired.tolist(),
                   "indices": budget.indices.tolist(), "mean_error": budget.mean_error},
        "tolerance_case": {"tolerance": TOLERANCE, "indices": tolerance.indices.tolist(),
                           "mean_error": tolerance.mean_error, "without_leaks": plain.indices.tolist()},
        "leaking_points": leaks,
        "pinned_case": pinned_case(ids, field, grid, raycaster, count),
        "dark_room_case": dark_room_case(ids, seed, raycaster),
    }
    text = json.dumps(golden, indent=None, separators=(",", ":"))
    write_text_atomic(Path(out_dir) / "leak_aware_golden.json", text + "\n")
    print("wrote", Path(out_dir) / "leak_aware_golden.json", leaks,
          {"budget": len(budget.indices), "tolerance": len(tolerance.indices), "plain": len(plain.indices)})


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "Tests/Data")
