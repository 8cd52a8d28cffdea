"""Compiled loops of the remembered segments (leak_rule.py SegmentVisibility). At 10^5 points a refinement round looks up
a few 10^5 segments; the numpy version gathered (M, slots) temporaries and spent more time looking up than Embree spent
casting what was not remembered. These loops give the same answers and fill the slots in the same order
(tests/quality/test_quality_leak_aware.py checks the answers against fresh casts). Compiled with numba and cached on disk
(core/cache.py)."""

from __future__ import annotations

from ...core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit, prange  # noqa: E402  (after the cache folder is chosen)

from .metric_kernel import chunk_bounds, chunk_count  # noqa: E402

UNKNOWN = 2  # looked_up's answer for a segment not remembered (0: blocked, 1: free)


@njit(cache=True, parallel=True)
def looked_up(partner, sees, starts, ends, out):
    """out[k] = 1 when the segment starts[k] -> ends[k] is remembered free, 0 remembered blocked, UNKNOWN otherwise
    (partner, sees: (N, slots) of each point's partners, -1 empty); pairs in parallel slices."""
    slots = partner.shape[1]
    chunks = chunk_count(starts.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(starts.shape[0], chunks, chunk)
        for k in range(lo, hi):
            row, other = starts[k], ends[k]
            out[k] = UNKNOWN
            for s in range(slots):
                if partner[row, s] == other:
                    out[k] = 1 if sees[row, s] else 0
                    break


@njit(cache=True)
def remember(partner, sees, following, starts, ends, seen):
    """Each segment in order takes its start's next slot (following[point], then advanced round robin): a point's
    oldest partner goes first."""
    slots = partner.shape[1]
    for k in range(starts.shape[0]):
        row = starts[k]
        slot = following[row]
        partner[row, slot] = ends[k]
        sees[row, slot] = seen[k]
        following[row] = (slot + 1) % slots
