"""Rays in bounded batches, and whether straight segments cross geometry (Documentation~/in-use.md "Definitions" 2;
leaks.md uses the same test). Shared by the in-use rule and the leak check.

A segment from a to b is free when a ray from a along (b - a)/|b - a| meets no surface of either facing within
|b - a|; a zero-length segment is free. The raycaster protocol takes one maximum distance per call, so every segment
is cast up to the longest one and a hit counts only when it is within its own segment's length: the same first hit
a ray limited to that length finds.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .features import Raycaster, _checked_hits

RAYS_PER_CAST = 1 << 20  # a batch: 10^6 floor rays go in one call; origins + directions + normals ~ 72 MB
Progress = Callable[[str, int, int], None]  # (stage, rays done, rays of the stage), as the C# ProgressCallback


def cast_in_batches(raycaster: Raycaster, origins: np.ndarray, directions: np.ndarray, max_distance: float,
                    stage: str = "rays", progress: Progress | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Distances (R,) and normals (R, 3) of rays cast in batches of RAYS_PER_CAST, reporting each batch."""
    count = origins.shape[0]
    distances = np.empty(count, dtype=np.float64)
    normals = np.empty((count, 3), dtype=np.float64)
    for start in range(0, count, RAYS_PER_CAST):
        stop = min(start + RAYS_PER_CAST, count)
        d, n = raycaster.cast(np.ascontiguousarray(origins[start:stop]), np.ascontiguousarray(directions[start:stop]),
                              max_distance)
        distances[start:stop], normals[start:stop] = _checked_hits(d, n, stop - start)
        if progress is not None:
            progress(stage, stop, count)
    return distances, normals


def segments_free(raycaster: Raycaster, starts: np.ndarray, ends: np.ndarray, stage: str = "segments",
                  progress: Progress | None = None) -> np.ndarray:
    """(S,) bool for segments starts (S, 3) -> ends (S, 3)."""
    a = np.asarray(starts, dtype=np.float64).reshape(-1, 3)
    b = np.asarray(ends, dtype=np.float64).reshape(-1, 3)
    if a.shape != b.shape:
        raise ValueError(f"segment starts {list(a.shape)} and ends {list(b.shape)} differ in shape")
    offsets = b - a
    lengths = np.sqrt(np.sum(offsets * offsets, axis=1))
    free = np.ones(a.shape[0], dtype=bool)
    cast = np.flatnonzero(lengths > 0.0)  # zero length: nothing to cross (and no direction to cast along)
    if cast.shape[0] == 0:
        return free
    directions = offsets[cast] / lengths[cast, None]
    distances, _ = cast_in_batches(raycaster, a[cast], directions, float(lengths[cast].max()), stage, progress)
    free[cast] = ~(distances <= lengths[cast])
    return free
