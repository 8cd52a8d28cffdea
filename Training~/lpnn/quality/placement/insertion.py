"""Error-driven insertion: the strongest non-learned lighting-driven placement we build fast (quality.md §5).

    insertion_ranking(field, grid) -> (N,) int64 point indices, most important first

Coarse to fine, the mirror image of the reference's decimation: start from a "typical" tetrahedron
(below), interpolate every point from the current probes (the metric's own tetrahedral blending,
hull projection included), and insert the worst-interpolated point of each tetrahedron, the cells
with the largest summed error first (the mean error is a sum over points: a cell where many points
are somewhat wrong outranks one bad point), up to ceil(INSERTION_GROWTH x current count) points per
round; repeat until every point is a probe or exactly interpolated (the rest then follow by index). The insertion order is
the ranking: any budget is its prefix, and the tolerance policy searches its prefixes as for every
other ranking. One point per tetrahedron per round keeps a round's insertions spread out (each
fixes a different cell); a round costs one tetrahedralisation (derived from the last round's: insertion_tetrahedra.py)
and one point location, so the whole
ranking costs about log(N / 4) / log(1 + growth) of them (~60 rounds for 1,000 points, ~1 s).
Chosen on 8 crops of training levels (none held out; tolerance 0.05, budgets 5 and 20 %): ordering
cells by summed rather than largest error cut the probes needed for the tolerance by 0-21 % (median
6 %), and growth 0.1 instead of 0.25 a further 0-33 % at twice the time.

Typical tetrahedron. On nearly uniform lighting the few probes the reference keeps are not the
volume's corners (often darker or brighter than the rest) but points whose lighting is close to
the volume's median, so that blending them reproduces most points within the tolerance. The start
is therefore four points among the TYPICAL_FRACTION of points nearest the median lighting (the
metric's relative error to the per-value median), spread out: the one farthest from the centroid
of those candidates, then farthest-point sampling among them, completed to a non-flat
tetrahedron in that order (selection.ensure_tetrahedron). The ranking's start then adds the grid's extreme points
along the 8 diagonal directions (insertion_start: a first hull that spans the volume; quality.md §5.1 step 1).

Why it is the yardstick: it reads the dense lighting, as the reference does, but never evaluates a
removal or an insertion candidate by itself (no greedy search over candidates), so it is the "best
fast non-learned" bar a learned tier has to beat. Deterministic: ties go to the lower index.

Guided insertion (quality.md §5.2): the same rounds, but each cell's candidate is the point with the
largest error x guide weight instead of the largest error, where the guide weight is a per-point
prior of importance — the network's score through the spread ranking's weights (`spread_weights`,
sqrt(score / median)). The error still decides which cells are fixed first and whether a cell needs
a point at all; the prior only decides which of a cell's badly interpolated points becomes the probe.
Why: a per-point scorer cannot place probes by itself however good its scores (even the reference's
own ranking through the spread ranking is 1.42x the reference's error at a 5 % budget on the
validation crops), and insertion cannot tell a point the reference keeps from its equally wrong
neighbour; together they beat insertion alone on the validation crops (benchmarks.md "The network").
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ...core.grid import EvaluationGrid
from ...core.selection import TETRAHEDRON_POINTS, ensure_tetrahedron
from ...core.spread import farthest_point_ranking, spread_weights
from .insertion_kernel import TIE, first_per_cell, median_deviation  # TIE: defined beside its kernel, re-exported here
from .insertion_state import Placed, located_set, mean_error, with_inserted
from .insertion_tetrahedra import InsertionTetrahedra
from ..metric.metric import (PRIMARY_METRIC, MetricError, ReferenceField, checked_metric, error_floor, probe_stencil,
                             mean_placement_error, stencil_point_errors)
from ..metric.metric_kernel import IRRADIANCE, SMAPE, run_rows
from .pins import Pins, pinned_start
from ..metric.triangulation import Tetrahedralization, tetrahedralize

INSERTION_GROWTH = 0.1  # points inserted per round, as a fraction of the current probes (module text)
TYPICAL_FRACTION = 0.1  # candidates of the starting tetrahedron: this fraction nearest the median lighting
STARTING_SPREAD = 64  # of the candidates' farthest-point ranking, the head computed first (typical_tetrahedron)
EXACT = 1e-12  # per-point errors at or below this are exact interpolation (nothing to fix there)
# Guided insertion uses the network's scores only on volumes of at most this many points (quality.md §5.2: chosen on
# whole training and validation levels; larger clouds than the network ever saw make its guide worse than none).
GUIDED_POINT_LIMIT = 32_768
# Rounds whose located sets InsertionOrder keeps for the tolerance search's bisection (it narrows a bracket of two
# counts a factor 2 apart: ~7 rounds of growth 0.1); ~12 bytes a point each.
KEPT_ROUNDS = 8


def typical_tetrahedron(field: ReferenceField, grid: EvaluationGrid, metric: str = PRIMARY_METRIC) -> np.ndarray:
    """Four or more point indices (in choice order) near the median lighting, spread out (module text)."""
    values = field.values(checked_metric(metric))
    # Column by column: the same medians as np.median(values, axis=0), without its (N, 42) copy (2.2 -> 0.6 s at 10^6).
    median = np.array([np.median(values[:, c]) for c in range(values.shape[1])])
    deviation = median_deviations(values, median, field.scale, metric)
    n = field.point_count
    count = min(n, max(4, int(math.ceil(TYPICAL_FRACTION * n))))
    candidates = largest_first_head(-deviation, np.arange(n), count)  # nearest the median first, ties (within TIE) by index
    local = field.local[candidates]
    first = int(np.argmax(np.linalg.norm(local - local.mean(axis=0), axis=1)))
    # Only the ranking's head is read unless its first points are flat: rank STARTING_SPREAD of them, and all only
    # when the tetrahedron guarantee reaches past that head (the same start either way; 8 s less at 10^6 points).
    for limit in (STARTING_SPREAD, None):
        spread = candidates[farthest_point_ranking(local, np.ones(count), np.asarray([first]), limit)]
        rest = np.ones(n, dtype=bool)
        rest[spread] = False
        # flat candidates: any point; np.setdiff1d(np.arange(n), spread), without its hashing (1.1 s at 10^6 points)
        preference = np.concatenate([spread, np.flatnonzero(rest)])
        start = ensure_tetrahedron(grid, preference, spread[:4])[0]
        rank_of = np.empty(n, dtype=np.int64)
        rank_of[preference] = np.arange(n)
        if spread.shape[0] == count or rank_of[start].max() < spread.shape[0]:
            break
    return start[np.argsort(rank_of[start], kind="stable")]


def median_deviations(values: np.ndarray, median: np.ndarray, scale: float, metric: str) -> np.ndarray:
    """(N,) POINT_ERRORS[metric](median broadcast to every row, values, scale), bit for bit, without its (N, 42)
    temporaries (insertion_kernel.median_deviation: 2.5 -> 0.2 s at 10^6 points)."""
    floor = error_floor(metric, scale)
    deviation = np.empty(values.shape[0])
    run_rows(median_deviation, values.shape[0], np.ascontiguousarray(values, dtype=np.float64),
             np.ascontiguousarray(median, dtype=np.float64), floor, IRRADIANCE if metric == "irradiance" else SMAPE,
             deviation)
    return deviation


# The 8 directions (s_i, s_j, s_k), each sign -1 or +1, in this order, along which insertion_start adds the grid's
# extreme point (quality.md §5.1 step 1).
EXTREME_DIRECTIONS = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)], dtype=np.int64)


def extreme_points(grid: EvaluationGrid) -> np.ndarray:
    """(8,) point indices: per direction of EXTREME_DIRECTIONS the point of largest s_i*i + s_j*j + s_k*k over its lattice
    id (exact integers; ties: lower index), repeats included."""
    if grid.point_count == 0:
        return np.zeros(0, dtype=np.int64)
    return np.argmax(grid.ids.astype(np.int64) @ EXTREME_DIRECTIONS.T, axis=0).astype(np.int64)


def insertion_start(field: ReferenceField, grid: EvaluationGrid, metric: str = PRIMARY_METRIC) -> np.ndarray:
    """The insertion ranking's first points (quality.md §5.1 step 1): the typical tetrahedron, then the grid's extreme
    points along the 8 diagonal directions not already listed, first occurrence first.

    Why the extremes: the rounds then start from a hull that spans the volume, not from four points near its middle;
    with a small hull most points lie outside it and every round projects them all (at 10^6 points 0.5-1.1 M points a
    round, two thirds of insertion's time). Measured on whole validation levels (benchmarks.md "Scale: whole levels")."""
    start = typical_tetrahedron(field, grid, metric)
    extremes = extreme_points(grid)
    _, first = np.unique(extremes, return_index=True)
    extremes = extremes[np.sort(first)]
    return np.concatenate([start, extremes[~np.isin(extremes, start)]])


def guide_weights(scores: np.ndarray) -> np.ndarray:
    """A guided insertion's per-point weights from importance scores: the spread ranking's weights
    (selection.md: clip to [1e-6, 1], NaN -> 1e-6, sqrt(score / median)), all > 0."""
    return spread_weights(scores)


def guide_applies(point_count: int) -> bool:
    """Whether guided insertion uses the network's guide on a volume of `point_count` points (quality.md §5.2)."""
    return point_count <= GUIDED_POINT_LIMIT


def guide_of(scores: np.ndarray) -> np.ndarray | None:
    """The guide of guided insertion for one volume's scores: guide_weights(scores), or None (plain insertion) above
    GUIDED_POINT_LIMIT points (quality.md §5.2). The C# core's InsertionRanking.GuideOf."""
    return guide_weights(scores) if guide_applies(np.asarray(scores).shape[0]) else None


def checked_guide(guide: np.ndarray | None, point_count: int) -> np.ndarray | None:
    """None, or (N,) float64 weights, each finite and > 0 (an error names the first bad one)."""
    if guide is None:
        return None
    weights = np.asarray(guide, dtype=np.float64)
    if weights.shape != (point_count,):
        raise MetricError(f"guide weights must be one number per point ({point_count:,}), got shape {list(weights.shape)}")
    bad = np.flatnonzero(~(np.isfinite(weights) & (weights > 0.0)))
    if bad.shape[0]:
        raise MetricError(f"guide weight {int(bad[0])} = {float(weights[bad[0]])!r} must be a finite number > 0 "
                          f"({bad.shape[0]:,} such weights): build them with guide_weights(scores)")
    return weights


def insertion_batch(field: ReferenceField, order: np.ndarray, metric: str = PRIMARY_METRIC,
                    growth: float = INSERTION_GROWTH, guide: np.ndarray | None = None,
                    candidates: np.ndarray | None = None) -> np.ndarray:
    """One round given the probes so far (`order`): the next points to insert, in insertion order (module
    text); empty when every other point is interpolated exactly. `guide` (checked_guide): each cell's
    candidate is its point of largest error x weight among those with error > EXACT (guided insertion)
    instead of its point of largest error. `candidates` ((N,) bool, pins.Pins.candidates): only these points become
    probes (a cell whose badly interpolated points are all blocked gets none). The C# core's InsertionRanking.NextBatch."""
    guide = checked_guide(guide, field.point_count)
    indices, others, stencil = probe_stencil(field, order)
    errors = stencil_point_errors(field, indices, others, stencil, metric)[others]
    return batch_of(others, errors, stencil.cell, len(order), growth, guide, candidates)


def batch_of(others: np.ndarray, errors: np.ndarray, cell: np.ndarray, probe_count: int, growth: float,
             guide: np.ndarray | None, candidates: np.ndarray | None) -> np.ndarray:
    """insertion_batch's choice given the other points (ascending), their errors and stencil cells, from a set of
    `probe_count` probes (guide and candidates already checked)."""
    # Per cell the candidate first, ties (within TIE of the cell's largest key) by index. Unguided, the key is the error
    # itself; guided, points at or below EXACT never become candidates (key -1), so a cell needs a point exactly when it
    # does unguided.
    key = errors if guide is None else np.where(errors > EXACT, errors * guide[others], -1.0)
    if candidates is not None:  # pinned probes (pins.py): a point near a pin is never a cell's candidate
        key = np.where(candidates[others], key, -np.inf)
    cell_count = int(cell.max()) + 1
    first = first_per_cell(cell, np.ascontiguousarray(key), cell_count, TIE)  # others ascend: first = lowest index
    worst = first[errors[first] > EXACT]
    if candidates is not None:
        worst = worst[candidates[others[worst]]]
    if worst.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    cell_error = np.bincount(cell, errors, minlength=cell_count)
    worst = worst[largest_first(cell_error[cell[worst]], others[worst])]
    return others[worst[:max(1, int(math.ceil(growth * probe_count)))]]


def largest_first(values: np.ndarray, index: np.ndarray) -> np.ndarray:
    """Positions of `values`, largest first, where a value within TIE of the next larger one counts as equal to it: each
    run of such values goes by `index`, lowest first (quality.md §5.1; the C# core's InsertionRanking.LargestFirst)."""
    by_value, run = _runs(values)
    return by_value[np.lexsort((index[by_value], run))]


def _runs(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """largest_first's positions by value (largest first, stable) and each one's run (numbered from 0 by the gaps above
    TIE before it)."""
    by_value = np.argsort(-values, kind="stable")
    ordered = values[by_value]
    run = np.zeros(ordered.shape[0], dtype=np.int64)
    with np.errstate(invalid="ignore"):  # equal infinite values (refinement's stale costs) differ by NaN: one run
        run[1:] = np.cumsum(ordered[:-1] - ordered[1:] > TIE)
    return by_value, run


def largest_first_head(values: np.ndarray, index: np.ndarray, count: int) -> np.ndarray:
    """largest_first(values, index)[:count], sorting only the values near the head's (the typical tetrahedron reads the
    first 10 %: a full sort of 10^6 values cost 0.3 s). The head is its runs down to the one holding position count - 1,
    that run's lowest indices; the values >= the count-th largest - margin sort into the same runs (the others are all
    smaller), so they give the head whenever that run ends among them (a gap above TIE after it); else a wider margin."""
    n = values.shape[0]
    margin = 1e3 * TIE
    if 0 < count < n and np.all(np.isfinite(values)):  # non-finite values (a NaN sorts last): the full sort
        kth = np.partition(values, n - count)[n - count]  # the count-th largest
        while margin < 1e300:
            near = np.flatnonzero(values >= kth - margin)
            if near.shape[0] == n:
                break
            by_value, run = _runs(values[near])
            if run[-1] > run[count - 1]:  # the head's last run ends among the near values
                return near[by_value[np.lexsort((index[near][by_value], run))][:count]]
            margin *= 1e3
    return largest_first(values, index)[:count]


class InsertionOrder:
    """The insertion order, computed only as far as it is asked for: `prefix(K)` runs rounds until K points
    are ranked. A budget K or the tolerance policy's search (exponential from 4, then bisection: it never
    asks beyond twice its answer) thus costs the rounds up to that count, not the ~log(N / 4) / log(1 +
    growth) rounds of the whole ranking; prefixes are those of `insertion_ranking` exactly."""

    def __init__(self, field: ReferenceField, grid: EvaluationGrid, metric: str = PRIMARY_METRIC,
                 growth: float = INSERTION_GROWTH, progress: Callable[[int, int], None] | None = None,
                 guide: np.ndarray | None = None, pins: Pins | None = None, head: np.ndarray | None = None) -> None:
        """`pins` (pins.py): the order starts with the pins, then the usual start without the points near a pin, and
        no point near a pin is ever ranked (the order then holds fewer than N points). `head` (distinct point indices,
        e.g. the points a network expects the default to keep, likeliest first; no pins): ranked right after the start
        (those not already in it, in the given order), the rounds continuing from start + head
        (Tools~/experiments/network-seed.py)."""
        checked_metric(metric)
        if not (math.isfinite(growth) and growth > 0.0):
            raise MetricError(f"growth {growth!r} must be a fraction > 0 of the current probes "
                              f"(e.g. {INSERTION_GROWTH})")
        self._field, self._grid, self._metric, self._growth, self._progress = field, grid, metric, growth, progress
        self._guide = checked_guide(guide, field.point_count)
        self._order = insertion_start(field, grid, metric).astype(np.int64)
        self._candidates = None if pins is None else pins.candidates
        if pins is not None:
            self._order = pinned_start(grid, pins, self._order)
        if head is not None:
            self._order = with_head(self._order, head, field.point_count, pins)
        self._exhausted = False  # every remaining point is interpolated exactly: they follow by index
        # The last KEPT_ROUNDS rounds' probe sets (count ranked then, the set; insertion_state): the next round starts
        # from the last one, the tolerance search's mean_error from any of them.
        self._placed: list[tuple[int, Placed]] = []
        self.rounds = 0
        self.tetrahedra = InsertionTetrahedra()  # the rounds' and the search's tetrahedralisations, derived (§5.1 step 6)

    @property
    def point_count(self) -> int:
        return self._field.point_count

    @property
    def computed(self) -> int:
        """How many leading points are ranked so far."""
        return int(self._order.shape[0])

    def prefix(self, count: int) -> np.ndarray:
        """The first min(count, N) points of the ranking, in order."""
        n = self._field.point_count
        count = min(int(count), n)
        while self._order.shape[0] < count and not self._exhausted:
            # insertion_batch's round, located incrementally (insertion_state.py)
            if self._placed:
                done, placed = self._placed[-1]
                located = with_inserted(self._field, placed, self._order[done:], self._metric, self.tetrahedra)
            else:
                located = located_set(self._field, self._order, self._metric)
            self._placed = (self._placed + [(self._order.shape[0], located.placed())])[-KEPT_ROUNDS:]
            batch = batch_of(located.others, located.errors, located.stencil.cell, self._order.shape[0],
                             self._growth, self._guide, self._candidates)
            self.rounds += 1
            if batch.shape[0] == 0:
                self._exhausted = True
            else:
                self._order = np.concatenate([self._order, batch])
            if self._progress is not None:  # points ranked so far, of the count asked for
                self._progress(min(self._order.shape[0], count), count)
        if self._order.shape[0] < count:  # exhausted: the rest by index
            chosen = np.zeros(n, dtype=bool)
            chosen[self._order] = True
            if self._candidates is not None:  # pinned: the points near a pin are never ranked
                chosen |= ~self._candidates
            self._order = np.concatenate([self._order, np.flatnonzero(~chosen)])
        return self._order[:count]

    def mean_error(self, count: int, probes: np.ndarray) -> float:
        """metric.mean_placement_error(field, probes) for `probes` = selection()(count), located from the last kept round
        at or below `count` (insertion_state.with_inserted: a fresh location's stencils), else from scratch."""
        rounds = [(done, placed) for done, placed in self._placed if done <= count]
        ordered = np.sort(probes)
        if not rounds or count > self._order.shape[0] or not np.array_equal(ordered, np.sort(self._order[:count])):
            return mean_placement_error(self._field, ordered, self._metric)
        done, placed = rounds[-1]
        return mean_error(self._field, with_inserted(self._field, placed, self._order[done:count], self._metric,
                                                     self.tetrahedra))

    def mesh_of(self, probes: np.ndarray) -> Tetrahedralization:
        """The tetrahedralisation of the sorted point indices `probes` (e.g. a selection's seed), its vertex i probes[i]:
        derived from the last kept round whose probes they all hold (InsertionTetrahedra.of_superset), else Qhull's."""
        probes = np.asarray(probes, dtype=np.int64)
        if np.any(probes[1:] <= probes[:-1]):
            raise ValueError("mesh_of needs sorted, distinct point indices (a selection's)")
        held = np.zeros(self._field.point_count, dtype=bool)
        held[probes] = True
        for _, placed in reversed(self._placed):
            if held[placed.probes].all():
                return self.tetrahedra.of_superset(self._field, placed.mesh, placed.probes, probes)
        return tetrahedralize(self._field.world[probes], self._field.frame, probes)

    def selection(self) -> Callable[[int], np.ndarray]:
        """K -> the first K points completed to a tetrahedron (sorted), as policies.prefix_selection(grid,
        insertion_ranking(...)) gives them, without the rest of the ranking."""
        def select(count: int) -> np.ndarray:
            # The tetrahedron guarantee as prefix_selection applies it, over the ranked points then the others by
            # index: the start is ranked and never flat, so every point it adds is one the whole ranking would add
            # (a start of 5 points, its first 4 in one plane, needs the fifth at count 4).
            prefix = self.prefix(max(int(count), TETRAHEDRON_POINTS))
            ranked = np.zeros(self.point_count, dtype=bool)
            ranked[prefix] = True
            provisional = np.concatenate([prefix, np.flatnonzero(~ranked)])
            return ensure_tetrahedron(self._grid, provisional, prefix[:max(int(count), 1)])[0]

        return select


def with_head(start: np.ndarray, head: np.ndarray, point_count: int, pins: Pins | None) -> np.ndarray:
    """InsertionOrder's first points given a `head`: the start, then the head's points not in it, in the head's order."""
    if pins is not None:
        raise MetricError("an insertion order with a head takes no pins (the head would have to avoid their neighbours)")
    points = np.asarray(head, dtype=np.int64).reshape(-1)
    if points.shape[0] and (points.min() < 0 or points.max() >= point_count):
        raise MetricError(f"head point indices must lie in [0, {point_count:,}), got {int(points.min())}..{int(points.max())}")
    if np.unique(points).shape[0] != points.shape[0]:
        raise MetricError("head point indices must be distinct")
    return np.concatenate([start, points[~np.isin(points, start)]])


def insertion_ranking(field: ReferenceField, grid: EvaluationGrid, metric: str = PRIMARY_METRIC,
                      growth: float = INSERTION_GROWTH, guide: np.ndarray | None = None) -> np.ndarray:
    """The insertion order of the module text (guided by `guide`, checked_guide, when given): (N,) int64, every
    point once."""
    return InsertionOrder(field, grid, metric, growth, guide=guide).prefix(field.point_count)
