"""Small vectorised tetrahedron kernels shared by point location and the fast reference."""

from __future__ import annotations

import numpy as np

# Face i of a tetrahedron: the vertices opposite vertex i, outward for a positive one (the tetrahedralisation's
# neighbours, the compiled passes of removal_kernel.py and the fast reference number faces so).
OPPOSITE = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]], dtype=np.int64)

# A tetrahedron is flat when |6 x volume| <= this x |e1| |e2| |e3| (its edges from vertex 0). Relative to its own
# edges, so it holds at any cell size and extent: an absolute 1e-14 on the unit-extent frame dropped every
# tetrahedron of a grid with more than ~46,000 cells along an axis. The zero-volume ties a tetrahedraliser
# emits for cospherical grid points leave only rounding noise (~1e-16 of the edge product); a real
# tetrahedron of grid points has 6 x volume >= h^3, i.e. above 1e-12 x its edge product unless its edges
# span more than ~10,000 cells while it stays one cell thin. Documentation~/quality.md §1; C# TetrahedralMesh.
FLAT_RELATIVE_VOLUME = 1e-12


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (T, 3) arrays (np.cross is several times slower on small arrays)."""
    out = np.empty_like(a)
    out[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    out[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    out[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return out


def edge_frames(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Edges e1, e2, e3 (T, 3) from vertex 0 and 6 x signed volume (T,)."""
    p = points[tets]
    e1, e2, e3 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]
    return e1, e2, e3, np.einsum("ij,ij->i", e1, _cross(e2, e3))


def edge_product(e1: np.ndarray, e2: np.ndarray, e3: np.ndarray) -> np.ndarray:
    """(T,) |e1| |e2| |e3|: the scale a tetrahedron's 6 x volume is compared with (is_flat)."""
    return np.sqrt(np.einsum("ij,ij->i", e1, e1) * np.einsum("ij,ij->i", e2, e2) * np.einsum("ij,ij->i", e3, e3))


def is_flat(e1: np.ndarray, e2: np.ndarray, e3: np.ndarray, det: np.ndarray) -> np.ndarray:
    """(T,) True where the tetrahedron with edges e1, e2, e3 (T, 3) and 6 x signed volume det is flat."""
    return ~(np.abs(det) > FLAT_RELATIVE_VOLUME * edge_product(e1, e2, e3))


def orient_and_invert(points: np.ndarray, tets: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Drop flat tetrahedra, orient the rest positively; returns tets, inverses (T, 3, 3), 6 x volume
    and the mask of the input rows kept.

    The inverse of the edge matrix [e1 e2 e3] has rows (e2 x e3, e3 x e1, e1 x e2) / det.
    """
    e1, e2, e3, det = edge_frames(points, tets)
    keep = ~is_flat(e1, e2, e3, det)
    out, e1, e2, e3, det = tets[keep].copy(), e1[keep], e2[keep], e3[keep], det[keep]
    negative = det < 0.0
    if np.any(negative):  # swapping vertices 2 and 3 flips the orientation
        out[negative, 2], out[negative, 3] = tets[keep][negative, 3], tets[keep][negative, 2]
        e2, e3 = np.where(negative[:, None], e3, e2), np.where(negative[:, None], e2, e3)
        det = np.abs(det)
    return out, _adjugate_inverse(e1, e2, e3, det), det, keep


def edge_inverse(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Inverses (T, 3, 3) of positively oriented tetrahedra's edge matrices, as orient_and_invert computes them (the C#
    core's TetrahedralMesh too); a tetrahedron of zero volume gets the identity instead of a division by zero."""
    e1, e2, e3, det = edge_frames(points, tets)
    zero = det == 0.0
    if np.any(zero):
        e1, e2, e3 = (np.where(zero[:, None], axis, e) for axis, e in zip(np.eye(3), (e1, e2, e3)))
        det = np.where(zero, 1.0, det)
    return _adjugate_inverse(e1, e2, e3, det)


def _adjugate_inverse(e1: np.ndarray, e2: np.ndarray, e3: np.ndarray, det: np.ndarray) -> np.ndarray:
    """The inverse of the edge matrix [e1 e2 e3] with 6 x volume det: rows (e2 x e3, e3 x e1, e1 x e2) / det."""
    return np.stack([_cross(e2, e3), _cross(e3, e1), _cross(e1, e2)], axis=1) / det[:, None, None]


def barycentric_in(points: np.ndarray, tets: np.ndarray, inverse: np.ndarray, query: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (P, 4) of query[i] in tetrahedron i (tets (P, 4), inverse (P, 3, 3))."""
    rest = np.einsum("pij,pj->pi", inverse, query - points[tets[:, 0]])
    return np.concatenate([1.0 - rest.sum(axis=1, keepdims=True), rest], axis=1)


def segment_pairs(left_segment: np.ndarray, right_start: np.ndarray, right_count: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """All (i, j) with j in the right-hand range of i's segment, i ascending (left rows sorted by segment).

    left_segment (L,): segment of each left row; right_start/right_count (K,): each segment's rows.
    """
    per_left = right_count[left_segment]
    left = np.repeat(np.arange(left_segment.shape[0]), per_left)
    first = np.cumsum(per_left) - per_left
    right = np.arange(left.shape[0]) - np.repeat(first, per_left) + np.repeat(right_start[left_segment], per_left)
    return left, right


def best_per_group(group: np.ndarray, value: np.ndarray, group_count: int) -> tuple[np.ndarray, np.ndarray]:
    """For pairs sorted by group: the index of the first pair with the largest value in each group,
    and that value (-1 and -inf for groups without pairs)."""
    best_value = np.full(group_count, -np.inf)
    index = np.full(group_count, -1, dtype=np.int64)
    if group.shape[0] == 0:
        return index, best_value
    starts = np.flatnonzero(np.concatenate([[True], group[1:] != group[:-1]]))
    present = group[starts]
    best_value[present] = np.maximum.reduceat(value, starts)
    # Pairs equal to their group's best, first one per group (pairs are sorted by group).
    is_best = np.flatnonzero(value == best_value[group])
    first = np.concatenate([[True], group[is_best][1:] != group[is_best][:-1]])
    index[group[is_best[first]]] = is_best[first]
    return index, best_value
