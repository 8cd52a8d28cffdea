"""Selection policies that model only what the scene requires (quality.md §4).

Any ranking (LPNN scores, a reference ordering, a baseline) becomes a probe set by
- budget: its top-K prefix;
- tolerance: the smallest prefix whose mean placement error is <= tau.
Both always end with lpnn.core.selection.ensure_tetrahedron (>= 4 probes, not all in one plane).

The error of a prefix is not monotonic in K (adding a probe re-tetrahedralises and can make some
points worse), so the tolerance search guarantees what it checks: the returned K has error <= tau,
a count within max(1, K // SEARCH_RESOLUTION) below K was checked and failed (unless K is the
smallest count searched), and every count below K that was checked failed. For a reference decimation every prefix's error is known (its error
curve), so the answer there is the exact smallest count.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ...errors import InvalidInputError
from ...core.grid import EvaluationGrid
from ...core.selection import ensure_tetrahedron, percentile_count
from ...core.spread import SpreadPrefix
from .policy_rules import SEARCH_RESOLUTION, budget_problem, tolerance_problem
from .decimation.decimation import MINIMUM_PROBES, Decimation
from ..metric.metric import PRIMARY_METRIC, ReferenceField, mean_placement_error, placement_error

SelectionForCount = Callable[[int], np.ndarray]


class PolicyError(InvalidInputError):
    """A policy parameter is out of range; the message names it and the valid range."""


@dataclass(frozen=True)
class Placement:
    indices: np.ndarray  # (K,) int64 point indices, sorted
    requested: int  # the count the policy asked for (prefix length)
    added_for_tetrahedron: int
    mean_error: float  # placement error (metric below) of `indices`
    metric: str
    checked: dict[int, float] = field(default_factory=dict)  # tolerance search: count -> mean error


def checked_fraction(fraction: float) -> float:
    value = float(fraction)
    problem = budget_problem(value)
    if problem:
        raise PolicyError(f"budget {fraction!r} {problem}")
    return value


def checked_tolerance(tolerance: float) -> float:
    value = float(tolerance)
    problem = tolerance_problem(value)
    if problem:
        raise PolicyError(f"tolerance {tolerance!r} {problem}")
    return value


def budget_count(fraction: float, point_count: int) -> int:
    """K for a budget fraction: round(f N) halves up (as selection.percentile_count), at least 1."""
    return max(1, percentile_count(1.0 - checked_fraction(fraction), point_count))


def prefix_selection(grid: EvaluationGrid, ranking: np.ndarray) -> SelectionForCount:
    """K -> the top-K of a ranking, completed to a tetrahedron."""
    order = np.asarray(ranking, dtype=np.int64)

    def select(count: int) -> np.ndarray:
        return ensure_tetrahedron(grid, order, order[:count])[0]

    return select


def spread_prefix_selection(grid: EvaluationGrid, spread: SpreadPrefix) -> SelectionForCount:
    """prefix_selection of the spread ranking, ranking only as many points as a count needs: the same
    sets. A prefix the tetrahedron guarantee completes with points beyond the ranked ones (a flat
    prefix) is completed again with the whole ranking."""

    def select(count: int) -> np.ndarray:
        head = spread.prefix(count)
        order = spread.provisional_order()
        indices, added = ensure_tetrahedron(grid, order, head)
        if added:
            position = np.empty(order.shape[0], dtype=np.int64)
            position[order] = np.arange(order.shape[0])
            if int(position[indices].max()) >= spread.computed:  # completed from the unranked tail
                order = spread.prefix(spread.point_count)
                indices = ensure_tetrahedron(grid, order, order[:count])[0]
        return indices

    return select


def place_count(field_: ReferenceField, selection: SelectionForCount, count: int,
                metric: str = PRIMARY_METRIC) -> Placement:
    """Budget policy: the selection at `count`, with its error."""
    indices = selection(count)
    return Placement(indices=indices, requested=count, added_for_tetrahedron=max(0, indices.shape[0] - count),
                     mean_error=placement_error(field_, indices, metric).mean, metric=metric)


def place_tolerance(field_: ReferenceField, selection: SelectionForCount, tolerance: float,
                    metric: str = PRIMARY_METRIC, smallest: int = MINIMUM_PROBES,
                    error_of: Callable[[int, np.ndarray], float] | None = None) -> Placement:
    """Tolerance policy: exponential search from `smallest`, then bisection over prefix counts down to the search's
    resolution (`search_resolved`). `error_of(count, probes)`: the mean error of selection(count) when the selection
    knows a cheaper way to it (insertion.InsertionOrder.mean_error), else metric.mean_placement_error."""
    found = bounded_tolerance(field_, selection, tolerance, metric, smallest, error_of=error_of)
    assert found is not None  # without a bound the search ends at the latest with all points
    return found


def search_resolved(failing: int, passing: int) -> bool:
    """Whether the bisection between the last failing and the first passing count may stop: they are adjacent, or
    at most passing / SEARCH_RESOLUTION apart (integers only, so C#'s ToleranceSearch decides exactly alike)."""
    width = passing - failing
    return width <= 1 or width * SEARCH_RESOLUTION <= passing


def bounded_tolerance(field_: ReferenceField, selection: SelectionForCount, tolerance: float,
                      metric: str = PRIMARY_METRIC, smallest: int = MINIMUM_PROBES,
                      largest: int | None = None,
                      error_of: Callable[[int, np.ndarray], float] | None = None) -> Placement | None:
    """place_tolerance, giving up (None) as soon as it is known that the answer exceeds `largest`:
    the search then never evaluates a count above largest + 1 (a caller with a cheaper plan for
    large answers, e.g. the refine tier running the full reference, stops paying for the search)."""
    tau = checked_tolerance(tolerance)
    n = field_.point_count
    low_limit = max(1, min(int(smallest), n))
    ceiling = n if largest is None else max(low_limit, min(int(largest) + 1, n))
    checked: dict[int, float] = {}
    chosen: dict[int, np.ndarray] = {}

    def error_at(count: int) -> float:
        if count not in checked:
            chosen[count] = selection(count)
            checked[count] = (mean_placement_error(field_, chosen[count], metric) if error_of is None
                              else error_of(count, chosen[count]))
        return checked[count]

    failing, passing = low_limit - 1, low_limit
    while error_at(passing) > tau:
        if passing == n:  # all points: error 0, so only an impossible tolerance gets here
            raise PolicyError(f"even all {n:,} points miss the tolerance {tau:g}")
        if passing >= ceiling:
            return None
        failing, passing = passing, min(2 * passing, ceiling)
    # Above a bound the bracket is narrowed to the unit: a resolved bracket [failing, largest + 1] may still hold a
    # passing count <= largest, and giving up then would send a caller to its costlier plan for nothing.
    while not search_resolved(failing, passing) or (largest is not None and failing + 1 < passing
                                                    and failing < largest < passing):
        middle = (failing + passing) // 2
        if error_at(middle) <= tau:
            passing = middle
        else:
            failing = middle
    if largest is not None and passing > largest:
        return None
    indices = chosen[passing]
    return Placement(indices=indices, requested=passing, added_for_tetrahedron=max(0, indices.shape[0] - passing),
                     mean_error=checked[passing], metric=metric, checked=dict(sorted(checked.items())))


def reference_tolerance(decimation: Decimation, tolerance: float) -> Placement:
    """Tolerance policy on a reference ordering: the exact smallest prefix, read from its error curve."""
    tau = checked_tolerance(tolerance)
    count = decimation.smallest_count_within(tau)
    if count is None:  # only a seeded decimation can miss: the full set has error 0
        raise PolicyError(f"the decimation started from {decimation.start_count:,} probes with mean error "
                          f"{decimation.error_curve[decimation.start_count]:.4g}, above the tolerance {tau:g}: "
                          "seed it with more points")
    return Placement(indices=decimation.prefix(count), requested=count, added_for_tetrahedron=0,
                     mean_error=float(decimation.error_curve[count]), metric=decimation.metric,
                     checked={count: float(decimation.error_curve[count])})


def reference_count(decimation: Decimation, count: int) -> Placement:
    """Budget policy on a reference ordering (its prefixes are the decimation's own states); a count
    below the decimation's floor of 4 gets the floor, one above its starting set gets that set."""
    kept = min(max(int(count), decimation.smallest_count), decimation.start_count)
    return Placement(indices=decimation.prefix(kept), requested=int(count),
                     added_for_tetrahedron=max(0, kept - int(count)),
                     mean_error=float(decimation.error_curve[kept]), metric=decimation.metric)


def reference_label_source(method: str, budget: float | None, tolerance: float | None) -> str:
    """The `label_source` of reference labels, e.g. "reference:fast-greedy budget=0.2"."""
    name = "fast-greedy" if method == "fast" else "faithful-greedy"
    parameter = f"budget={budget:g}" if budget is not None else f"tolerance={tolerance:g}"
    return f"reference:{name} {parameter}"
