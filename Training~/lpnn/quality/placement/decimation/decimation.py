"""What an error-driven reference placement returns: a removal order, an ordering and an error curve.

Both references remove probes one at a time from a starting set: all candidates (the reference
placement) or a given initial set (seeded refinement, quality.md §4). Reversing the removal order
(after the survivors) gives an importance ordering in which every prefix up to the starting count is
exactly a set the decimation held, so any such budget is a prefix, and the error curve states that
prefix's error without re-evaluating it. Points never in the initial set come last, by index.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MINIMUM_PROBES = 4  # Unity needs a tetrahedron
TIE_DECIMALS = 9  # error sums closer than 1e-9 (sum of per-point relative errors) are ties


def tie_key(error_sum: float) -> float:
    """Round an error sum so that rounding noise cannot decide between equal choices (then: lower index)."""
    return round(float(error_sum), TIE_DECIMALS) if np.isfinite(error_sum) else float("inf")


def initial_mask(initial: np.ndarray | None, point_count: int) -> np.ndarray | None:
    """The starting set as a boolean mask (N,), from a mask or an index array; None = every point."""
    if initial is None:
        return None
    given = np.asarray(initial)
    if given.dtype == bool:
        if given.shape != (point_count,):
            raise ValueError(f"an initial mask must have shape ({point_count},) (one flag per point), "
                             f"got {list(given.shape)}")
        mask = given.copy()
    else:
        if given.ndim != 1 or not (np.issubdtype(given.dtype, np.integer) or given.shape[0] == 0):
            raise ValueError(f"initial must be a boolean mask or a 1-D array of point indices, "
                             f"got {given.dtype} {list(given.shape)}")
        indices = given.astype(np.int64)
        bad = indices[(indices < 0) | (indices >= point_count)]
        if bad.shape[0]:
            raise ValueError(f"initial point index {int(bad[0])} is outside the {point_count:,} points")
        mask = np.zeros(point_count, dtype=bool)
        mask[indices] = True
        if np.count_nonzero(mask) != indices.shape[0]:
            unique, counts = np.unique(indices, return_counts=True)
            raise ValueError(f"initial point index {int(unique[np.argmax(counts > 1)])} is listed more than once")
    if np.count_nonzero(mask) < MINIMUM_PROBES:
        raise ValueError(f"the initial set has {np.count_nonzero(mask)} point(s); a decimation starts from at least "
                         f"{MINIMUM_PROBES} (Unity needs a tetrahedron)")
    return mask


@dataclass(frozen=True)
class Decimation:
    method: str  # "fast-greedy" or "faithful-greedy"
    metric: str
    removed: np.ndarray  # (R,) int64 point indices in removal order
    error_curve: np.ndarray  # (N+1,) float64: mean error with n probes kept; NaN where never reached
    stop_reason: str
    seconds: float
    initial: np.ndarray | None = None  # (N,) bool starting set; None = every point
    leak_weight: float | None = None  # the curve's errors are leak-weighted so (reference_fast.py); None: plain

    @property
    def point_count(self) -> int:
        return int(self.error_curve.shape[0] - 1)

    @property
    def start_count(self) -> int:
        """Probes the decimation started from (N unless seeded)."""
        return self.point_count if self.initial is None else int(np.count_nonzero(self.initial))

    @property
    def smallest_count(self) -> int:
        """Probes left when it stopped."""
        return self.start_count - int(self.removed.shape[0])

    @property
    def survivors(self) -> np.ndarray:
        kept = np.ones(self.point_count, dtype=bool) if self.initial is None else self.initial.copy()
        kept[self.removed] = False
        return np.flatnonzero(kept)

    @property
    def ordering(self) -> np.ndarray:
        """(N,) int64, most important first: the survivors (by index), then the removals, last removed
        first, then the points never in the initial set (by index)."""
        outside = np.zeros(0, dtype=np.int64) if self.initial is None else np.flatnonzero(~self.initial)
        return np.concatenate([self.survivors, self.removed[::-1], outside]).astype(np.int64)

    def prefix(self, count: int) -> np.ndarray:
        """The set the decimation held at `count` probes, sorted by index."""
        if not self.smallest_count <= count <= self.start_count:
            raise ValueError(f"the decimation went from {self.start_count:,} down to {self.smallest_count:,} probes; "
                             f"{count:,} is outside that range")
        return np.sort(self.ordering[:count])

    def smallest_count_within(self, tolerance: float) -> int | None:
        """Smallest count whose error is <= tolerance, exact over all sets the decimation held; None
        when none was (only possible when seeded: the full set has error 0)."""
        reached = np.flatnonzero(np.isfinite(self.error_curve) & (self.error_curve <= tolerance))
        return int(reached[0]) if reached.shape[0] else None


def error_curve_from(removal_errors: list[float], point_count: int, start_count: int | None = None,
                     start_error: float = 0.0) -> np.ndarray:
    """curve[start] = the starting set's mean error (0 for all N points), curve[start - r] = mean error
    after the r-th removal, NaN elsewhere."""
    start = point_count if start_count is None else int(start_count)
    curve = np.full(point_count + 1, np.nan)
    curve[start] = start_error
    if removal_errors:
        curve[start - len(removal_errors):start] = np.asarray(removal_errors[::-1])
    return curve
