"""Building the evaluation grid of a union of boxes, counting it, and suggesting a cell size that fits the
point limit (grid.md "Limits"; the C# core's GridBuilder). Points are only materialised after the exact union
count passed the limit.
"""

from __future__ import annotations

import math
from typing import Iterable

import numpy as np

from .box_coverage import BoxRange, box_range, box_rows, merge_rows
from .grid import EvaluationGrid, GridError, round_up_significant, validate_cell_size
from .grid_box import Box, validate_boxes

DEFAULT_POINT_LIMIT = 2_000_000
ROWS_PER_POINT_LIMIT = 4  # the candidate-row bound is 4 x point limit (grid.md "Limits")
FITTING_STEPS = 400  # at most this many third-digit steps up, then down, when suggesting a cell size


def _validate_point_limit(point_limit: int) -> int:
    if isinstance(point_limit, bool) or not isinstance(point_limit, (int, np.integer)) or point_limit < 1:
        raise GridError(f"point limit {point_limit!r} must be a whole number >= 1 (default {DEFAULT_POINT_LIMIT:,})")
    return int(point_limit)


def _ranges(boxes: list[Box], h: float) -> list[BoxRange]:
    return [box_range(box, h, number) for number, box in enumerate(boxes)]


def _candidate_rows(ranges: list[BoxRange]) -> int:
    return sum(r.row_count for r in ranges)


def _merged_rows(boxes: list[Box], h: float, ranges: list[BoxRange], stop_above: int | None = None) -> np.ndarray | None:
    """Union of all boxes' rows. With `stop_above`, returns None as soon as one box alone has more
    points than that (a lower bound of the union), so a search over cell sizes stays cheap."""
    parts: list[np.ndarray] = []
    for number, (box, coverage) in enumerate(zip(boxes, ranges)):
        box_points = 0
        for rows in box_rows(box, h, number, coverage):
            parts.append(rows)
            box_points += interval_count(rows)
            if stop_above is not None and box_points > stop_above:
                return None
    if not parts:
        return np.zeros((0, 4), dtype=np.int64)
    return merge_rows(np.concatenate(parts))


def interval_count(rows: np.ndarray) -> int:
    return int(np.sum(rows[:, 3] - rows[:, 2] + 1)) if rows.shape[0] else 0


def _check_row_bound(ranges: list[BoxRange], h: float, point_limit: int, boxes: list[Box]) -> None:
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
    h = validate_cell_size(cell_size)
    box_list = validate_boxes(boxes)
    limit = _validate_point_limit(point_limit)
    ranges = _ranges(box_list, h)
    _check_row_bound(ranges, h, limit, box_list)
    return interval_count(_merged_rows(box_list, h, ranges))


def _fits(boxes: list[Box], h: float, point_limit: int) -> bool:
    """Whether cell size h passes every limit (ids, rows, points)."""
    try:
        ranges = _ranges(boxes, h)
        if _candidate_rows(ranges) > ROWS_PER_POINT_LIMIT * point_limit:
            return False
        rows = _merged_rows(boxes, h, ranges, stop_above=point_limit)
        return rows is not None and interval_count(rows) <= point_limit
    except GridError:
        return False


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
    h = validate_cell_size(cell_size)
    box_list = validate_boxes(boxes)
    limit = _validate_point_limit(point_limit)
    ranges = _ranges(box_list, h)
    rows_fit = _candidate_rows(ranges) <= ROWS_PER_POINT_LIMIT * limit
    exact = interval_count(_merged_rows(box_list, h, ranges)) if rows_fit else None
    return _suggested_cell_size(box_list, h, ranges, limit, exact)


def _candidate_points(ranges: list[BoxRange]) -> int:
    """Sum over boxes of the lattice points in the box's range: an upper bound of the union's count
    (exact for one axis-aligned box), computed without enumerating anything."""
    return sum(0 if r.empty else r.row_count * (r.hi[0] - r.lo[0] + 1) for r in ranges)


def _suggested_cell_size(boxes: list[Box], h: float, ranges: list[BoxRange], point_limit: int,
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


def build_grid(boxes: Iterable[Box], cell_size: float, point_limit: int = DEFAULT_POINT_LIMIT) -> EvaluationGrid:
    """The evaluation grid of the union of boxes; checks every limit before allocating per-point arrays."""
    h = validate_cell_size(cell_size)
    box_list = validate_boxes(boxes)
    limit = _validate_point_limit(point_limit)
    ranges = _ranges(box_list, h)
    _check_row_bound(ranges, h, limit, box_list)
    rows = _merged_rows(box_list, h, ranges)
    count = interval_count(rows)
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
