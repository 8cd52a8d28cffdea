"""What an error-driven reference placement returns: a removal order, an ordering and an error curve.

Both references remove probes one at a time from the full candidate set. Reversing the removal
order (after the survivors) gives an importance ordering in which every prefix is exactly the set
the decimation held at that count, so any budget is a prefix, and the error curve states that
prefix's error without re-evaluating it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MINIMUM_PROBES = 4  # Unity needs a tetrahedron
TIE_DECIMALS = 9  # error sums closer than 1e-9 (sum of per-point relative errors) are ties


def tie_key(error_sum: float) -> float:
    """Round an error sum so that rounding noise cannot decide between equal choices (then: lower index)."""
    return round(float(error_sum), TIE_DECIMALS) if np.isfinite(error_sum) else float("inf")


@dataclass(frozen=True)
class Decimation:
    method: str  # "fast-greedy" or "faithful-greedy"
    metric: str
    removed: np.ndarray  # (R,) int64 point indices in removal order
    error_curve: np.ndarray  # (N+1,) float64: mean error with n probes kept; NaN where never reached
    stop_reason: str
    seconds: float

    @property
    def point_count(self) -> int:
        return int(self.error_curve.shape[0] - 1)

    @property
    def survivors(self) -> np.ndarray:
        kept = np.ones(self.point_count, dtype=bool)
        kept[self.removed] = False
        return np.flatnonzero(kept)

    @property
    def ordering(self) -> np.ndarray:
        """(N,) int64, most important first: the survivors (by index), then the removals, last removed first."""
        return np.concatenate([self.survivors, self.removed[::-1]]).astype(np.int64)

    def prefix(self, count: int) -> np.ndarray:
        """The set the decimation held at `count` probes, sorted by index."""
        smallest = self.point_count - self.removed.shape[0]
        if not smallest <= count <= self.point_count:
            raise ValueError(f"the decimation went from {self.point_count:,} down to {smallest:,} probes; "
                             f"{count:,} is outside that range")
        return np.sort(self.ordering[:count])

    def smallest_count_within(self, tolerance: float) -> int:
        """Smallest count whose error is <= tolerance: exact over all prefixes the decimation visited."""
        reached = np.flatnonzero(np.isfinite(self.error_curve) & (self.error_curve <= tolerance))
        return int(reached[0]) if reached.shape[0] else self.point_count


def error_curve_from(removal_errors: list[float], point_count: int) -> np.ndarray:
    """curve[N] = 0 (all probes), curve[N - r] = mean error after the r-th removal."""
    curve = np.full(point_count + 1, np.nan)
    curve[point_count] = 0.0
    if removal_errors:
        curve[point_count - len(removal_errors):point_count] = np.asarray(removal_errors[::-1])
    return curve
