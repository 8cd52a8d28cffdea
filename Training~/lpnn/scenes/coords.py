"""Quake III world space -> Unity world space (Documentation~/openarena.md, quake3-bsp.md §4).

Quake: right-handed, +Z up, one unit ~ one inch. Unity: left-handed, +Y up, metres.
    (x, y, z)_Unity = s * (-y, z, x)_Quake,   s = 0.0254 m per unit for positions, 1 for directions.
The matrix is a signed axis permutation with determinant -1: it flips handedness (as it must) and
keeps lengths and angles, so unit vectors stay unit and Q3's clockwise-front winding becomes Unity's.
"""

from __future__ import annotations

import numpy as np

from .defaults import METRES_PER_UNIT

# rows: Unity axes; columns: Quake axes.
QUAKE_TO_UNITY = np.array([[0.0, -1.0, 0.0],
                           [0.0, 0.0, 1.0],
                           [1.0, 0.0, 0.0]])


def quake_to_unity(vectors: np.ndarray, scale: float = METRES_PER_UNIT) -> np.ndarray:
    """Map Quake vectors (..., 3) to Unity axes, times `scale` (positions: metres per unit; directions: 1)."""
    return scale * (np.asarray(vectors, dtype=np.float64) @ QUAKE_TO_UNITY.T)


def unity_to_quake(vectors: np.ndarray, scale: float = METRES_PER_UNIT) -> np.ndarray:
    """Inverse of `quake_to_unity` with the same `scale` (the matrix is orthogonal: inverse = transpose)."""
    return (np.asarray(vectors, dtype=np.float64) @ QUAKE_TO_UNITY) / scale
