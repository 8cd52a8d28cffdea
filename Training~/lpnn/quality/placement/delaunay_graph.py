"""The Delaunay graph of a probe set (batched refinement's candidates are independent sets of it: quality.md §5.3),
made from the tetrahedra, or updated after a removal from the old graph and the removed probes' refills.

    edges = graph_edges(probes, tets)                                     # every edge both ways, sorted
    edges = edges_after_removal(edges, tets, neighbours, gone, refills)   # the same, from the old graph (or None)

Why the update. Made afresh, the graph sorts 12 directed keys per tetrahedron every round (~840,000 at 11,000 probes);
a round removes a few stars, so the old graph with their probes' edges dropped and their refills' edges added is the
new one but for one case: an edge between two kept probes whose every tetrahedron lay in a removed star, which the
refills may not bring back. Such an edge is looked for where it can be: around an edge the tetrahedra form a ring
(a fan on the hull) linked by the faces that hold the edge, so if any of them survives, one does next to a removed
star's tetrahedron across a face, unless a crack (a face with no tetrahedron across inside the hull:
metric/triangulation.py) breaks the ring there; then the update gives up (None) and the graph is made afresh. The
answer is graph_edges' array exactly (tests).
"""

from __future__ import annotations

import numpy as np

from ...core.integer_sets import sorted_contains, sorted_unique
from ..metric.triangulation import INNER_BOUNDARY

_PAIRS = [(a, b) for a in range(4) for b in range(4) if a != b]  # the 12 directed edges of a tetrahedron


def graph_edges(probes: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The Delaunay graph of the tetrahedra `tets` (T, 4), vertices positions in the sorted `probes`: every edge both
    ways, global ids, sorted by first then second id."""
    count = probes.shape[0]
    keys = sorted_unique(_directed_keys(tets, count))
    return probes[np.stack([keys // count, keys % count], axis=1)]


def edges_after_removal(edges: np.ndarray, tets: np.ndarray, neighbours: np.ndarray, gone: np.ndarray,
                        refills: np.ndarray) -> np.ndarray | None:
    """graph_edges of the tetrahedralisation without the `gone` ((N,) bool, N the point count) probes, whose stars were
    refilled with `refills` (F, 4), from the old graph `edges` (graph_edges' form) and the old tetrahedra `tets`
    (T, 4), both in global ids, and their `neighbours` (T, 4: Tetrahedralization.neighbours). None when a removed
    star borders a crack (module text): make the graph afresh."""
    size = np.int64(gone.shape[0])
    in_star = gone[tets].any(axis=1)
    across = neighbours[in_star]
    if np.any(across == INNER_BOUNDARY):
        return None
    rim = sorted_unique(across[across >= 0].reshape(-1))
    rim = rim[~in_star[rim]]
    star_keys = _directed_keys(tets[in_star], size)
    link = sorted_unique(star_keys[~gone[star_keys // size] & ~gone[star_keys % size]])  # kept-kept edges of the stars
    refill_keys = sorted_unique(_directed_keys(refills, size))
    present = sorted_unique(np.concatenate([_directed_keys(tets[rim], size), refill_keys]))
    vanished = link[~sorted_contains(link, present)]
    old = edges[:, 0] * size + edges[:, 1]
    keep = ~gone[edges[:, 0]] & ~gone[edges[:, 1]]
    if vanished.shape[0]:
        keep &= ~sorted_contains(old, vanished)
    kept = old[keep]
    new = refill_keys[~sorted_contains(refill_keys, kept)]
    merged = np.insert(kept, np.searchsorted(kept, new), new)
    return np.stack([merged // size, merged % size], axis=1)


def _directed_keys(tets: np.ndarray, size: int | np.int64) -> np.ndarray:
    """first * size + second for the 12 directed edges of every tetrahedron (ids < size)."""
    tets = np.asarray(tets, dtype=np.int64)
    return np.concatenate([tets[:, a] * size + tets[:, b] for a, b in _PAIRS])
