"""The in-use rule (Documentation~/in-use.md): the evaluation points where dynamic objects go.

`all` keeps every point; `band` the points within the band height above a walkable floor; `reachable` the band
points a character walks to from seeds (spawns, items). Mirrors the C# core (Lpnn.Probes.Core.InUse); both are pinned
to Tests/Data/in_use_golden.json.

Vectorised for 10^6 points: every kind of ray (floor rays, seed-attachment segments, floor-profile samples, move
segments) is cast in a few large batches, and the walk is a breadth-first search over an index array of moves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInputError
from .features import Raycaster
from .grid import ID_BOUND, EvaluationGrid
from .in_use_defaults import BAND_HEIGHT, RULES, SLOPE_LIMIT_DEGREES, STEP_HEIGHT
from .segments import RAYS_PER_CAST, Progress, cast_in_batches, segments_free

SEED_REACH_CELLS = 2.0  # a seed attaches to in-band points within 2h
PROFILE_INTERVAL = 0.25  # metres per floor-profile interval: M = ceil(h / 0.25) ...
MAX_PROFILE_INTERVALS = 64  # ... at most 64 (and at least 1)
BAND_HEIGHT_MAX = 1e4
STEP_HEIGHT_MAX = 1e4
SLOPE_LIMIT_MAX = 90.0
DOWN = np.array([0.0, -1.0, 0.0])


class InUseError(InvalidInputError):
    """The in-use rule cannot be applied as asked; the message names the bad value and the fix."""


def _parameter(name: str, value: float, low: float, high: float, low_open: bool, high_open: bool,
               unit: str, default: float) -> float:
    left, right = "(" if low_open else "[", ")" if high_open else "]"
    valid = f"a finite number in {left}{low:g}, {high:g}{right} {unit} (default {default:g})"
    try:
        number = float(value)
    except (TypeError, ValueError) as exc:
        raise InUseError(f"in-use {name} {value!r} is not a number; use {valid}") from exc
    inside = math.isfinite(number) and (number > low if low_open else number >= low) and \
        (number < high if high_open else number <= high)
    if not inside:
        raise InUseError(f"in-use {name} {value!r} is out of range; use {valid}")
    return number


@dataclass(frozen=True)
class InUseParameters:
    """H, theta and s of in-use.md "Parameters" (metres and degrees)."""

    band_height: float = BAND_HEIGHT
    slope_limit_degrees: float = SLOPE_LIMIT_DEGREES
    step_height: float = STEP_HEIGHT

    def __post_init__(self) -> None:
        object.__setattr__(self, "band_height", _parameter("band_height", self.band_height, 0.0, BAND_HEIGHT_MAX,
                                                           True, False, "metres", BAND_HEIGHT))
        object.__setattr__(self, "slope_limit_degrees", _parameter(
            "slope_limit_degrees", self.slope_limit_degrees, 0.0, SLOPE_LIMIT_MAX, False, True, "degrees", SLOPE_LIMIT_DEGREES))
        object.__setattr__(self, "step_height", _parameter("step_height", self.step_height, 0.0, STEP_HEIGHT_MAX,
                                                           False, False, "metres", STEP_HEIGHT))

    @property
    def walkable_cosine(self) -> float:
        """cos theta: a floor is walkable when |n_y| >= this (math.radians: degrees * (pi / 180), as the C# core)."""
        return math.cos(math.radians(self.slope_limit_degrees))

    def rise_limit(self, cell_size: float) -> float:
        """s + (h/M) tan theta: the largest rise over one floor-profile interval of a horizontal move."""
        return self.step_height + cell_size / profile_intervals(cell_size) * math.tan(math.radians(self.slope_limit_degrees))


def profile_intervals(cell_size: float) -> int:
    """M = min(64, max(1, ceil(h / 0.25))): the floor-profile intervals of a horizontal move."""
    return min(MAX_PROFILE_INTERVALS, max(1, math.ceil(cell_size / PROFILE_INTERVAL)))


# -------------------------------------------------------------------------------------------------- rays

def _floor_heights(origins: np.ndarray, raycaster: Raycaster, parameters: InUseParameters, stage: str,
                   progress: Progress | None) -> np.ndarray:
    """f = y - d of each origin's floor ray (straight down, at most H) where it hits a walkable surface, else NaN."""
    directions = np.broadcast_to(DOWN, origins.shape)
    distances, normals = cast_in_batches(raycaster, origins, directions, parameters.band_height, stage, progress)
    length = np.sqrt(np.sum(normals * normals, axis=1))
    # The raycaster's normals are unit by contract; dividing keeps a slightly unnormalised mesh normal honest.
    up = np.abs(normals[:, 1]) / np.where(length > 0.0, length, 1.0)
    walkable = (distances <= parameters.band_height) & (length > 0.0) & (up >= parameters.walkable_cosine)
    return np.where(walkable, origins[:, 1] - np.where(walkable, distances, 0.0), np.nan)


# ---------------------------------------------------------------------------------------------- the band

def _positions(grid: EvaluationGrid) -> np.ndarray:
    return grid.positions.astype(np.float64)  # the float32 grid positions, compared in double


def _band(grid: EvaluationGrid, raycaster: Raycaster, parameters: InUseParameters,
          progress: Progress | None) -> tuple[np.ndarray, np.ndarray]:
    floor = _floor_heights(_positions(grid), raycaster, parameters, "in use: floor rays", progress)
    return np.isfinite(floor), floor


def in_band(grid: EvaluationGrid, raycaster: Raycaster,
            parameters: InUseParameters) -> tuple[np.ndarray, np.ndarray]:
    """(N,) bool: within H above a walkable surface; (N,) float64 floor height f(p) (NaN where not in band)."""
    return _band(grid, raycaster, parameters, None)


# ------------------------------------------------------------------------------------------------ seeds

def _checked_seeds(seeds: np.ndarray | None) -> np.ndarray:
    if seeds is None:
        raise InUseError("the 'reachable' rule needs seeds (none given): add seeds (spawn points, items, the "
                         "volume's seed transforms), or use the rule 'band'")
    values = np.asarray(seeds, dtype=np.float64)
    if values.ndim == 1 and values.shape[0] == 3:
        values = values[None, :]
    if values.ndim != 2 or values.shape[1] != 3:
        raise InUseError(f"seeds need shape (S, 3) (x, y, z in metres), got {list(values.shape)}")
    if values.shape[0] == 0:
        raise InUseError("the 'reachable' rule needs at least one seed (0 given): add seeds (spawn points, items, "
                         "the volume's seed transforms), or use the rule 'band'")
    bad = np.flatnonzero(~np.all(np.isfinite(values), axis=1))
    if bad.shape[0]:
        x, y, z = (float(v) for v in values[bad[0]])
        raise InUseError(f"seed {int(bad[0])} is ({x}, {y}, {z}), not finite ({bad.shape[0]} of {values.shape[0]} "
                         "seeds are not): give every seed a finite position")
    return values


def _seed_starts(grid: EvaluationGrid, raycaster: Raycaster, band: np.ndarray, seeds: np.ndarray,
                 progress: Progress | None) -> np.ndarray:
    """Indices of the in-band points some seed attaches to: |q - s| <= 2h and the segment from s to q free."""
    h = grid.cell_size
    reach = SEED_REACH_CELLS * h
    # Candidate ids: the lattice box around each seed, one id wider than 2h on each side (the exact test follows).
    low = np.floor((seeds - reach) / h) - 1.0
    high = np.ceil((seeds + reach) / h) + 1.0
    inside = np.all((low >= -ID_BOUND) & (high <= ID_BOUND), axis=1)  # a seed beyond the lattice attaches to nothing
    span = int(2.0 * SEED_REACH_CELLS) + 4
    offsets = np.stack(np.meshgrid(*(np.arange(span),) * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    seed_rows = np.repeat(np.flatnonzero(inside), offsets.shape[0])
    ids = (low[inside].astype(np.int64)[:, None, :] + offsets[None, :, :]).reshape(-1, 3)
    points = grid.index_of(ids)
    known = points >= 0
    seed_rows, points = seed_rows[known], points[known]
    keep = band[points]
    seed_rows, points = seed_rows[keep], points[keep]
    origins = seeds[seed_rows]
    targets = _positions(grid)[points]
    offset = targets - origins
    close = np.sqrt(np.sum(offset * offset, axis=1)) <= reach
    origins, targets, points = origins[close], targets[close], points[close]
    free = segments_free(raycaster, origins, targets, "in use: seed attachment rays", progress)
    return np.unique(points[free])


# ------------------------------------------------------------------------------------------------ moves

def _vertical_moves(grid: EvaluationGrid, raycaster: Raycaster, band: np.ndarray,
                    progress: Progress | None) -> tuple[np.ndarray, np.ndarray]:
    """Directed moves (sources, targets) between in-band vertical neighbours whose segment is free."""
    lower = np.flatnonzero(band)
    upper = grid.neighbour(1, 1)[lower]
    both = upper >= 0
    lower, upper = lower[both], upper[both]
    both = band[upper]
    lower, upper = lower[both], upper[both]
    sources, targets, free = _both_ways(grid, raycaster, lower, upper, "in use: vertical move rays", progress)
    return sources[free], targets[free]


def _both_ways(grid: EvaluationGrid, raycaster: Raycaster, first: np.ndarray, second: np.ndarray, stage: str,
               progress: Progress | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The moves first -> second then second -> first (sources, targets) and whether each one's own segment, cast
    from its source, is free."""
    positions = _positions(grid)
    sources = np.concatenate([first, second])
    targets = np.concatenate([second, first])
    return sources, targets, segments_free(raycaster, positions[sources], positions[targets], stage, progress)


def _horizontal_moves(grid: EvaluationGrid, raycaster: Raycaster, parameters: InUseParameters, band: np.ndarray,
                      floor: np.ndarray, progress: Progress | None) -> tuple[np.ndarray, np.ndarray]:
    """Directed moves between in-band x and z neighbours: segment free and the floor profile walkable that way.

    Each pair's profile is sampled once, from the point with the lower id toward the higher (x_i = p + (i/M)(q - p)),
    and read forwards for p -> q and backwards for q -> p."""
    h = grid.cell_size
    intervals = profile_intervals(h)
    rise_limit = parameters.rise_limit(h)
    positions = _positions(grid)
    in_band_points = np.flatnonzero(band)
    pairs = []
    for axis in (0, 2):
        higher = grid.neighbour(axis, 1)[in_band_points]
        both = higher >= 0
        first, second = in_band_points[both], higher[both]
        both = band[second]
        pairs.append((first[both], second[both]))
    first = np.concatenate([p for p, _ in pairs])
    second = np.concatenate([q for _, q in pairs])
    profile = np.empty((first.shape[0], intervals + 1), dtype=np.float64)
    profile[:, 0], profile[:, intervals] = floor[first], floor[second]
    if intervals > 1:
        _sample_profiles(positions[first], positions[second], raycaster, parameters, profile, progress)
    rises = np.diff(profile, axis=1)  # NaN where an interior sample has no walkable floor: every test below fails
    forward = np.all(rises <= rise_limit, axis=1)
    backward = np.all(-rises <= rise_limit, axis=1)
    walkable = forward | backward
    first, second, forward, backward = first[walkable], second[walkable], forward[walkable], backward[walkable]
    sources, targets, free = _both_ways(grid, raycaster, first, second, "in use: horizontal move rays", progress)
    allowed = free & np.concatenate([forward, backward])
    return sources[allowed], targets[allowed]


def _sample_profiles(starts: np.ndarray, ends: np.ndarray, raycaster: Raycaster, parameters: InUseParameters,
                     profile: np.ndarray, progress: Progress | None) -> None:
    """Fills profile[:, 1:M] with the floor heights of the interior samples x_i = p + (i/M)(q - p), in batches of
    pairs so that at most RAYS_PER_CAST samples are held at once (M - 1 of them per pair)."""
    intervals = profile.shape[1] - 1
    fractions = np.arange(1, intervals, dtype=np.float64) / intervals
    pairs_per_batch = max(1, RAYS_PER_CAST // (intervals - 1))
    total = starts.shape[0] * (intervals - 1)
    stage = "in use: floor profile rays"
    for first in range(0, starts.shape[0], pairs_per_batch):
        last = min(first + pairs_per_batch, starts.shape[0])
        start, step = starts[first:last], ends[first:last] - starts[first:last]
        samples = (start[:, None, :] + fractions[None, :, None] * step[:, None, :]).reshape(-1, 3)
        heights = _floor_heights(samples, raycaster, parameters, stage, None)
        profile[first:last, 1:intervals] = heights.reshape(last - first, intervals - 1)
        if progress is not None:
            progress(stage, last * (intervals - 1), total)


# ------------------------------------------------------------------------------------------------- walk

def _walk(point_count: int, starts: np.ndarray, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """(N,) bool: the points the directed moves reach from the starts (breadth-first, level by level)."""
    order = np.argsort(sources, kind="stable")
    targets = targets[order]
    offsets = np.zeros(point_count + 1, dtype=np.int64)
    np.cumsum(np.bincount(sources, minlength=point_count), out=offsets[1:])
    reached = np.zeros(point_count, dtype=bool)
    reached[starts] = True
    frontier = np.asarray(starts, dtype=np.int64)
    while frontier.shape[0]:
        begin = offsets[frontier]
        counts = offsets[frontier + 1] - begin
        total = int(counts.sum())
        if total == 0:
            break
        # Every move out of the frontier: each frontier point's run of targets, laid end to end.
        run_start = np.repeat(begin - (np.cumsum(counts) - counts), counts)
        following = targets[run_start + np.arange(total, dtype=np.int64)]
        following = np.unique(following[~reached[following]])
        reached[following] = True
        frontier = following
    return reached


def _no_point_in_use(rule: str, grid: EvaluationGrid, parameters: InUseParameters) -> InUseError:
    return InUseError(
        f"the in-use rule '{rule}' leaves no point in use among the grid's {grid.point_count:,} points (band height "
        f"{parameters.band_height:g} m, cell size {grid.cell_size:g} m): no point lies within the band height above a "
        "walkable floor; use the rule 'all', or a band height larger than the cell size and the points' height above "
        "the floor")


def _reachable(grid: EvaluationGrid, raycaster: Raycaster, parameters: InUseParameters, seeds: np.ndarray,
               band: tuple[np.ndarray, np.ndarray] | None, progress: Progress | None) -> np.ndarray:
    values = _checked_seeds(seeds)
    in_band_mask, floor = _band(grid, raycaster, parameters, progress) if band is None else band
    in_band_mask = np.asarray(in_band_mask, dtype=bool)
    floor = np.asarray(floor, dtype=np.float64)
    if in_band_mask.shape != (grid.point_count,) or floor.shape != (grid.point_count,):
        raise InUseError(f"band needs (N,) in-band flags and floor heights for the grid's {grid.point_count:,} points, "
                         f"got {list(in_band_mask.shape)} and {list(floor.shape)}: pass what in_band returns")
    if not in_band_mask.any():
        raise _no_point_in_use("reachable", grid, parameters)
    starts = _seed_starts(grid, raycaster, in_band_mask, values, progress)
    if starts.shape[0] == 0:
        reach = SEED_REACH_CELLS * grid.cell_size
        raise InUseError(
            f"none of the {values.shape[0]:,} seeds attaches to an in-band point (one within {reach:g} m, 2 cells, "
            f"with nothing in between; {int(in_band_mask.sum()):,} of {grid.point_count:,} points are in band): move the "
            "seeds into the volume near walkable floors, add seeds, or use the rule 'band'")
    vertical = _vertical_moves(grid, raycaster, in_band_mask, progress)
    horizontal = _horizontal_moves(grid, raycaster, parameters, in_band_mask, floor, progress)
    sources = np.concatenate([vertical[0], horizontal[0]])
    targets = np.concatenate([vertical[1], horizontal[1]])
    return _walk(grid.point_count, starts, sources, targets)


def reachable(grid: EvaluationGrid, raycaster: Raycaster, parameters: InUseParameters, seeds: np.ndarray,
              band: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """(N,) bool: the in-band points the moves reach from the seeds' start points.

    seeds (S, 3) metres; band: what in_band returned, to skip casting the floor rays again."""
    return _reachable(grid, raycaster, parameters, seeds, band, None)


def in_use_mask(rule: str, grid: EvaluationGrid, raycaster: Raycaster, parameters: InUseParameters,
                seeds: np.ndarray | None = None, progress: Progress | None = None) -> np.ndarray:
    """(N,) bool: the points in use by `rule` (one of RULES); an error when none is.

    progress(stage, done, total), if given, is called after every batch of rays."""
    if rule not in RULES:
        raise InUseError(f"in-use rule {rule!r} is not one of {', '.join(RULES)}")
    if rule == "all":
        return np.ones(grid.point_count, dtype=bool)
    if rule == "band":
        mask, _ = _band(grid, raycaster, parameters, progress)
    else:
        mask = _reachable(grid, raycaster, parameters, seeds, None, progress)
    if not mask.any():
        raise _no_point_in_use(rule, grid, parameters)
    return mask
