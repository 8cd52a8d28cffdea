"""Writes Tests/Data/batched_refinement_golden.json (Tests/Data/README.md; contract: Documentation~/quality.md §5.3).

Run through Tools~/regenerate-golden.sh (deliberately; review the diff). The results come from the Python reference
(lpnn.quality.placement.batched_refinement); the C# port (BatchedRefinement) is an independent implementation that must agree:
its own tetrahedraliser in the tests (Bowyer-Watson, Tests/Core/Support), point location, hull projection, independent
set, sorting and summation. Agreement is only meaningful where the answer is unique, so this script CERTIFIES every
probe set a case evaluates (each round's set, its trial set and the set after the commit) with exact integer
arithmetic, as make_insertion_golden.py does for insertion (its Delaunay and cell certificates), and every decision
with a margin: the measured costs a round ranks and thresholds are pairwise separated by > 1e-9 (relative), and
with a tolerance every running error sum compared with tau x N differs from it by > 1e-9 (relative).

    PYTHONPATH=Training~ python Tools~/golden/make_batched_refinement_golden.py Tests/Data
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from lpnn.core.atomic import write_text_atomic
from lpnn.quality.placement.batched_refinement import (COUNT_COMMIT_FRACTION, TOLERANCE_COMMIT_FRACTION,
                                                       batched_refinement)
from lpnn.quality.metric.triangulation import tetrahedralize

from make_insertion_golden import (MARGIN, _field, certify_cells, certify_delaunay, enclosed_points, exact,
                                   first_certified, separated)


def _certified_set(field, ids: np.ndarray, probes: np.ndarray, extent: int) -> bool:
    tri = tetrahedralize(field.world[probes], field.frame)
    return certify_delaunay(ids, probes, tri.tets, extent) and certify_cells(field, ids, probes)


def _apart(value: float, limit: float) -> bool:
    return abs(value - limit) > MARGIN * abs(limit)


def _certified_rounds(field, ids: np.ndarray, extent: int, rounds: list[dict[str, Any]], limit: float | None) -> bool:
    for step in rounds:
        sets = [step["following"]] if "following" in step else [step["probes"], step["remaining"]]
        if not all(_certified_set(field, ids, np.asarray(s), extent) for s in sets):
            return False
        if "following" in step:
            if limit is not None and not _apart(step["following_sum"], limit):
                return False
            continue
        if not separated(step["measured"]):
            return False
        if limit is not None:
            running = step["error_sum"] + np.cumsum(_costs_of(step, step["eligible"]))
            if not (_apart(step["error_sum"], limit) and all(_apart(float(v), limit) for v in running)):
                return False
    return True


def _costs_of(step: dict[str, Any], points: np.ndarray) -> np.ndarray:
    by_point = dict(zip(step["candidates"].tolist(), step["costs"].tolist()))
    return np.asarray([by_point[int(p)] for p in points], dtype=np.float64)


def refinement_case(name: str, note: str, seed: int, count: int | None = None,
                    tolerance: float | None = None) -> dict[str, Any] | None:
    """The enclosed construction refined from all its points with its 4 corners kept (as a Unity volume keeps its
    bounds corners): no point ever leaves the probes' hull, so every stencil can be certified unique (a point projected
    onto a shrunken hull lands on an edge too often to certify)."""
    ids, sh, is_corner, extent = enclosed_points(seed)
    grid, sh32, scale, field = _field(ids, sh)
    n = ids.shape[0]
    keep = np.flatnonzero(is_corner)
    rounds: list[dict[str, Any]] = []
    result = batched_refinement(field, np.arange(n), count=count, tolerance=tolerance, keep=keep, trace=rounds.append)
    limit = None if tolerance is None else tolerance * n
    if not (_certified_set(field, ids, np.arange(n), extent) and _certified_rounds(field, ids, extent, rounds, limit)):
        return None
    if result.rounds < 4:
        return None  # too short to pin the rounds
    trace = [{"probes": r["probes"].tolist(), "candidates": r["candidates"].tolist(), "commit": r["commit"].tolist()}
             for r in rounds if "candidates" in r]
    case: dict[str, Any] = {"name": name, "note": note, "cell_size": 0.25, "ids": ids.tolist(),
                            "positions": exact(grid.positions), "sh": exact(sh32), "lighting_scale": scale,
                            "seed_points": list(range(n)), "commit_fraction": COUNT_COMMIT_FRACTION if count is not None else TOLERANCE_COMMIT_FRACTION,
                            "indices": result.indices.tolist(), "mean_error": result.mean_error,
                            "rounds": result.rounds, "stop_reason": result.stop_reason, "keep": keep.tolist(),
                            "trace": trace}
    if count is not None:
        case["count"] = count
    if tolerance is not None:
        case["tolerance"] = tolerance
    return case


def count_case(seed: int) -> dict[str, Any] | None:
    return refinement_case("count", "the enclosed construction (make_insertion_golden.py) refined from all 40 points down "
                           "to 10, its 4 corners kept; every evaluated set and decision certified", seed, count=10)


def tolerance_case(seed: int) -> dict[str, Any] | None:
    return refinement_case("tolerance", "the enclosed construction refined from all 40 points within a mean error of "
                           "0.08, its 4 corners kept; running sums certified apart from tau x N", seed, tolerance=0.08)


def main(out_dir: str) -> None:
    golden = {
        "contract": "Documentation~/quality.md §5.3 (batched refinement, irradiance metric)",
        "tolerance": "exact: kept indices, rounds and stop reasons equal; mean error within 1e-9 relative",
        "cases": [first_certified(count_case, range(1, 200)), first_certified(tolerance_case, range(1, 200))],
    }
    text = json.dumps(golden, indent=None, separators=(",", ":"))
    write_text_atomic(Path(out_dir) / "batched_refinement_golden.json", text + "\n")
    print("wrote", Path(out_dir) / "batched_refinement_golden.json", [(c["name"], c.get("seed")) for c in golden["cases"]])


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "Tests/Data")
