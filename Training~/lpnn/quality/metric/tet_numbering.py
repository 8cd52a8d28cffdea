"""The numbering of a tetrahedralisation's tetrahedra that §1's tie rule reads (Documentation~/quality.md §1 "Ties").

A point on a face, edge or vertex shared by several tetrahedra belongs to the lowest-index one, so the numbering is part
of the answer. It is made a function of the set of tetrahedra alone — not of Qhull's (or Unity's) facet order, of the
order the probes were given in, or of whether the tetrahedra were tetrahedralised or derived — by ordering them by a
64-bit hash of their four corners' *point indices* (the evaluation points' indices, the same in both languages; never
float positions): each tetrahedron's corners ascending by point index (then oriented by swapping the last two where
negative, tet_geometry.orient_and_invert), the tetrahedra by ascending `tet_hash` of those indices, ties (never seen,
but possible) by the sorted indices. A hash rather than the sorted indices themselves: ordered by their
sorted corners, the tetrahedra kept +2.4 % probes on the validation levels against Qhull's order, ordered by a hash
about as many as Qhull's (benchmarks.md "Insertion rounds derived by insertion"). The C# core's Quality.TetrahedronNumbering is the same rule; Tests/Data/tet_numbering_golden.json
pins both.
"""

from __future__ import annotations

import numpy as np

GOLDEN_GAMMA = np.uint64(0x9E3779B97F4A7C15)  # splitmix64's increment: the hash's start


def mix64(x: np.ndarray) -> np.ndarray:
    """splitmix64's finaliser (uint64 in, uint64 out): a well-spread, platform-independent 64-bit mix."""
    with np.errstate(over="ignore"):  # uint64 wrap-around is the point of the hash
        x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


def tet_hash(corners: np.ndarray) -> np.ndarray:
    """(T,) uint64 hash of each row of ascending point indices (T, 4):
    h = mix64(a + GOLDEN_GAMMA); h = mix64(h ^ b); h = mix64(h ^ c); h = mix64(h ^ d) (uint64 arithmetic)."""
    ids = np.asarray(corners, dtype=np.int64).astype(np.uint64)
    with np.errstate(over="ignore"):
        key = mix64(ids[:, 0] + GOLDEN_GAMMA)
    for column in range(1, 4):
        key = mix64(key ^ ids[:, column])
    return key


def numbered(tets: np.ndarray, ids: np.ndarray | None = None) -> np.ndarray:
    """The tetrahedra (T, 4) (positions in the probe set) renumbered by the rule above: each row's corners ascending by
    point index `ids[corner]` (None: the positions themselves), the rows by (tet_hash, sorted point indices). A function
    of the set of tetrahedra and of `ids` only: any row order and corner order of the same tetrahedra give the same
    array."""
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
    if tets.shape[0] == 0:
        return tets.copy()
    point = tets if ids is None else np.asarray(ids, dtype=np.int64)[tets]
    corner_order = np.argsort(point, axis=1, kind="stable")
    rows = np.arange(tets.shape[0])[:, None]
    corners, point = tets[rows, corner_order], point[rows, corner_order]
    order = np.lexsort((point[:, 3], point[:, 2], point[:, 1], point[:, 0], tet_hash(point)))
    return corners[order]
