"""Writes Tests/Data/spread_golden.json and Tests/Data/placement_error_golden.json (Tests/Data/README.md).

Run through Tools~/regenerate-golden.sh (deliberately; review the diff). The numbers come from the
Python reference implementation: lpnn.core.spread (selection.md "Spread ranking") and
lpnn.quality.metric.metric / lpnn.quality.placement.policies (quality.md §1, §2, §4). The C# port must reproduce them.

    PYTHONPATH=Training~ python Tools~/golden/make_quality_golden.py Tests/Data
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial import Delaunay

from lpnn.core.analytic_scene import AnalyticLightField, LightBlob
from lpnn.core import sh as shmath
from lpnn.core.atomic import write_text_atomic
from lpnn.core.features import scene_scale
from lpnn.core.grid import EvaluationGrid
from lpnn.core.spread import spread_ranking
from lpnn.quality.metric.metric import METRIC_EPSILON, ReferenceField, placement_error, point_errors, probe_stencil
from lpnn.quality.placement.policies import place_tolerance, prefix_selection
from lpnn.quality.metric.triangulation import tetrahedralize

SEED = 20261122


def exact(values: np.ndarray) -> list:
    """float32 values as their exact double value (JSON, round-trips through a double parser); NaN -> null."""
    out = np.asarray(values, dtype=np.float32).astype(np.float64)
    return [None if np.isnan(v) else float(v) for v in out.reshape(-1)] if out.ndim == 1 else [exact(row) for row in out]


def lattice(nx: int, ny: int, nz: int) -> np.ndarray:
    """Integer ids (N, 3) in grid order (x fastest)."""
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    return np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1)


def spread_case(name: str, positions: np.ndarray, scores: np.ndarray, note: str) -> dict[str, Any]:
    positions = np.asarray(positions, dtype=np.float32)
    scores = np.asarray(scores, dtype=np.float32)
    return {"name": name, "note": note, "positions": exact(positions), "scores": exact(scores), "exponent": 0.5,
            "ranking": spread_ranking(positions, scores, 0.5).tolist()}


def spread_golden(rng: np.random.Generator) -> dict[str, Any]:
    irregular = rng.normal(size=(40, 3)) * np.array([3.0, 1.0, 2.0])
    box = lattice(5, 4, 3).astype(np.float64) * 0.5
    thin = lattice(6, 5, 1).astype(np.float64) * 0.28
    special_scores = np.tile(np.array([np.nan, 0.0, 1.0, 0.5, -3.0, 7.0, 1e-7, 0.25]), 6)
    far = (lattice(4, 4, 3).astype(np.float64) * 0.25 + np.array([10000.0, -2500.0, 731.0])
           + rng.uniform(-0.05, 0.05, (48, 3)))
    cases = [
        spread_case("irregular", irregular, rng.uniform(0.0, 1.0, 40), "40 normally distributed points, random scores"),
        spread_case("lattice_equal_scores", box, np.full(60, 0.5), "5x4x3 lattice, cell 0.5, all scores equal: "
                    "every weight is 1, distances tie everywhere, ties go to the lower index"),
        spread_case("lattice_repeated_scores", box, rng.choice([0.2, 0.5, 0.9], 60),
                    "5x4x3 lattice, three distinct scores: keys tie between equal-weight points"),
        spread_case("lattice_special_scores", lattice(4, 4, 3).astype(np.float64), special_scores,
                    "4x4x3 lattice, cell 1: NaN (null), 0, 1, below 0, above 1 and below the 1e-6 floor; "
                    "median of an even count"),
        spread_case("plane", thin, rng.uniform(0.0, 1.0, 30), "6x5x1 lattice, cell 0.28 (float32 positions): "
                    "one plane; the ranking does not need a solid"),
        spread_case("far_from_origin", far, rng.uniform(0.0, 1.0, 48),
                    "jittered 4x4x3 lattice around (10000, -2500, 731): float32 positions with few fractional bits"),
        spread_case("four_points", rng.normal(size=(4, 3)), np.array([0.9, 0.1, 0.5, 0.5]), "seeds only"),
    ]
    return {
        "description": "Spread ranking (Documentation~/selection.md 'Spread ranking'). Written by "
                       "Tools~/golden/make_quality_golden.py from lpnn.core.spread; see Tests/Data/README.md.",
        "tolerance": "exact: the ranking must be equal, index for index",
        "cases": cases,
    }


def capture_like(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A jittered 5x4x4 lattice (cell 1 m, jitter +-0.2 m: its Delaunay tetrahedralisation is unique),
    analytic SH (lpnn.core.analytic_scene) at those positions, and the lattice ids."""
    ids = lattice(5, 4, 4)
    positions = (ids + rng.uniform(-0.2, 0.2, ids.shape) + np.array([-2.0, 0.5, -1.5])).astype(np.float32)
    base = shmath.ambient(np.array([0.05, 0.06, 0.08]))
    blobs = (LightBlob(np.array([0.5, 2.0, 0.0]), 1.2, shmath.directional(np.array([0.0, -1.0, 0.0]),
                                                                           np.array([1.0, 0.8, 0.6]), 2.0)),
             LightBlob(np.array([-2.0, 1.0, 1.5]), 0.8, shmath.directional(np.array([0.6, 0.0, -0.8]),
                                                                            np.array([0.2, 0.4, 1.0]), 1.5)
                       + shmath.ambient(np.array([0.1, 0.2, 0.3]))))
    sh = AnalyticLightField(base, blobs).sample(positions)
    return positions, sh, ids


def check_unique_delaunay(positions: np.ndarray, tets: np.ndarray) -> None:
    """Our (tie-broken) tetrahedralisation must equal plain Delaunay: then any Delaunay code agrees."""
    plain = Delaunay(positions.astype(np.float64)).simplices
    ours = {tuple(sorted(t)) for t in tets.tolist()}
    theirs = {tuple(sorted(t)) for t in plain.tolist()}
    if ours != theirs:
        raise SystemExit("the golden probe set's Delaunay tetrahedralisation is not unique: change the jitter seed")


def placement_golden(rng: np.random.Generator) -> dict[str, Any]:
    positions, sh, ids = capture_like(rng)
    n = positions.shape[0]
    field = ReferenceField.from_sh(positions, sh)
    corner = np.all((ids == ids.min(axis=0)) | (ids == ids.max(axis=0)), axis=1)
    boundary = np.any((ids == ids.min(axis=0)) | (ids == ids.max(axis=0)), axis=1)
    corners = np.flatnonzero(corner)[[0, 1, 2, 4, 5, 7]]  # 6 of 8 corners: points near the other 2 are outside
    others = rng.choice(np.flatnonzero(boundary & ~corner), 6, replace=False)
    interior = rng.choice(np.flatnonzero(~boundary), 5, replace=False)
    probes = np.sort(np.concatenate([corners, others, interior])).astype(np.int64)
    tri = tetrahedralize(field.world[probes], field.frame)
    check_unique_delaunay(positions[probes], tri.tets)
    indices, other_points, stencil = probe_stencil(field, probes)
    irradiance = point_errors(field, probes, "irradiance")
    smape = point_errors(field, probes, "smape")
    if not np.any(stencil.outside):
        raise SystemExit("no evaluation point lies outside the probes' hull: pick other probes")
    probe_slot = {int(p): k for k, p in enumerate(indices.tolist())}
    row_of = {int(p): r for r, p in enumerate(other_points.tolist())}
    points = []
    for p in range(n):
        entry: dict[str, Any] = {"index": p, "irradiance": float(irradiance[p]), "smape": float(smape[p])}
        if p in probe_slot:
            entry["probe"] = probe_slot[p]
        else:
            r = row_of[p]
            entry["outside"] = bool(stencil.outside[r])
            entry["stencil"] = stencil.vertices[r].tolist()
            entry["weights"] = stencil.weights[r].tolist()
        points.append(entry)
    summaries = {metric: {"mean": placement_error(field, probes, metric).mean,
                          "p95": placement_error(field, probes, metric).p95} for metric in ("irradiance", "smape")}
    # Tolerance policy on the spread ranking of fixed scores (the first 4 ranked points are not coplanar,
    # so the tetrahedron guarantee adds nothing; every prefix's tetrahedralisation is unique too).
    scores = rng.uniform(0.0, 1.0, n).astype(np.float32)
    ranking = spread_ranking(positions, scores)
    select = prefix_selection(EvaluationGrid(cell_size=1.0, ids=ids.astype(np.int32)), ranking)
    tolerance = 0.03
    placement = place_tolerance(field, select, tolerance)
    for count in placement.checked:
        prefix = select(count)
        if prefix.shape[0] != count:
            raise SystemExit(f"the tetrahedron guarantee changed prefix {count}: choose other scores")
        check_unique_delaunay(positions[prefix], tetrahedralize(field.world[prefix], field.frame).tets)
    return {
        "description": "Placement error (Documentation~/quality.md §1-2) and the tolerance policy (§4). Written by "
                       "Tools~/golden/make_quality_golden.py from lpnn.quality; see Tests/Data/README.md.",
        "tolerance": {"abs": 1e-7, "rel": 1e-6},
        "weights_tolerance": {"abs": 1e-7, "rel": 0.0},
        "epsilon": METRIC_EPSILON,
        "lighting_scale": float(scene_scale(sh.astype(np.float64))),
        "positions": exact(positions),
        "sh": exact(sh),
        "probes": probes.tolist(),
        "tetrahedra": tri.tets.tolist(),
        "hull_triangles": tri.hull_faces.tolist(),
        "points": points,
        "irradiance": summaries["irradiance"],
        "smape": summaries["smape"],
        "tolerance_policy": {
            "scores": exact(scores),
            "ranking": ranking.tolist(),
            "tolerance": tolerance,
            "checked": [{"count": int(c), "mean_error": float(e)} for c, e in placement.checked.items()],
            "count": int(placement.requested),
            "mean_error": float(placement.mean_error),
        },
    }


def main(out: Path) -> None:
    rng = np.random.default_rng(SEED)
    for name, document in (("spread_golden.json", spread_golden(rng)),
                           ("placement_error_golden.json", placement_golden(rng))):
        target = write_text_atomic(out / name, json.dumps(document, indent=1, allow_nan=False) + "\n")
        print(f"wrote {target}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "Tests" / "Data")
