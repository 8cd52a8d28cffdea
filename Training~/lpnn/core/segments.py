"""Whether straight segments cross geometry (Documentation~/in-use.md "Definitions" 2; leaks.md uses the same test).

A segment from a to b is free when a ray from a along (b - a)/|b - a| meets no surface of either facing within
|b - a|; a zero-length segment is free. The raycaster protocol takes one maximum distance per call, so every segment
is cast up to the longest one and a hit counts only when it is not beyond its own segment's end.
"""

from __future__ import annotations

import numpy as np

from .features import Raycaster


def segments_free(raycaster: Raycaster, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """(S,) bool for segments starts (S, 3) -> ends (S, 3), in one batched cast."""
    a = np.asarray(starts, dtype=np.float64).reshape(-1, 3)
    b = np.asarray(ends, dtype=np.float64).reshape(-1, 3)
    if a.shape != b.shape:
        raise ValueError(f"segment starts {list(a.shape)} and ends {list(b.shape)} differ in shape")
    offsets = b - a
    lengths = np.linalg.norm(offsets, axis=1)
    free = np.ones(a.shape[0], dtype=bool)
    cast = np.flatnonzero(lengths > 0.0)  # zero length: nothing to cross (and no direction to cast along)
    if cast.shape[0] == 0:
        return free
    directions = offsets[cast] / lengths[cast, None]
    distances, _ = raycaster.cast(a[cast], directions, float(lengths[cast].max()))
    free[cast] = distances > lengths[cast]
    return free
