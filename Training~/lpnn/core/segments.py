"""Rays in bounded batches, and whether straight segments cross geometry (Documentation~/in-use.md "Definitions" 2;
leaks.md uses the same test). Shared by the in-use rule and the leak check.

A segment from a to b is free when a ray from a along (b - a)/|b - a| meets no surface of either facing within
|b - a|; a zero-length segment is free. A raycaster that can end each ray at its own distance (`first_hit_distances`,
the Embree one) casts every segment to its own length. The plain protocol takes one maximum distance per call: every
segment is then cast up to the longest one and a hit counts only when it is within its own segment's length. The two
agree except for a ray that grazes a triangle in its own plane, which Embree decides by the ray's end (measured on
ctf_compromise's leak checks: 4 of 4.2 million segments); with its own end a segment's answer depends on that segment
alone, not on the longest one it was cast beside (and the rays stop where they must: the leak-aware default's segment
tests on ctf_compromise, 4.2 million segments, take 0.86 s instead of 1.32 s).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .features import Raycaster, _checked_distances, _checked_hits
from .segments_kernel import unit_segments

RAYS_PER_CAST = 1 << 20  # a batch: 10^6 floor rays go in one call; origins + directions + normals ~ 72 MB
Progress = Callable[[str, int, int], None]  # (stage, rays done, rays of the stage), as the C# ProgressCallback


def _in_batches(count: int, cast: Callable[[int, int], None], stage: str, progress: Progress | None) -> None:
    """cast(start, stop) over [0, count) in batches of RAYS_PER_CAST, reporting each batch."""
    for start in range(0, count, RAYS_PER_CAST):
        stop = min(start + RAYS_PER_CAST, count)
        cast(start, stop)
        if progress is not None:
            progress(stage, stop, count)


def cast_in_batches(raycaster: Raycaster, origins: np.ndarray, directions: np.ndarray, max_distance: float,
                    stage: str = "rays", progress: Progress | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Distances (R,) and normals (R, 3) of rays cast in batches of RAYS_PER_CAST, reporting each batch."""
    count = origins.shape[0]
    distances = np.empty(count, dtype=np.float64)
    normals = np.empty((count, 3), dtype=np.float64)

    def cast(start: int, stop: int) -> None:
        d, n = raycaster.cast(np.ascontiguousarray(origins[start:stop]), np.ascontiguousarray(directions[start:stop]),
                              max_distance)
        distances[start:stop], normals[start:stop] = _checked_hits(d, n, stop - start)

    _in_batches(count, cast, stage, progress)
    return distances, normals


def _distances_to_own_ends(first_hit_distances: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray],
                           origins: np.ndarray, directions: np.ndarray, ends: np.ndarray, stage: str,
                           progress: Progress | None) -> np.ndarray:
    """Distances (R,) of rays each cast up to its own end (R,), in batches of RAYS_PER_CAST, reporting each batch."""
    count = origins.shape[0]
    distances = np.empty(count, dtype=np.float64)

    def cast(start: int, stop: int) -> None:
        d = first_hit_distances(np.ascontiguousarray(origins[start:stop]), np.ascontiguousarray(directions[start:stop]),
                                ends[start:stop])
        distances[start:stop] = _checked_distances(d, stop - start)  # as cast_in_batches checks the plain casts'

    _in_batches(count, cast, stage, progress)
    return distances


def segments_free(raycaster: Raycaster, starts: np.ndarray, ends: np.ndarray, stage: str = "segments",
                  progress: Progress | None = None) -> np.ndarray:
    """(S,) bool for segments starts (S, 3) -> ends (S, 3)."""
    a = np.asarray(starts, dtype=np.float64).reshape(-1, 3)
    b = np.asarray(ends, dtype=np.float64).reshape(-1, 3)
    if a.shape != b.shape:
        raise ValueError(f"segment starts {list(a.shape)} and ends {list(b.shape)} differ in shape")
    free = np.ones(a.shape[0], dtype=bool)
    if a.shape[0] == 0:
        return free
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    directions = np.empty_like(a)
    lengths = np.empty(a.shape[0], dtype=np.float64)
    unit_segments(a, b, directions, lengths)
    cast = lengths > 0.0  # zero length: nothing to cross (and no direction to cast along)
    if not cast.all():  # (rare: the leak checks never ask a point about itself) the segments to cast, gathered
        if not cast.any():
            return free
        a, directions, lengths = a[cast], directions[cast], lengths[cast]
    own_ends = getattr(raycaster, "first_hit_distances", None)
    if own_ends is not None:
        distances = _distances_to_own_ends(own_ends, a, directions, lengths, stage, progress)
    else:
        distances, _ = cast_in_batches(raycaster, a, directions, float(lengths.max()), stage, progress)
    free[cast] = ~(distances <= lengths)
    return free
