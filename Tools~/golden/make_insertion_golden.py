"""Writes Tests/Data/insertion_golden.json (Tests/Data/README.md; contract: Documentation~/quality.md §5).

Run through Tools~/regenerate-golden.sh (deliberately; review the diff). The rankings come from the Python
reference (lpnn.quality.placement.insertion); the C# port (InsertionRanking) is an independent implementation that must
agree: its own tetrahedraliser in the tests (Bowyer-Watson, Tests/Core/Support), its own point location (bucket
grid), hull projection (BVH) and ordering code. Agreement is only meaningful where the answer is unique, so this
script CERTIFIES each case with exact integer arithmetic before writing it (else it tries the next seed):
- every round's tetrahedra are THE Delaunay tetrahedralisation of the probes: every other probe lies strictly
  outside every circumsphere (exact integer in-sphere determinants, with a margin far above double rounding);
- every other point lies strictly inside one tetrahedron (exact barycentric coordinates >= 1e-6), or, outside the
  hull, projects into the interior of one hull triangle (weights >= 1e-6), so its cell is unique;
- every decision of a round has a margin: per cell the worst error beats the next by > 1e-9 (relative), no error
  lies in (1e-14, 1e-9) around the "exact" threshold, and the cells' summed errors differ by > 1e-9 (relative);
- the typical tetrahedron's inputs: the deviation at the cut and the farthest-point distances are separated by
  > 1e-9, or tie exactly in identical IEEE arithmetic (the "plane" case: lattice coordinates, exact zeros).
- guided insertion (the "guided" case, quality.md §5.2): per cell the largest error x guide weight among the points
  above EXACT beats the next by > 1e-9 (relative); the weights come from float32 scores through guide_weights.
The "ties" case is the opposite: a lattice round whose answer exists only through the tie rules (quality.md §1 "Ties",
§5.1 "Equal errors"); its expected cells, weights and batch are derived independently in exact rational arithmetic
(ties_case), and each rule is shown to matter (the opposite choice changes the answer).

    PYTHONPATH=Training~ python Tools~/golden/make_insertion_golden.py Tests/Data
"""

from __future__ import annotations

import json
import math
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from make_tet_numbering_golden import tet_hash as plain_tet_hash  # this directory: the numbering in plain integers

from lpnn.core.atomic import write_text_atomic
from lpnn.core.features import scene_scale
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.insertion import (EXACT, INSERTION_GROWTH, TIE, guide_weights, insertion_batch,
                                              insertion_ranking, insertion_start, typical_tetrahedron)
from lpnn.quality.metric.metric import POINT_ERRORS, ReferenceField, probe_stencil
from lpnn.quality.metric.triangulation import tetrahedralize

# quality.md §5.1 step 1's directions, written out here rather than imported (the checks above use them independently).
DIRECTIONS = [(a, b, c) for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)]
CELL = 0.25  # dyadic: positions id x 0.25 are exact in float32, so exact integer geometry is the float geometry
MARGIN = 1e-9
INSIDE = 1e-6


def exact(values: np.ndarray) -> list:
    """float32 values as their exact double value (round-trips through a double parser)."""
    out = np.asarray(values, dtype=np.float32).astype(np.float64)
    return [float(v) for v in out.reshape(-1)] if out.ndim == 1 else [exact(row) for row in out]


def grid_order(ids: np.ndarray) -> np.ndarray:
    return ids[np.lexsort((ids[:, 0], ids[:, 1], ids[:, 2]))]


def det(m: list[list[int]]) -> int:
    """Exact determinant (Bareiss-free cofactor expansion; matrices of at most 5 rows)."""
    if len(m) == 1:
        return m[0][0]
    return sum((-1) ** c * m[0][c] * det([row[:c] + row[c + 1:] for row in m[1:]]) for c in range(len(m)) if m[0][c])


def orient(a, b, c, d) -> int:
    return det([[int(b[i] - a[i]) for i in range(3)], [int(c[i] - a[i]) for i in range(3)], [int(d[i] - a[i]) for i in range(3)]])


def insphere(a, b, c, d, e) -> int:
    rows = []
    for p in (a, b, c, d):
        q = [int(p[i] - e[i]) for i in range(3)]
        rows.append(q + [q[0] * q[0] + q[1] * q[1] + q[2] * q[2]])
    return det(rows)


def certify_delaunay(ids: np.ndarray, probes: np.ndarray, tets: np.ndarray, extent: int) -> bool:
    """Every other probe strictly outside every circumsphere, by a margin relative to extent^5."""
    pts = [tuple(int(v) for v in ids[p]) for p in probes]
    bound = MARGIN * float(extent) ** 5
    for t in tets:
        a, b, c, d = (pts[int(v)] for v in t)
        if orient(a, b, c, d) == 0:
            return False
        # The sign a point strictly inside the circumsphere gets: that of the centroid (coordinates x 4 stay integer).
        scaled = [tuple(4 * v for v in p) for p in (a, b, c, d)]
        inside = 1 if insphere(*scaled, tuple(a[i] + b[i] + c[i] + d[i] for i in range(3))) > 0 else -1
        for k, e in enumerate(pts):
            if k in (int(v) for v in t):
                continue
            if not insphere(a, b, c, d, e) * inside < -bound:  # strictly outside, with a margin
                return False
    return True


def certify_cells_one(field: ReferenceField, ids: np.ndarray, indices: np.ndarray, stencil, row: int, point: int) -> bool:
    """One point's cell is unique: strictly inside a tetrahedron (exact barycentrics), or projecting into a face interior."""
    if stencil.outside[row]:
        return bool(np.min(stencil.weights[row, :3]) >= INSIDE)
    tri = tetrahedralize(field.world[indices], field.frame, indices)
    a, b, c, d = (tuple(int(v) for v in ids[indices[int(v)]]) for v in tri.tets[stencil.cell[row]])
    q = tuple(int(v) for v in ids[point])
    whole = orient(a, b, c, d)
    lam = [Fraction(orient(q, b, c, d), whole), Fraction(orient(a, q, c, d), whole), Fraction(orient(a, b, q, d), whole),
           Fraction(orient(a, b, c, q), whole)]
    return min(lam) >= INSIDE


def certify_cells(field: ReferenceField, ids: np.ndarray, order: np.ndarray) -> bool:
    indices, others, stencil = probe_stencil(field, order)
    return all(certify_cells_one(field, ids, indices, stencil, row, point) for row, point in enumerate(others))


def separated(values: np.ndarray) -> bool:
    """Distinct values, every pair more than MARGIN apart relative to the largest."""
    v = np.sort(np.asarray(values, dtype=np.float64))
    if v.shape[0] < 2:
        return True
    return bool(np.all(np.diff(v) > MARGIN * max(1e-300, float(np.max(np.abs(v))))))


def certify_round(field: ReferenceField, order: np.ndarray, guide: np.ndarray | None = None) -> bool:
    indices, others, stencil = probe_stencil(field, order)
    errors = POINT_ERRORS["irradiance"](
        np.einsum("mk,mkv->mv", stencil.weights, field.light[indices][stencil.vertices]), field.light[others], field.scale)
    if np.any((errors > 1e-14) & (errors < 1e-9)):
        return False
    keys = errors if guide is None else np.where(errors > EXACT, errors * guide[others], -1.0)
    sums = []
    for cell in np.unique(stencil.cell):
        e = np.sort(keys[stencil.cell == cell])[::-1]
        if e.shape[0] > 1 and e[0] > EXACT and not e[0] - e[1] > MARGIN * e[0]:
            return False
        if e[0] > EXACT:
            sums.append(float(errors[stencil.cell == cell].sum()))
    return separated(np.asarray(sums))


def enclosed_case(seed: int) -> dict[str, Any] | None:
    """40 points inside a large tetrahedron whose corners carry the typical lighting: every round's probes
    include the corners, so no point is ever outside the hull, and every cell is certified unique."""
    ids, sh, is_corner, extent = enclosed_points(seed)
    case = finish_case("enclosed", "40 points strictly inside a tetrahedron of 4 corners that carry the median lighting, general "
                       "position (integer ids < 1024 at cell 0.25); full ranking with every round certified", ids, sh, extent)
    if case is None or sorted(case["typical_tetrahedron"]) != sorted(np.flatnonzero(is_corner).tolist()):
        return None  # the start must be the corners (typical lighting), else points would fall outside the hull
    return case


def guided_case(seed: int) -> dict[str, Any] | None:
    """The enclosed construction, ranked by guided insertion (quality.md §5.2) with seeded float32 scores in
    [0.05, 1]: every round certified as for `enclosed`, with the guide's keys (error x weight) separated per cell."""
    ids, sh, is_corner, extent = enclosed_points(seed)
    scores = np.random.default_rng(seed + 1000).uniform(0.05, 1.0, ids.shape[0]).astype(np.float32)
    case = finish_case("guided", "the enclosed construction ranked by guided insertion: seeded float32 scores in [0.05, 1], "
                       "guide weights sqrt(score / median); full ranking with every round certified", ids, sh, extent, scores)
    if case is None or sorted(case["typical_tetrahedron"]) != sorted(np.flatnonzero(is_corner).tolist()):
        return None
    return case


def enclosed_points(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Ids (grid order), SH and corner flags of the enclosed construction (see enclosed_case), and its extent."""
    rng = np.random.default_rng(seed)
    extent = 1024
    corners = np.array([[0, 0, 0], [extent, 37, 91], [53, extent, 11], [29, 71, extent]], dtype=np.int64)
    inner = []
    while len(inner) < 36:
        lam = rng.dirichlet(np.ones(4))
        if lam.min() < 0.03:
            continue
        p = np.rint(lam @ corners).astype(np.int64)
        if not any(np.array_equal(p, q) for q in inner):
            inner.append(p)
    ids = grid_order(np.concatenate([corners, np.asarray(inner)]))
    n = ids.shape[0]
    is_corner = np.array([any(np.array_equal(row, c) for c in corners) for row in ids])
    base = np.array([1.0, 0.8, 0.6] * 9, dtype=np.float64) * np.array([1.0 if c % 9 == 0 else 0.15 for c in range(27)])
    sh = np.tile(base, (n, 1))
    bumps = rng.uniform(0.2, 0.6, (n, 27)) * rng.choice([-1.0, 1.0], (n, 27))
    sh[~is_corner] += bumps[~is_corner] * np.array([1.0 if c % 9 == 0 else 0.3 for c in range(27)])
    return ids, sh, is_corner, extent


def finish_case(name: str, note: str, ids: np.ndarray, sh: np.ndarray, extent: int,
                scores: np.ndarray | None = None) -> dict[str, Any] | None:
    grid, sh32, scale, field = _field(ids, sh)
    guide = None if scores is None else guide_weights(scores)
    typical = typical_tetrahedron(field, grid)
    start = insertion_start(field, grid)
    # Independently of insertion_start: the extremes of a linear function over the ids lie at hull vertices of the ids.
    extremes = [int(np.flatnonzero((ids @ s) == (ids @ s).max())[0]) for s in DIRECTIONS]
    assert start.tolist() == typical.tolist() + [p for p in dict.fromkeys(extremes) if p not in typical], name
    ranking = insertion_ranking(field, grid, guide=guide)
    rounds = []
    order = start
    while order.shape[0] < ids.shape[0]:
        indices = order
        tri = tetrahedralize(field.world[indices], field.frame, indices)
        if not (certify_delaunay(ids, indices, tri.tets, extent) and certify_cells(field, ids, indices)
                and certify_round(field, indices, guide)):
            return None
        batch = insertion_batch(field, indices, guide=guide)
        rounds.append({"probes": indices.tolist(), "tetrahedra": tri.tets.tolist(), "batch": batch.tolist()})
        if batch.shape[0] == 0:
            break
        order = np.concatenate([order, batch])
    np.testing.assert_array_equal(ranking[:order.shape[0]], order)
    case = {"name": name, "note": note, "cell_size": CELL, "ids": ids.tolist(), "positions": exact(grid.positions),
            "sh": exact(sh32), "lighting_scale": scale, "growth": INSERTION_GROWTH, "typical_tetrahedron": typical.tolist(),
            "start": start.tolist(), "rounds": rounds, "ranking": ranking.tolist()}
    if scores is not None:
        if np.array_equal(ranking, insertion_ranking(field, grid)):
            return None  # the guide must change the ranking, else the case pins nothing of it
        case["scores"] = exact(scores)
        case["guide"] = [float(w) for w in guide]
    return case


def _field(ids: np.ndarray, sh: np.ndarray) -> tuple[EvaluationGrid, np.ndarray, float, ReferenceField]:
    grid = EvaluationGrid(cell_size=CELL, ids=ids.astype(np.int32))
    sh32 = np.asarray(sh, dtype=np.float32)
    scale = float(np.float32(scene_scale(sh32.astype(np.float64))))
    return grid, sh32, scale, ReferenceField.from_sh(grid.positions, sh32, scale)


def outside_round_case(seed: int) -> dict[str, Any] | None:
    """One round given the mesh, with points outside the probes' hull: 12 probes in the middle of the volume, and
    the other points kept only where their cell is unique (strictly inside a tetrahedron, or projecting into the
    interior of a hull triangle)."""
    rng = np.random.default_rng(seed)
    extent = 1024
    probe_ids = rng.integers(256, 768, (12, 3))
    others = rng.integers(0, extent, (200, 3))
    ids = np.unique(np.concatenate([probe_ids, others]), axis=0)
    for _ in range(3):
        ids = grid_order(ids)
        n = ids.shape[0]
        sh = np.tile(np.array([1.0, 0.8, 0.6] * 9) * np.array([1.0 if c % 9 == 0 else 0.15 for c in range(27)]), (n, 1))
        sh += np.random.default_rng(seed + 1).uniform(-0.4, 0.4, (n, 27))
        grid, sh32, scale, field = _field(ids, sh)
        probes = np.asarray([int(np.flatnonzero((ids == p).all(axis=1))[0]) for p in probe_ids], dtype=np.int64)
        indices, rest, stencil = probe_stencil(field, probes)
        keep = np.zeros(n, dtype=bool)
        keep[probes] = True
        for row, point in enumerate(rest):
            keep[point] = certify_cells_one(field, ids, probes, stencil, row, point)
        if np.all(keep):
            break
        ids = ids[keep]
    else:
        return None
    if not (certify_delaunay(ids, probes, tetrahedralize(field.world[probes], field.frame, probes).tets, extent)
            and certify_cells(field, ids, probes) and certify_round(field, probes)):
        return None
    outside = int(np.count_nonzero(stencil.outside))
    if outside < 10:
        return None
    tri = tetrahedralize(field.world[probes], field.frame, probes)
    batch = insertion_batch(field, probes)
    return {"name": "outside", "note": f"{ids.shape[0]} random lattice points, 12 probes in random order; {outside} of the "
            "other points lie outside the probes' hull", "cell_size": CELL, "ids": ids.tolist(), "positions": exact(grid.positions),
            "sh": exact(sh32), "lighting_scale": scale, "growth": INSERTION_GROWTH,
            "rounds": [{"probes": probes.tolist(), "tetrahedra": tri.tets.tolist(), "batch": batch.tolist()}]}


def plane_case() -> dict[str, Any]:
    """A 5x5x5 lattice whose lighting depends on the layer only: the middle layer IS the median (deviation exactly 0),
    so the typical candidates are its 13 lowest indices, all in one plane, and the tetrahedron guarantee must add
    the first point off it (point 0). Ties here are exact in both languages (identical IEEE operations)."""
    k, j, i = np.meshgrid(np.arange(5), np.arange(5), np.arange(5), indexing="ij")
    ids = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1)
    sh = np.zeros((ids.shape[0], 27))
    layer = ids[:, 2].astype(np.float64)
    for c in (0, 9, 18):
        sh[:, c] = 1.0 + 0.5 * layer * layer
    sh[:, 1] = 0.25 * layer
    grid = EvaluationGrid(cell_size=CELL, ids=ids.astype(np.int32))
    sh32 = np.asarray(sh, dtype=np.float32)
    scale = float(np.float32(scene_scale(sh32.astype(np.float64))))
    field = ReferenceField.from_sh(grid.positions, sh32, scale)
    typical = typical_tetrahedron(field, grid)
    assert typical.shape[0] == 5 and int(typical[-1]) == 0, typical  # the guarantee's extra point, by construction
    # The start adds the cube's corners i + 5 j + 25 k (i, j, k in {0, 4}) by direction (-,-,-), (-,-,+), ..., corner 0
    # (the first direction's) already listed: by construction, not by insertion_start.
    corners = [4 * (a > 0) + 20 * (b > 0) + 100 * (c > 0) for a, b, c in DIRECTIONS]
    start = insertion_start(field, grid)
    assert start.tolist() == typical.tolist() + [p for p in corners if p != 0], start
    return {"name": "plane", "note": "5x5x5 lattice, lighting by layer; the typical candidates lie in one plane; the start "
            "adds the cube's other 7 corners", "cell_size": CELL, "ids": ids.tolist(), "positions": exact(grid.positions),
            "sh": exact(sh32), "lighting_scale": scale, "typical_tetrahedron": typical.tolist(), "start": start.tolist()}


def closest_weights_exact(p, a, b, c) -> tuple[Fraction, Fraction, Fraction]:
    """Ericson's closest point on triangle abc (Real-Time Collision Detection §5.1.5) in exact rationals: its weights."""
    def sub(x, y):
        return [Fraction(x[i]) - Fraction(y[i]) for i in range(3)]

    def dot(x, y):
        return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]

    ab, ac, ap, bp, cp = sub(b, a), sub(c, a), sub(p, a), sub(p, b), sub(p, c)
    d1, d2, d3, d4, d5, d6 = dot(ab, ap), dot(ac, ap), dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    vc, vb, va = d1 * d4 - d3 * d2, d5 * d2 - d1 * d6, d3 * d6 - d5 * d4
    one, zero = Fraction(1), Fraction(0)
    if d1 <= 0 and d2 <= 0:
        return one, zero, zero
    if d3 >= 0 and d4 <= d3:
        return zero, one, zero
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        t = d1 / (d1 - d3)
        return 1 - t, t, zero
    if d6 >= 0 and d5 <= d6:
        return zero, zero, one
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        t = d2 / (d2 - d6)
        return 1 - t, zero, t
    if va <= 0 and d4 - d3 >= 0 and d5 - d6 >= 0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return zero, 1 - t, t
    v, w = vb / (va + vb + vc), vc / (va + vb + vc)
    return 1 - v - w, v, w


def exact_cells(ids: np.ndarray, probes: np.ndarray, tets: np.ndarray, prefer=min
                ) -> tuple[dict[int, int], dict[int, dict[int, Fraction]], dict[str, int]] | None:
    """The tie rules of quality.md §1 by brute-force enumeration in exact rationals, independent of both languages' code:
    each other point's cell and weights (probe-list index -> weight), and how many points each rule decided. Inside:
    the tetrahedra it is inside (every exact barycentric >= 0); clearly inside one (all > 0): that one; else the lowest
    index (`prefer`). Outside: the hull triangles (faces of exactly one tetrahedron) at exactly the smallest distance; the
    lowest owner (`prefer`), then the smallest sorted corners; the nearest point snapped onto the corners every tied
    triangle holds. None when a point lies near, not on, a boundary (within 1e-6 of a decision), so float rounding in
    the ±1e-9 and relative-1e-9 bands of both languages meets exactly these ties."""
    pts = [tuple(int(v) for v in ids[p]) for p in probes]
    faces: dict[tuple[int, ...], list[tuple[tuple[int, int, int], int]]] = {}
    for t, tet in enumerate(tets):
        for skip in range(4):
            face = tuple(int(tet[k]) for k in range(4) if k != skip)
            faces.setdefault(tuple(sorted(face)), []).append((face, t))
    hull = [(face, owners[0][1]) for face, owners in ((key, value) for key, value in faces.items()) if len(owners) == 1]
    cells: dict[int, int] = {}
    weights: dict[int, dict[int, Fraction]] = {}
    decided = {"inside": 0, "outside": 0}
    for point in range(ids.shape[0]):
        if point in set(probes.tolist()):
            continue
        q = tuple(int(v) for v in ids[point])
        candidates = []
        for t, tet in enumerate(tets):
            a, b, c, d = (pts[int(v)] for v in tet)
            whole = orient(a, b, c, d)
            lam = [Fraction(orient(q, b, c, d), whole), Fraction(orient(a, q, c, d), whole),
                   Fraction(orient(a, b, q, d), whole), Fraction(orient(a, b, c, q), whole)]
            if -INSIDE < min(lam) < 0 or 0 < min(lam) < INSIDE:
                return None
            if min(lam) >= 0:
                candidates.append((t, lam))
        if candidates:
            clear = [(t, lam) for t, lam in candidates if min(lam) > 0]
            t, lam = clear[0] if clear else (prefer(t for t, _ in candidates), None)
            lam = lam if lam is not None else dict(candidates)[t]
            decided["inside"] += len(candidates) > 1
            cells[point] = t
            weights[point] = {int(v): w for v, w in zip(tets[t], lam) if w}
            continue
        distances = []
        for (key, owner) in hull:
            face, _ = next(entry for entry in faces[key] if entry[1] == owner)
            a, b, c = (pts[v] for v in face)
            w = closest_weights_exact(q, a, b, c)
            x = [w[0] * a[i] + w[1] * b[i] + w[2] * c[i] for i in range(3)]
            distances.append((sum((x[i] - q[i]) ** 2 for i in range(3)), face, owner, w))
        nearest = min(d for d, *_ in distances)
        if any(nearest < d < nearest * (1 + INSIDE) for d, *_ in distances):
            return None
        tied = [(face, owner, w) for d, face, owner, w in distances if d == nearest]
        best = prefer(owner for _, owner, _ in tied)
        face, owner, w = min((entry for entry in tied if entry[1] == best), key=lambda entry: sorted(entry[0]))
        common = set(face).intersection(*(set(f) for f, _, _ in tied))
        decided["outside"] += len(tied) > 1
        cells[point] = owner
        if len(common) == 1:
            weights[point] = {next(iter(common)): Fraction(1)}
        elif len(common) == 2:
            s, e = sorted(common)
            edge = [pts[e][i] - pts[s][i] for i in range(3)]
            t = Fraction(sum((q[i] - pts[s][i]) * edge[i] for i in range(3)), sum(v * v for v in edge))
            t = min(max(t, Fraction(0)), Fraction(1))
            weights[point] = {v: x for v, x in ((s, 1 - t), (e, t)) if x}
        else:
            weights[point] = {int(v): x for v, x in zip(face, w) if x}
    return cells, weights, decided


def batch_by_counts(cells: dict[int, int], layer: np.ndarray, growth: float, probe_count: int, worst=min, order=min
                    ) -> list[int]:
    """The batch of quality.md §5.1 step 2 when every point of the middle layer has one same error e > 0 and every other
    point 0 (ties_case's lighting): a cell's worst point is its lowest-index (`worst`) middle-layer point, its sum is e x
    its middle-layer count, and the cells go by count, equal counts by their worst point's index (`order`)."""
    members: dict[int, list[int]] = {}
    for point, cell in cells.items():
        if layer[point] == 1:
            members.setdefault(cell, []).append(point)
    ranked = sorted(((len(points), worst(points)) for points in members.values()),
                    key=lambda entry: (-entry[0], entry[1] if order is min else -entry[1]))
    return [point for _, point in ranked[:max(1, math.ceil(growth * probe_count))]]


def check_numbering(probes: np.ndarray, tets: np.ndarray) -> None:
    """The tetrahedra are numbered as quality.md §1 "Ties" says — by the hash of their corners' point indices, then those
    indices — recomputed in plain integers (make_tet_numbering_golden.tet_hash, not lpnn's), since the tie rules' cells
    below read that numbering; each one's corners ascending by point index but for the orientation's swap of the last
    two."""
    points = [[int(probes[v]) for v in tet] for tet in tets.tolist()]
    keys = [(plain_tet_hash(*sorted(p)), sorted(p)) for p in points]
    if keys != sorted(keys):
        raise AssertionError("the tetrahedra are not in the order of quality.md §1's hash of their point indices")
    for p in points:
        if not (p[0] < p[1] < min(p[2], p[3])):
            raise AssertionError(f"a tetrahedron's corners {p} are not ascending by point index (but for the last two)")


def ties_case(seed: int) -> dict[str, Any] | None:
    """One round on a lattice (6 x 5 x 3 points, cell 0.25) whose probes are a few random columns at layers 0 and 2,
    lit by layer only: every point of the middle layer, inside the probes' prism or outside it, interpolates the two
    outer layers half and half, so all of them have one same error and the other points none. Most middle points lie on
    faces and edges shared by several tetrahedra, and the outside ones' nearest hull points on shared edges and
    vertices: every cell, every worst point and the order of cells with equal counts come from the tie rules alone.
    Growth 1 puts every cell's candidate in the batch, so the batch pins the whole order."""
    rng = np.random.default_rng(seed)
    k, j, i = np.meshgrid(np.arange(3), np.arange(5), np.arange(6), indexing="ij")
    ids = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1)  # grid order
    columns = rng.choice(30, int(rng.integers(5, 8)), replace=False)
    footprint = np.stack([columns % 6, columns // 6], axis=1)
    if np.linalg.matrix_rank(footprint[1:] - footprint[0]) < 2:
        return None
    probes = np.asarray([int(np.flatnonzero((ids == [x, y, z]).all(axis=1))[0]) for z in (0, 2) for x, y in footprint])
    probes = probes[rng.permutation(probes.shape[0])]  # insertion order
    sh = np.zeros((ids.shape[0], 27))
    for c, level in zip((0, 9, 18), (1.0, 0.8, 0.6)):
        sh[:, c] = level * np.array([1.0, 1.6, 1.2])[ids[:, 2]]
    sh[:, 1] = 0.3 * np.array([0.2, -0.1, 0.4])[ids[:, 2]]
    grid, sh32, scale, field = _field(ids, sh)
    tri = tetrahedralize(field.world[probes], field.frame, probes)
    check_numbering(probes, tri.tets)
    exact_answer = exact_cells(ids, probes, tri.tets)
    if exact_answer is None:
        return None
    cells, weights, decided = exact_answer
    indices, others, stencil = probe_stencil(field, probes)
    errors = POINT_ERRORS["irradiance"](
        np.einsum("mk,mkv->mv", stencil.weights, field.light[indices][stencil.vertices]), field.light[others], field.scale)
    middle = ids[others, 2] == 1
    if not (np.all(errors[~middle] < 1e-14) and errors[middle].min() > 1e-6
            and np.ptp(errors[middle]) < 1e-3 * TIE):  # equal errors, a few ulps apart at most
        return None
    growth = 1.0
    batch = insertion_batch(field, probes, growth=growth)
    expected = batch_by_counts(cells, ids[:, 2], growth, probes.shape[0])
    if batch.tolist() != expected or not np.array_equal(stencil.cell, [cells[int(p)] for p in others]):
        raise AssertionError(f"seed {seed}: the Python answer is not the exact tie rules' ({batch.tolist()} vs {expected})")
    for row, point in enumerate(others.tolist()):
        ours = np.zeros(probes.shape[0])
        np.add.at(ours, stencil.vertices[row], stencil.weights[row])
        theirs = np.zeros(probes.shape[0])
        for v, w in weights[point].items():
            theirs[v] = float(w)
        if np.max(np.abs(ours - theirs)) > 1e-12:
            raise AssertionError(f"seed {seed}: point {point}'s weights {ours} are not the exact rule's {theirs}")
    # Each rule matters: the opposite choice (highest index, highest owner) changes the cells or the batch.
    opposite = exact_cells(ids, probes, tri.tets, prefer=max)
    if opposite is None or decided["inside"] == 0 or decided["outside"] == 0:
        return None
    flipped = {p: cells[p] != opposite[0][p] for p in cells}
    outside = set(np.asarray(others)[stencil.outside].tolist())
    if not (any(flipped[p] for p in cells if p not in outside) and any(flipped[p] for p in outside)
            and batch_by_counts(opposite[0], ids[:, 2], growth, probes.shape[0]) != expected
            and batch_by_counts(cells, ids[:, 2], growth, probes.shape[0], worst=max) != expected
            and batch_by_counts(cells, ids[:, 2], growth, probes.shape[0], order=max) != expected):
        return None
    stencils = [[[int(v), float(w)] for v, w in sorted(weights[int(p)].items())] for p in others]
    return {"name": "ties", "note": f"6 x 5 x 3 lattice lit by layer, {probes.shape[0]} probes on {footprint.shape[0]} "
            f"columns at layers 0 and 2, growth 1; {decided['inside']} points inside lie on boundaries shared by several "
            f"tetrahedra and {decided['outside']} outside have several nearest hull triangles; every middle-layer point has "
            "the same error", "cell_size": CELL, "ids": ids.tolist(), "positions": exact(grid.positions), "sh": exact(sh32),
            "lighting_scale": scale, "growth": growth,
            "rounds": [{"probes": probes.tolist(), "tetrahedra": tri.tets.tolist(), "batch": batch.tolist(),
                        "cells": [cells.get(p, -1) for p in range(ids.shape[0])],
                        "stencils": [stencils[list(others).index(p)] if p in cells else [] for p in range(ids.shape[0])]}]}


def first_certified(make, seeds) -> dict[str, Any]:
    for seed in seeds:
        print(make.__name__, seed, flush=True)
        case = make(seed)
        if case is not None:
            case["seed"] = seed
            return case
    raise SystemExit(f"no certified case among seeds {seeds}")


def main(out_dir: str) -> None:
    golden = {
        "contract": "Documentation~/quality.md §5 (insertion ranking, irradiance metric; §5.2 guided insertion)",
        "tolerance": "exact: typical tetrahedra, batches and rankings equal index for index",
        "exact_threshold": EXACT,
        "cases": [first_certified(enclosed_case, range(1, 200)), first_certified(outside_round_case, range(1, 400)), plane_case(),
                  first_certified(guided_case, range(1, 400)), first_certified(ties_case, range(1, 400))],
    }
    text = json.dumps(golden, indent=None, separators=(",", ":"))
    write_text_atomic(Path(out_dir) / "insertion_golden.json", text + "\n")
    print("wrote", Path(out_dir) / "insertion_golden.json", [(c["name"], c.get("seed")) for c in golden["cases"]])


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "Tests/Data")
