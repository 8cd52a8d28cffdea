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

UNKNOWN = 2  # stencil_looked_up's answer for a segment not remembered (0: blocked, 1: free)
NOT_WEIGHING = 3  # stencil_looked_up's answer for a stencil probe of weight <= the minimum: no segment to ask


@njit(cache=True, parallel=True)
def stencil_looked_up(partner, sees, points, probes, vertices, weights, min_weight, out):
    """out[i, j] (int8) for stencil probe j of point points[i] (global probe id probes[vertices[i, j]]): NOT_WEIGHING
    when weights[i, j] <= min_weight, else the remembered answer for the segment points[i] -> that probe (1 free,
    0 blocked; partner, sees: (N, slots) of each point's partners, -1 empty) or UNKNOWN; rows in parallel slices. One
    pass instead of gathering the weighing pairs and their ends first."""
    slots = partner.shape[1]
    chunks = chunk_count(points.shape[0])
    for chunk in prange(chunks):
        lo, hi = chunk_bounds(points.shape[0], chunks, chunk)
        for i in range(lo, hi):
            row = points[i]
            for j in range(vertices.shape[1]):
                if not weights[i, j] > min_weight:
                    out[i, j] = NOT_WEIGHING
                    continue
                other = probes[vertices[i, j]]
                out[i, j] = UNKNOWN
                for s in range(slots):
                    if partner[row, s] == other:
                        out[i, j] = 1 if sees[row, s] else 0
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


@njit(cache=True)
def blocked_rows(answers, blocked):
    """blocked[i] = some answers[i, j] is 0 (a weighing probe hidden from point i); returns the number of segments
    asked (answers other than NOT_WEIGHING). One pass over the answers instead of numpy's comparisons, reductions and
    count (0.8 s of a 10^6-point leak-aware placement)."""
    asked = 0
    for i in range(answers.shape[0]):
        hidden = False
        for j in range(answers.shape[1]):
            answer = answers[i, j]
            if answer != NOT_WEIGHING:
                asked += 1
            if answer == 0:
                hidden = True
        blocked[i] = hidden
    return asked
