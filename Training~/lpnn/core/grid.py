"""Evaluation grid (Documentation~/grid.md): lattice points whose cell touches the union of boxes.

The lattice is anchored at the world origin: id (i, j, k) sits at (h*i, h*j, h*k). A point belongs to
the grid when its closed cell (cube of side h centred on it) and a closed box share a point, decided
by the separating-axis theorem row by row (fixed j, k) with the 1e-9-cell tolerance of the spec, so
the C# core (Lpnn.Probes.Core.Grid) produces the same point set.

Rows are enumerated with numpy over all candidate rows of a box at once (in chunks); points are only
materialised after the exact union count passed the point limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Iterator, Sequence

import numpy as np

from ..errors import InvalidInputError

DEFAULT_POINT_LIMIT = 2_000_000
ROWS_PER_POINT_LIMIT = 4  # the candidate-row bound is 4 x point limit (grid.md "Limits")
ID_BOUND = 2**30  # |i|, |j|, |k| <= 2^30 so neighbour offsets never overflow int32
# A built grid stays within +-2^23 cells of the origin: positions h*id are float32, whose spacing at h*2^23
# is at most h, so up to there neighbouring points keep distinct positions (beyond, they may round to one).
BUILD_ID_BOUND = 2**23
CELL_TOLERANCE = 1e-9  # "exactly touching" tolerance, relative to one cell
SIGNIFICANT_DIGITS = 3  # cell-size suggestions
FITTING_STEPS = 400  # at most this many third-digit steps up, then down, when suggesting a cell size
ROW_CHUNK = 1 << 16  # candidate rows evaluated per numpy pass (bounds temporary memory)
# grid.md "Memory estimate": ids + positions + SH + score + label + id lookup + lighting cache; features add 4*F.
BYTES_PER_POINT_FIXED = 12 + 12 + 108 + 4 + 1 + 32 + 168
BYTES_PER_FEATURE = 4


class GridError(InvalidInputError):
    """The grid cannot be built as asked; the message names the bad value and what to change."""


# ------------------------------------------------------------------------------------------- boxes

@dataclass(frozen=True)
class Box:
    """A parallelepiped: centre c and half-edge vectors u, v, w (rows of `half_edges`).

    Half-edges may be zero (a flat box, a line, a point); every component must be finite.
    """

    center: np.ndarray  # (3,) float64
    half_edges: np.ndarray  # (3, 3) float64, rows u, v, w

    def __post_init__(self) -> None:
        center = np.array(self.center, dtype=np.float64).reshape(-1)
        half_edges = np.array(self.half_edges, dtype=np.float64)
        if center.shape != (3,):
            raise GridError(f"box centre needs 3 values, got shape {np.shape(self.center)}")
        if half_edges.shape != (3, 3):
            raise GridError(f"box half_edges needs 3 vectors of 3 values (u, v, w), got shape {np.shape(self.half_edges)}")
        if not np.all(np.isfinite(center)):
            raise GridError(f"box centre {center.tolist()} is not finite: every coordinate must be a finite number")
        if not np.all(np.isfinite(half_edges)):
            raise GridError(f"box half_edges {half_edges.tolist()} are not finite: every component must be a finite number")
        center.setflags(write=False)
        half_edges.setflags(write=False)
        object.__setattr__(self, "center", center)
        object.__setattr__(self, "half_edges", half_edges)

    @staticmethod
    def axis_aligned(min_corner: Sequence[float] | np.ndarray, max_corner: Sequence[float] | np.ndarray) -> "Box":
        lo = np.asarray(min_corner, dtype=np.float64).reshape(-1)
        hi = np.asarray(max_corner, dtype=np.float64).reshape(-1)
        if lo.shape != (3,) or hi.shape != (3,):
            raise GridError(f"box corners need 3 values each, got {lo.tolist()} and {hi.tolist()}")
        if np.any(lo > hi):
            raise GridError(f"box min corner {lo.tolist()} exceeds max corner {hi.tolist()}: swap them")
        return Box(center=(lo + hi) / 2.0, half_edges=np.diag((hi - lo) / 2.0))

    @staticmethod
    def from_json(data: dict) -> "Box":
        """{"center": [x, y, z], "half_edges": [[ux, uy, uz], [vx, vy, vz], [wx, wy, wz]]}."""
        try:
            return Box(center=np.asarray(data["center"], dtype=np.float64),
                       half_edges=np.asarray(data["half_edges"], dtype=np.float64))
        except (KeyError, TypeError) as exc:
            raise GridError(f"box {data!r} needs 'center' (3 numbers) and 'half_edges' (3x3 numbers)") from exc

    def to_json(self) -> dict:
        return {"center": self.center.tolist(), "half_edges": self.half_edges.tolist()}

    def corners(self) -> np.ndarray:
        """The 8 corners c +- u +- v +- w, (8, 3) float64."""
        signs = np.array([[sx, sy, sz] for sx in (-1.0, 1.0) for sy in (-1.0, 1.0) for sz in (-1.0, 1.0)])
        return self.center + signs @ self.half_edges


# --------------------------------------------------------------------------------- row enumeration

@dataclass(frozen=True)
class _BoxRange:
    """Step 1 of grid.md: a box's lattice range per axis, as Python ints."""

    lo: tuple[int, int, int]
    hi: tuple[int, int, int]

    @property
    def empty(self) -> bool:
        return any(l > h for l, h in zip(self.lo, self.hi))

    @property
    def row_count(self) -> int:
        if self.empty:
            return 0
        return (self.hi[1] - self.lo[1] + 1) * (self.hi[2] - self.lo[2] + 1)


def _validate_cell_size(cell_size: float) -> float:
    try:
        h = float(cell_size)
    except (TypeError, ValueError) as exc:
        raise GridError(f"cell size {cell_size!r} is not a number; use a positive cell size such as 0.5") from exc
    if not (math.isfinite(h) and h > 0.0):
        raise GridError(f"cell size {cell_size!r} must be a finite number > 0; use a positive cell size such as 0.5")
    return h


def _validate_boxes(boxes: Iterable[Box]) -> list[Box]:
    box_list = list(boxes)
    if not box_list:
        raise GridError("no boxes: add at least one box to the volume")
    for number, box in enumerate(box_list):
        if not isinstance(box, Box):
            raise GridError(f"box {number} is a {type(box).__name__}, expected lpnn.core.grid.Box")
    return box_list


def _box_range(box: Box, h: float, number: int) -> _BoxRange:
    """Lattice range [ceil(lo/h - 1e-9), floor(hi/h + 1e-9)] per axis, guarding the +-2^23 build bound."""
    u, v, w = np.abs(box.half_edges)
    reach = u + v + w + h / 2.0  # |u_a| + |v_a| + |w_a| + h/2
    lo = box.center - reach
    hi = box.center + reach
    first = np.ceil(lo / h - CELL_TOLERANCE)
    last = np.floor(hi / h + CELL_TOLERANCE)
    for axis in range(3):
        for bound, index in ((lo[axis], first[axis]), (hi[axis], last[axis])):
            if not (math.isfinite(index) and abs(index) <= BUILD_ID_BOUND):
                raise GridError(
                    f"cell size {h:g} is too small for box {number}: its bound {'xyz'[axis]} = {bound:g} is lattice "
                    f"index {index:g}, beyond the limit of +-2^23 ({BUILD_ID_BOUND:,}) cells from the origin where "
                    "float32 positions still tell neighbouring points apart; use a cell size of at least "
                    f"{round_up_significant(abs(bound) / BUILD_ID_BOUND):.3g} or move the box closer to the origin"
                )
    return _BoxRange(lo=tuple(int(v) for v in first), hi=tuple(int(v) for v in last))


def _dot3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a . b summed x, y, z in that order (no BLAS, no fused multiply-add), like the C# core."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def _separating_axes(box: Box) -> np.ndarray:
    """Candidate SAT axes of grid.md in its order (x, y, z; v x w, w x u, u x v; e x b with e outer, b
    inner), without the exactly-zero ones (zero half-edges, parallel edges). (A, 3)."""
    u, v, w = box.half_edges
    world = np.eye(3)
    face_normals = np.array([np.cross(v, w), np.cross(w, u), np.cross(u, v)])
    edge_products = np.array([np.cross(e, b) for e in world for b in (u, v, w)])
    axes = np.concatenate([world, face_normals, edge_products])
    return axes[np.any(axes != 0.0, axis=1)]


def _box_rows(box: Box, h: float, number: int, box_range: _BoxRange) -> Iterator[np.ndarray]:
    """Non-empty rows of one box as (M, 4) int64 arrays [k, j, i_first, i_last], in chunks."""
    if box_range.empty:
        return
    axes = _separating_axes(box)
    u, v, w = box.half_edges
    c = box.center
    # R(a) = |a.u| + |a.v| + |a.w| + (h/2)(|a_x| + |a_y| + |a_z|);  a.c summed x, y, z in order
    absolute = np.abs(axes)
    radius = (np.abs(_dot3(axes, u)) + np.abs(_dot3(axes, v)) + np.abs(_dot3(axes, w))
              + (h / 2.0) * (absolute[:, 0] + absolute[:, 1] + absolute[:, 2]))
    a_dot_c = _dot3(axes, c)
    # rows with a_x = 0 are kept when |q| <= R + 1e-9 h (|a_y| + |a_z|)
    touching = radius + CELL_TOLERANCE * h * (absolute[:, 1] + absolute[:, 2])
    if not (np.all(np.isfinite(radius)) and np.all(np.isfinite(a_dot_c))):
        raise GridError(
            f"box {number} (centre {c.tolist()}, half-edges {box.half_edges.tolist()}) with cell size {h:g} is too "
            "large to test exactly in double precision; scale the scene down"
        )
    a_x = axes[:, 0]
    zero_x = a_x == 0.0
    safe_a_x = np.where(zero_x, 1.0, a_x)
    (i_lo, j_lo, k_lo), (i_hi, j_hi, _) = box_range.lo, box_range.hi
    row_width = j_hi - j_lo + 1
    total = box_range.row_count
    for start in range(0, total, ROW_CHUNK):
        flat = np.arange(start, min(start + ROW_CHUNK, total), dtype=np.int64)
        k = k_lo + flat // row_width
        j = j_lo + flat % row_width
        # q = a_y (h j) + a_z (h k) - (a_x c_x + a_y c_y + a_z c_z), per (row, axis)
        y = (h * j.astype(np.float64))[:, None]
        z = (h * k.astype(np.float64))[:, None]
        q = (axes[None, :, 1] * y + axes[None, :, 2] * z) - a_dot_c[None, :]
        kept = np.all(~zero_x[None, :] | (np.abs(q) <= touching[None, :]), axis=1)
        end_a = (-radius[None, :] - q) / safe_a_x[None, :]
        end_b = (radius[None, :] - q) / safe_a_x[None, :]
        x_lo = np.where(zero_x[None, :], -np.inf, np.minimum(end_a, end_b)).max(axis=1, initial=-np.inf)
        x_hi = np.where(zero_x[None, :], np.inf, np.maximum(end_a, end_b)).min(axis=1, initial=np.inf)
        # Clamped to the box's own i range (as the C# core does): an axis with a tiny a_x gives a huge
        # interval, and the float -> int conversion needs bounded values.
        first = np.clip(np.ceil(x_lo / h - CELL_TOLERANCE), i_lo, i_hi + 1)
        last = np.clip(np.floor(x_hi / h + CELL_TOLERANCE), i_lo - 1, i_hi)
        kept &= first <= last
        if np.any(kept):
            yield np.stack([k[kept], j[kept], first[kept].astype(np.int64), last[kept].astype(np.int64)], axis=1)


def _merge_rows(rows: np.ndarray) -> np.ndarray:
    """Union of row intervals [k, j, first, last] -> disjoint, non-adjacent intervals in grid order.

    Sweep with +1 at `first` and -1 at `last + 1`: every row's events sum to zero, so one global
    cumulative sum is the per-row coverage count (no reset needed). Starts sort before ends at the
    same position, so touching intervals merge.
    """
    if rows.shape[0] == 0:
        return rows.reshape(0, 4)
    count = rows.shape[0]
    k = np.concatenate([rows[:, 0], rows[:, 0]])
    j = np.concatenate([rows[:, 1], rows[:, 1]])
    position = np.concatenate([rows[:, 2], rows[:, 3] + 1])
    delta = np.concatenate([np.ones(count, np.int64), -np.ones(count, np.int64)])
    order = np.lexsort((-delta, position, j, k))
    k, j, position, delta = k[order], j[order], position[order], delta[order]
    coverage = np.cumsum(delta)
    before = coverage - delta
    starts = np.flatnonzero((before == 0) & (coverage > 0))
    ends = np.flatnonzero((before > 0) & (coverage == 0))
    return np.stack([k[starts], j[starts], position[starts], position[ends] - 1], axis=1)


def _validate_point_limit(point_limit: int) -> int:
    if isinstance(point_limit, bool) or not isinstance(point_limit, (int, np.integer)) or point_limit < 1:
        raise GridError(f"point limit {point_limit!r} must be a whole number >= 1 (default {DEFAULT_POINT_LIMIT:,})")
    return int(point_limit)


def _ranges(boxes: list[Box], h: float) -> list[_BoxRange]:
    return [_box_range(box, h, number) for number, box in enumerate(boxes)]


def _candidate_rows(ranges: list[_BoxRange]) -> int:
    return sum(r.row_count for r in ranges)


def _merged_rows(boxes: list[Box], h: float, ranges: list[_BoxRange], stop_above: int | None = None) -> np.ndarray | None:
    """Union of all boxes' rows. With `stop_above`, returns None as soon as one box alone has more
    points than that (a lower bound of the union), so a search over cell sizes stays cheap."""
    parts: list[np.ndarray] = []
    for number, (box, box_range) in enumerate(zip(boxes, ranges)):
        box_points = 0
        for rows in _box_rows(box, h, number, box_range):
            parts.append(rows)
            box_points += _interval_count(rows)
            if stop_above is not None and box_points > stop_above:
                return None
    if not parts:
        return np.zeros((0, 4), dtype=np.int64)
    return _merge_rows(np.concatenate(parts))


def _interval_count(rows: np.ndarray) -> int:
    return int(np.sum(rows[:, 3] - rows[:, 2] + 1)) if rows.shape[0] else 0


def _check_row_bound(ranges: list[_BoxRange], h: float, point_limit: int, boxes: list[Box]) -> None:
    rows = _candidate_rows(ranges)
    bound = ROWS_PER_POINT_LIMIT * point_limit
    if rows > bound:
        suggestion = _suggested_cell_size(boxes, h, ranges, point_limit)
        hint = f"use a cell size of at least {suggestion:.3g}" if suggestion is not None else "use a larger cell size"
        raise GridError(
            f"cell size {h:g} gives {rows:,} candidate rows, more than {bound:,} (4 x the point limit "
            f"{point_limit:,}); {hint}"
        )


def count_points(boxes: Iterable[Box], cell_size: float, point_limit: int = DEFAULT_POINT_LIMIT) -> int:
    """Exact number of grid points of the union of boxes, from merged row intervals (no per-point arrays).

    `point_limit` only sets the candidate-row bound (4 x point_limit); the count itself may exceed it.
    """
    h = _validate_cell_size(cell_size)
    box_list = _validate_boxes(boxes)
    limit = _validate_point_limit(point_limit)
    ranges = _ranges(box_list, h)
    _check_row_bound(ranges, h, limit, box_list)
    return _interval_count(_merged_rows(box_list, h, ranges))


def _fits(boxes: list[Box], h: float, point_limit: int) -> bool:
    """Whether cell size h passes every limit (ids, rows, points)."""
    try:
        ranges = _ranges(boxes, h)
        if _candidate_rows(ranges) > ROWS_PER_POINT_LIMIT * point_limit:
            return False
        rows = _merged_rows(boxes, h, ranges, stop_above=point_limit)
        return rows is not None and _interval_count(rows) <= point_limit
    except GridError:
        return False


def round_up_significant(value: float, digits: int = SIGNIFICANT_DIGITS) -> float:
    """`value` rounded up to `digits` significant digits, without binary noise (0.19, not 0.19000000000000003)
    and never below `value` (the C# core's InvariantFormat.RoundUpSignificant, step for step)."""
    if not (math.isfinite(value) and value > 0.0):
        return value
    magnitude = 10.0 ** (math.floor(math.log10(value)) - (digits - 1))
    rounded = math.ceil(value / magnitude) * magnitude
    trimmed = float(f"{rounded:.{digits}g}")
    return trimmed if trimmed >= value else rounded


def _third_digit(value: float) -> float:
    """One unit of the third significant digit (0.01 for 1.23)."""
    return 10.0 ** (math.floor(math.log10(value)) - 2)


def _fitting_from_estimate(boxes: list[Box], h: float, estimate: float, point_limit: int) -> float | None:
    """grid.md: from the estimate rounded up to 3 digits, step one third-digit unit up until the grid fits,
    then down while it still fits (and stays above h). None when 400 steps up never fit."""
    candidate = round_up_significant(estimate)
    for _ in range(FITTING_STEPS):
        if _fits(boxes, candidate, point_limit):
            break
        candidate = round_up_significant(candidate + _third_digit(candidate))
    else:
        if not _fits(boxes, candidate, point_limit):
            return None
    for _ in range(FITTING_STEPS):
        lower = round_up_significant(candidate - _third_digit(candidate * (1.0 - 1e-12)))
        if not lower < candidate or lower <= h or not _fits(boxes, lower, point_limit):
            break
        candidate = lower
    return candidate


def fitting_cell_size(boxes: Iterable[Box], cell_size: float, point_limit: int = DEFAULT_POINT_LIMIT) -> float | None:
    """The smallest 3-significant-digit cell size whose grid fits the limits (grid.md "Limits"): from the
    h * cbrt(count / limit) estimate, stepped up or down one third-digit unit while recounting.

    When even the rows are over their bound at h, the count is taken at the size that brings the rows
    under it (rows scale as 1/h^2) and the estimate scales from there. Returns None when the grid already
    fits, or when no size within 400 steps up fits.
    """
    h = _validate_cell_size(cell_size)
    box_list = _validate_boxes(boxes)
    limit = _validate_point_limit(point_limit)
    ranges = _ranges(box_list, h)
    rows_fit = _candidate_rows(ranges) <= ROWS_PER_POINT_LIMIT * limit
    exact = _interval_count(_merged_rows(box_list, h, ranges)) if rows_fit else None
    return _suggested_cell_size(box_list, h, ranges, limit, exact)


def _candidate_points(ranges: list[_BoxRange]) -> int:
    """Sum over boxes of the lattice points in the box's range: an upper bound of the union's count
    (exact for one axis-aligned box), computed without enumerating anything."""
    return sum(0 if r.empty else r.row_count * (r.hi[0] - r.lo[0] + 1) for r in ranges)


def _suggested_cell_size(boxes: list[Box], h: float, ranges: list[_BoxRange], point_limit: int,
                         exact_count: int | None = None) -> float | None:
    """grid.md "Limits": the search starts from h * cbrt(count / limit). When even the rows are over their
    bound, the cell first grows until they fit (rows ~ 1/h^2) and the count there is the cheap
    candidate-point upper bound, so no huge grid is enumerated just to make a suggestion."""
    counted_at, counted_ranges = h, ranges
    bound = ROWS_PER_POINT_LIMIT * point_limit
    rows = _candidate_rows(ranges)
    for _ in range(FITTING_STEPS):
        if rows <= bound:
            break
        counted_at = round_up_significant(counted_at * max(math.sqrt(rows / bound), 1.001))
        try:
            counted_ranges = _ranges(boxes, counted_at)
        except GridError:
            return None
        rows = _candidate_rows(counted_ranges)
    else:
        return None
    if counted_at == h and exact_count is not None:
        count = exact_count
    else:
        count = _candidate_points(counted_ranges)
    if count <= point_limit:
        return None if counted_at == h else _fitting_from_estimate(boxes, h, counted_at, point_limit)
    return _fitting_from_estimate(boxes, h, counted_at * (count / point_limit) ** (1.0 / 3.0), point_limit)


# ----------------------------------------------------------------------------------------- the grid

def _ranks(values: np.ndarray, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position of each query in sorted unique `values`, and whether it is present."""
    position = np.searchsorted(values, query)
    inside = position < values.shape[0]
    found = np.zeros(query.shape, dtype=bool)
    found[inside] = values[position[inside]] == query[inside]
    return position, found


@dataclass
class _IdIndex:
    """Exact id -> index lookup for ids anywhere in int32 range.

    Each coordinate is replaced by its rank among the grid's distinct values on that axis, then each
    (k, j) row by its rank among the grid's distinct rows, giving keys row_rank * n_i + i_rank < N^2
    that increase in grid order: no overflow for any id range, vectorised lookups by binary search.
    The grid points' own ranks are kept, so a neighbour query only re-ranks the shifted axis.
    """

    values: tuple[np.ndarray, np.ndarray, np.ndarray]  # sorted distinct i, j, k
    point_ranks: tuple[np.ndarray, np.ndarray, np.ndarray]  # each point's rank per axis, (N,) int64
    row_values: np.ndarray  # sorted distinct row keys k_rank * n_j + j_rank
    point_rows: np.ndarray  # each point's row position in row_values, (N,) int64
    keys: np.ndarray  # (N,) strictly increasing

    @staticmethod
    def build(ids: np.ndarray) -> "_IdIndex":
        columns = [np.ascontiguousarray(ids[:, axis], dtype=np.int64) for axis in range(3)]
        values = tuple(np.unique(column) for column in columns)
        ranks = tuple(np.searchsorted(v, column) for v, column in zip(values, columns))
        row = ranks[2] * np.int64(values[1].shape[0]) + ranks[1]
        row_values = np.unique(row)
        point_rows = np.searchsorted(row_values, row)
        keys = point_rows * np.int64(values[0].shape[0]) + ranks[0]
        return _IdIndex(values, ranks, row_values, point_rows, keys)

    def _find(self, i_rank: np.ndarray, row: np.ndarray | None, found: np.ndarray,
              row_position: np.ndarray | None = None) -> np.ndarray:
        """Indices for rank-encoded queries; `row_position` given when the row is known to exist."""
        if row_position is None:
            row_position, row_found = _ranks(self.row_values, row)
            found &= row_found
        key = row_position * np.int64(self.values[0].shape[0]) + i_rank
        position = np.searchsorted(self.keys, key)
        found &= position < self.keys.shape[0]
        found[found] = self.keys[position[found]] == key[found]
        return np.where(found, position, np.int64(-1))

    def lookup(self, query: np.ndarray) -> np.ndarray:
        if self.keys.shape[0] == 0 or query.shape[0] == 0:
            return np.full(query.shape[0], -1, dtype=np.int64)
        ranked = [_ranks(self.values[axis], np.ascontiguousarray(query[:, axis])) for axis in range(3)]
        found = ranked[0][1] & ranked[1][1] & ranked[2][1]
        row = ranked[2][0] * np.int64(self.values[1].shape[0]) + ranked[1][0]
        return self._find(ranked[0][0], row, found)

    def shifted(self, column: np.ndarray, axis: int, offset: int) -> np.ndarray:
        """Indices of the grid's own points moved by offset along axis (`column` = their ids on it)."""
        if self.keys.shape[0] == 0:
            return np.zeros(0, dtype=np.int64)
        rank, found = _ranks(self.values[axis], column + np.int64(offset))
        ranks = list(self.point_ranks)
        ranks[axis] = rank
        if axis == 0:  # same row: its position is known
            return self._find(rank, None, found, row_position=self.point_rows)
        row = ranks[2] * np.int64(self.values[1].shape[0]) + ranks[1]
        return self._find(ranks[0], row, found)


@dataclass
class EvaluationGrid:
    """Grid points in grid order (k, then j, then i ascending); index = position in that order."""

    cell_size: float
    ids: np.ndarray  # (N, 3) int32
    _index: _IdIndex | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.cell_size = _validate_cell_size(self.cell_size)
        ids = np.asarray(self.ids)
        if ids.ndim != 2 or ids.shape[1] != 3:
            raise GridError(f"grid ids need shape (N, 3), got {list(ids.shape)}")
        if ids.shape[0] and (np.abs(ids.astype(np.int64)).max() > ID_BOUND):
            raise GridError(f"grid ids must stay within +-2^30 ({ID_BOUND:,})")
        self.ids = np.ascontiguousarray(ids, dtype=np.int32)
        wide = self.ids.astype(np.int64)
        if wide.shape[0] > 1:
            d = wide[1:] - wide[:-1]
            later = (d[:, 2] > 0) | ((d[:, 2] == 0) & ((d[:, 1] > 0) | ((d[:, 1] == 0) & (d[:, 0] > 0))))
            if not np.all(later):
                bad = int(np.flatnonzero(~later)[0]) + 1
                raise GridError(f"grid ids must be unique and in grid order (k, j, i); id {wide[bad].tolist()} at "
                                f"index {bad} follows {wide[bad - 1].tolist()}")

    @property
    def point_count(self) -> int:
        return int(self.ids.shape[0])

    @property
    def positions(self) -> np.ndarray:
        """(N, 3) float32 world positions h*id, computed in double."""
        return (self.ids.astype(np.float64) * self.cell_size).astype(np.float32)

    def _lookup(self) -> _IdIndex:
        if self._index is None:
            self._index = _IdIndex.build(self.ids)
        return self._index

    def index_of(self, ids: np.ndarray) -> np.ndarray:
        """Indices (M,) int64 of the points with these ids (M, 3); -1 where an id is not in the grid."""
        query = np.asarray(ids)
        if query.ndim != 2 or query.shape[1] != 3:
            raise GridError(f"index_of needs ids of shape (M, 3), got {list(query.shape)}")
        return self._lookup().lookup(np.asarray(query, dtype=np.int64))

    def neighbour(self, axis: int, offset: int) -> np.ndarray:
        """For every point, the index of the point at id + offset*e_axis, or -1. (N,) int64."""
        if axis not in (0, 1, 2):
            raise GridError(f"neighbour axis {axis!r} must be 0 (x), 1 (y) or 2 (z)")
        return self._lookup().shifted(np.ascontiguousarray(self.ids[:, axis], dtype=np.int64), axis, int(offset))

    def subset(self, mask: np.ndarray) -> "EvaluationGrid":
        """The points where `mask` (N,) is true, keeping grid order (e.g. dropping points inside walls)."""
        keep = np.asarray(mask)
        if keep.dtype != bool or keep.shape != (self.point_count,):
            raise GridError(f"subset needs a boolean mask of shape ({self.point_count},), got {keep.dtype} {list(keep.shape)}")
        if not np.any(keep):
            raise GridError(f"no evaluation point is left after filtering all {self.point_count:,} points")
        return EvaluationGrid(cell_size=self.cell_size, ids=self.ids[keep])

    @staticmethod
    def estimate_bytes(point_count: int, feature_count: int) -> int:
        """grid.md: count x (12 ids + 12 positions + 108 SH + 4F features + 4 score + 1 label + 32 hash)."""
        if point_count < 0 or feature_count < 0:
            raise GridError(f"estimate_bytes needs counts >= 0, got {point_count} points, {feature_count} features")
        return int(point_count) * (BYTES_PER_POINT_FIXED + BYTES_PER_FEATURE * int(feature_count))


def build_grid(boxes: Iterable[Box], cell_size: float, point_limit: int = DEFAULT_POINT_LIMIT) -> EvaluationGrid:
    """The evaluation grid of the union of boxes; checks every limit before allocating per-point arrays."""
    h = _validate_cell_size(cell_size)
    box_list = _validate_boxes(boxes)
    limit = _validate_point_limit(point_limit)
    ranges = _ranges(box_list, h)
    _check_row_bound(ranges, h, limit, box_list)
    rows = _merged_rows(box_list, h, ranges)
    count = _interval_count(rows)
    if count > limit:
        suggestion = _suggested_cell_size(box_list, h, ranges, limit, count)  # = fitting_cell_size
        hint = (f"the smallest cell size that fits is {suggestion:.3g}" if suggestion is not None
                else "no cell size fits; raise the point limit")
        raise GridError(
            f"the volume has {count:,} evaluation points at cell size {h:g}, more than the point limit of "
            f"{limit:,}; {hint} (or raise the point limit)"
        )
    return EvaluationGrid(cell_size=h, ids=_expand_rows(rows, count))


def _expand_rows(rows: np.ndarray, count: int) -> np.ndarray:
    """Merged row intervals (grid order) -> ids (count, 3) int32 in grid order."""
    lengths = rows[:, 3] - rows[:, 2] + 1
    ids = np.empty((count, 3), dtype=np.int32)
    ids[:, 2] = np.repeat(rows[:, 0], lengths)
    ids[:, 1] = np.repeat(rows[:, 1], lengths)
    row_start = np.cumsum(lengths) - lengths  # first point index of each row
    ids[:, 0] = np.arange(count, dtype=np.int64) - np.repeat(row_start - rows[:, 2], lengths)
    return ids
