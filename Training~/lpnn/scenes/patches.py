"""Bezier patch (face type 2) tessellation at a fixed level, vectorised over all patches.

A control grid of W x H points (odd, >= 3) holds ((W-1)/2) x ((H-1)/2) biquadratic patches that
share boundary rows/columns (quake3-bsp.md §2). Each patch is evaluated at t = k/L on both axes.

Why L = 8: the engine subdivides until the chord error is below 4 units (r_subdivisions). With
uniform steps the error of a quadratic is |P0 - 2P1 + P2| / (4L^2); over every patch of
openarena-081-maps, L = 8 keeps 99.97% of them within 4 units and the worst at 9 units (0.23 m,
a seventh of the default cell), where the thesis' L = 3 reached 66 units. Cost: 128 triangles a
patch, under 10^5 triangles for the most curved level.
"""

from __future__ import annotations

import numpy as np

from .ranges import concatenated_ranges

PATCH_LEVEL = 8


def bernstein_weights(level: int) -> np.ndarray:
    """Quadratic Bernstein weights (level + 1, 3) at t = k/level."""
    t = np.arange(level + 1, dtype=np.float64) / level
    return np.stack([(1.0 - t) ** 2, 2.0 * t * (1.0 - t), t * t], axis=1)


def patch_triangles(level: int) -> np.ndarray:
    """Triangles (2 level^2, 3) of one (level+1)^2 vertex grid, vertex (k, l) = k*(level+1) + l.

    Order (k,l),(k+1,l),(k,l+1) and (k,l+1),(k+1,l),(k+1,l+1) with k the row: Q3's winding.
    """
    side = level + 1
    k, l = np.meshgrid(np.arange(level), np.arange(level), indexing="ij")
    v00 = (k * side + l).ravel()
    v10, v01, v11 = v00 + side, v00 + 1, v00 + side + 1
    first = np.stack([v00, v10, v01], axis=1)
    second = np.stack([v01, v10, v11], axis=1)
    return np.stack([first, second], axis=1).reshape(-1, 3)


def tessellate_patches(control_points: np.ndarray, first_vert: np.ndarray, width: np.ndarray,
                       height: np.ndarray, level: int = PATCH_LEVEL) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tessellate patch faces given their control grids inside `control_points` (V, 3).

    first_vert, width, height: one entry per patch face (validated by the reader: odd, >= 3).
    Returns vertices (P*(level+1)^2, 3) float64, triangles (P*2*level^2, 3) int64 indexing those
    vertices, and for each triangle the position of its face in the input arrays.
    """
    first_vert = np.asarray(first_vert, dtype=np.int64)
    width = np.asarray(width, dtype=np.int64)
    height = np.asarray(height, dtype=np.int64)
    columns, rows = (width - 1) // 2, (height - 1) // 2
    per_face = columns * rows
    face_of_patch = np.repeat(np.arange(len(first_vert)), per_face)
    index_in_face = concatenated_ranges(np.zeros_like(per_face), per_face)
    i = index_in_face % columns[face_of_patch]  # patch column
    j = index_in_face // columns[face_of_patch]  # patch row
    # control point (row 2j+a, column 2i+b) of each patch: (P, 3, 3)
    a = np.arange(3)[None, :, None]
    b = np.arange(3)[None, None, :]
    w = width[face_of_patch][:, None, None]
    indices = first_vert[face_of_patch][:, None, None] + (2 * j[:, None, None] + a) * w + (2 * i[:, None, None] + b)
    controls = np.asarray(control_points, dtype=np.float64)[indices]  # (P, 3, 3, 3)

    weights = bernstein_weights(level)
    # rows follow v (weights over a), columns follow u (weights over b)
    grid = np.einsum("ka,lb,pabx->pklx", weights, weights, controls)
    side = level + 1
    vertices = grid.reshape(-1, grid.shape[-1])  # (V, 3) positions, or any (V, k) attributes
    local = patch_triangles(level)
    offsets = (np.arange(len(controls), dtype=np.int64) * side * side)[:, None, None]
    triangles = (local[None, :, :] + offsets).reshape(-1, 3)
    face_of_triangle = np.repeat(face_of_patch, len(local))
    return vertices, triangles, face_of_triangle
