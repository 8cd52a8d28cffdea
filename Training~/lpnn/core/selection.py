"""From scores to probes (Documentation~/selection.md): ranking, remap, policies, tetrahedron guarantee.

Ranking is by raw score, best first (+inf > finite > -inf, NaN last), ties by lower point index, so
equal scores never give duplicates or run-to-run differences. Coplanarity is decided exactly on the
integer lattice ids.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable

import numpy as np

from ..errors import InvalidInputError
from .grid import EvaluationGrid
from .grid_box import Box

POLICIES = ("percentile", "budget", "threshold")
PERCENTILE_ROUNDING = 1e-9  # absorbs binary rounding: (1 - 0.9) * 125 + 0.5 is 12.999... in double
TETRAHEDRON_POINTS = 4


class SelectionError(InvalidInputError):
    """A policy parameter is out of range, or no valid probe set exists; the message says what to change."""


@dataclass
class SelectionResult:
    indices: np.ndarray  # (K,) int64 point indices, sorted ascending
    added_for_tetrahedron: int
    corners_added: int


# --------------------------------------------------------------------------------- ranking, remap

def _scores(scores: np.ndarray, n: int | None = None) -> np.ndarray:
    values = np.asarray(scores)
    if values.ndim != 1:
        raise SelectionError(f"scores must be one value per point (shape (N,)), got shape {list(values.shape)}")
    if n is not None and values.shape[0] != n:
        raise SelectionError(f"{values.shape[0]:,} scores for a grid of {n:,} points")
    return values.astype(np.float64)


def rank(scores: np.ndarray) -> np.ndarray:
    """Point indices (N,) int64, best first: +inf, finite descending, -inf, NaN; ties by lower index."""
    values = _scores(scores)
    category = np.select([values == np.inf, np.isfinite(values), values == -np.inf], [0, 1, 2], default=3)
    key = np.where(np.isfinite(values), -values, 0.0)
    return np.lexsort((key, category)).astype(np.int64)  # lexsort is stable: equal keys keep index order


def remap(scores: np.ndarray) -> np.ndarray:
    """Scores to [0, 1] over the finite range (all equal -> 1); +inf -> 1, -inf -> 0, NaN -> 0."""
    values = _scores(scores)
    finite = np.isfinite(values)
    out = np.where(values == np.inf, 1.0, 0.0)
    if not np.any(finite):
        return out
    lo, hi = float(values[finite].min()), float(values[finite].max())
    if hi > lo:
        span = hi - lo
        if math.isfinite(span):
            out[finite] = (values[finite] - lo) / span
        else:  # float64 extremes: halve both sides so the span cannot overflow
            out[finite] = (values[finite] / 2.0 - lo / 2.0) / (hi / 2.0 - lo / 2.0)
        np.clip(out, 0.0, 1.0, out=out)
    else:
        out[finite] = 1.0
    return out


def percentile_count(p: float, n: int) -> int:
    """K = floor((1 - p) n + 0.5 + 1e-9): p = 0.9 keeps the top 10 %, rounded to the nearest point, halves up."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise SelectionError(f"point count {n!r} must be a whole number >= 0")
    value = _number(p, "percentile")
    if not 0.0 <= value <= 1.0:
        raise SelectionError(f"percentile {p!r} is outside [0, 1]: 0.9 keeps the top 10 % of the points")
    return int(math.floor((1.0 - value) * int(n) + 0.5 + PERCENTILE_ROUNDING))


def _number(value: object, what: str) -> float:
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError) as exc:
        raise SelectionError(f"{what} {value!r} is not a number") from exc
    if not math.isfinite(number):
        raise SelectionError(f"{what} {value!r} is not a finite number")
    return number


# ---------------------------------------------------------------------------------------- policies

def _policy_indices(ranking: np.ndarray, remapped: np.ndarray | None, scores: np.ndarray, policy: str,
                    value: float) -> np.ndarray:
    n = ranking.shape[0]
    if policy == "percentile":
        return ranking[: percentile_count(value, n)]
    if policy == "budget":
        budget = _number(value, "budget")
        if budget < 1 or budget != math.floor(budget):
            raise SelectionError(f"budget {value!r} must be a whole number of probes >= 1")
        return ranking[: min(int(budget), n)]
    if policy == "threshold":
        threshold = _number(value, "threshold")
        if not 0.0 <= threshold <= 1.0:
            raise SelectionError(f"threshold {value!r} is outside [0, 1] (it applies to the remapped scores)")
        assert remapped is not None
        return np.flatnonzero((remapped >= threshold) & ~np.isnan(scores))
    raise SelectionError(f"unknown selection policy {policy!r}; use one of {', '.join(POLICIES)} "
                         "(the tolerance policy lives with the quality metric)")


def _corner_indices(grid: EvaluationGrid, boxes: Iterable[Box]) -> np.ndarray:
    """Grid points floor(corner/h + 0.5) of every box corner; corners whose point is not in the grid
    (e.g. dropped inside a wall by the importer) are skipped."""
    box_list = list(boxes)
    if not box_list:
        return np.zeros(0, dtype=np.int64)
    corners = np.concatenate([box.corners() for box in box_list])
    lattice = np.floor(corners / grid.cell_size + 0.5)
    inside = np.all(np.abs(lattice) <= 2.0**31, axis=1)
    found = grid.index_of(lattice[inside].astype(np.int64))
    return np.unique(found[found >= 0])


def select(grid: EvaluationGrid, scores: np.ndarray, policy: str, value: float, keep_corners: bool = False,
           boxes: Iterable[Box] | None = None) -> SelectionResult:
    """Apply a policy, then the options in spec order: bounds corners (optional), tetrahedron guarantee."""
    values = _scores(scores, grid.point_count)
    if grid.point_count == 0:
        raise SelectionError("the evaluation grid has no points: there is nothing to select")
    ranking = rank(values)
    remapped = remap(values) if policy == "threshold" else None
    chosen = np.unique(_policy_indices(ranking, remapped, values, policy, value))
    corners_added = 0
    if keep_corners:
        if boxes is None:
            raise SelectionError("keep_corners needs the volume's boxes (pass boxes=...)")
        with_corners = np.union1d(chosen, _corner_indices(grid, boxes))
        corners_added = int(with_corners.shape[0] - chosen.shape[0])
        chosen = with_corners
    indices, added = ensure_tetrahedron(grid, ranking, chosen)
    return SelectionResult(indices=indices, added_for_tetrahedron=added, corners_added=corners_added)


# ------------------------------------------------------------------------------ tetrahedron guarantee

class _ExactLattice:
    """Exact collinearity / coplanarity tests on integer ids.

    Differences of ids reach 2^31, so cross products reach 2^63 and triple products 2^95: int64 is
    used when the grid's id span guarantees no overflow (6 D^3 < 2^63), Python integers otherwise.
    """

    def __init__(self, ids: np.ndarray):
        wide = ids.astype(np.int64)
        span = int((wide.max(axis=0) - wide.min(axis=0)).max()) if wide.shape[0] else 0
        self.dtype = np.int64 if 6 * span**3 < 2**63 else object
        self.ids = wide.astype(self.dtype)

    def _from(self, origin: np.ndarray, rows: np.ndarray | slice) -> np.ndarray:
        return self.ids[rows] - origin

    def off_line(self, a: int, b: int, rows: np.ndarray | slice = slice(None)) -> np.ndarray:
        """Which points are not on the line through points a and b."""
        direction = self.ids[b] - self.ids[a]
        cross = np.cross(self._from(self.ids[a], rows), direction)
        return np.any(cross != 0, axis=1)

    def normal(self, a: int, b: int, c: int) -> np.ndarray:
        """(b - a) x (c - a), exact."""
        return np.cross(self.ids[b] - self.ids[a], self.ids[c] - self.ids[a])

    def off_plane(self, a: int, b: int, c: int, rows: np.ndarray | slice = slice(None)) -> np.ndarray:
        """Which points are not on the plane through points a, b, c (not collinear)."""
        normal = self.normal(a, b, c)
        relative = self._from(self.ids[a], rows)
        return (relative[:, 0] * normal[0] + relative[:, 1] * normal[1] + relative[:, 2] * normal[2]) != 0


def degenerate_shape(ids: np.ndarray) -> str | None:
    """None when the integer lattice ids (N, 3) span a tetrahedron, else the shape they are confined to (exact):
    "none at all", "a single point", "all on one line" or "all in one plane"."""
    if len(ids) == 0:
        return "none at all"
    lattice = _ExactLattice(np.asarray(ids))
    moved = np.flatnonzero(np.any(lattice.ids != lattice.ids[0], axis=1))
    if len(moved) == 0:
        return "a single point"
    off_line = np.flatnonzero(lattice.off_line(0, int(moved[0])))
    if len(off_line) == 0:
        return "all on one line"
    return None if lattice.off_plane(0, int(moved[0]), int(off_line[0])).any() else "all in one plane"


def _first_ranked(ranking: np.ndarray, candidates: np.ndarray) -> int | None:
    """The highest-ranked point where `candidates` (N,) is true, or None."""
    ordered = candidates[ranking]
    if not np.any(ordered):
        return None
    return int(ranking[int(np.argmax(ordered))])


def _flat_grid_error(grid: EvaluationGrid, kind: str, axes: str) -> SelectionError:
    return SelectionError(
        f"Unity needs at least {TETRAHEDRON_POINTS} light probes that are not all in one plane, but the whole "
        f"evaluation grid ({grid.point_count:,} points, cell size {grid.cell_size:g}) is {kind}: make the volume at "
        f"least two cells deep along {axes} or use a smaller cell size"
    )


def _axes_names(weights: np.ndarray, count: int) -> str:
    """The `count` axes with the smallest weights, named 'x', 'y and z', ... (ties: lower axis first)."""
    order = sorted(range(3), key=lambda axis: (float(weights[axis]), axis))[:count]
    names = ["xyz"[axis] for axis in sorted(order)]
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def ensure_tetrahedron(grid: EvaluationGrid, ranking: np.ndarray, selected: np.ndarray) -> tuple[np.ndarray, int]:
    """Add at most 4 highest-ranked points so the set has 4 points not all in one plane.

    Returns (indices sorted ascending, number added). Raises SelectionError when the whole grid is a
    single point, a line or one plane.
    """
    chosen = np.unique(np.asarray(selected, dtype=np.int64))
    order = np.asarray(ranking, dtype=np.int64)
    n = grid.point_count
    if order.shape != (n,):
        raise SelectionError(f"ranking has {order.shape[0]:,} entries for a grid of {n:,} points")
    if chosen.shape[0] and (chosen[0] < 0 or chosen[-1] >= n):
        raise SelectionError(f"selected indices must be in [0, {n}), got {chosen[0]}..{chosen[-1]}")
    if degenerate_shape(grid.ids[chosen]) is None:
        # Already a tetrahedron: the loop below would add nothing, and its lattice over every point costs 40 ms at 10^6
        # points (the tolerance search's every selection; exact either way).
        return chosen, 0
    lattice = _ExactLattice(grid.ids)
    added: list[int] = []
    while True:
        if chosen.shape[0] == 0:
            if n == 0:
                raise SelectionError("the evaluation grid has no points: there is nothing to select")
            new = int(order[0])
        elif chosen.shape[0] == 1:
            outside = np.ones(n, dtype=bool)
            outside[chosen] = False
            new = _first_ranked(order, outside)
            if new is None:
                raise _flat_grid_error(grid, "a single point", "x, y and z")
        else:
            a, b = int(chosen[0]), int(chosen[1])
            off_line = lattice.off_line(a, b, chosen)
            if not np.any(off_line):
                new = _first_ranked(order, lattice.off_line(a, b))
                if new is None:
                    direction = lattice.ids[b] - lattice.ids[a]
                    raise _flat_grid_error(grid, "a line", _axes_names(np.abs(np.asarray(direction, dtype=np.float64)), 2))
            else:
                c = int(chosen[int(np.argmax(off_line))])
                if np.any(lattice.off_plane(a, b, c, chosen)):
                    break
                new = _first_ranked(order, lattice.off_plane(a, b, c))
                if new is None:
                    normal = np.asarray([float(v) for v in lattice.normal(a, b, c)])
                    raise _flat_grid_error(grid, "one plane", _axes_names(-np.abs(normal), 1))
        added.append(new)
        chosen = np.union1d(chosen, [new]).astype(np.int64)
    return chosen, len(added)
