"""Probe validity: an evaluation point inside geometry must never become a probe (Documentation~/features.md).

The rule of Unity's Adaptive Probe Volumes: a probe's validity is the share of its rays that hit a back face, and a
probe whose share exceeds 0.25 is invalid (Unity-Technologies/Graphics, SRP Core ProbeDilationSettings.SetDefaults:
dilationValidityThreshold = 0.25). A ray hits a back face when the hit surface's oriented normal (the side its
winding calls front) points along the ray. Misses count as rays, not as back faces.
"""

from __future__ import annotations

import numpy as np

BACK_FACE_THRESHOLD = 0.25


def back_face_fraction(directions: np.ndarray, hits: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(N,) share of back-face hits among the R rays of each point.

    directions (N, R, 3) or (R, 3) unit ray directions; hits (N, R) bool; normals (N, R, 3) oriented hit normals
    (ignored where hits is False)."""
    hit = np.asarray(hits, dtype=bool)
    if hit.ndim != 2 or hit.shape[1] == 0:
        raise ValueError(f"hits must be (points, rays) with at least one ray, got shape {list(hit.shape)}")
    d = np.broadcast_to(np.asarray(directions, dtype=np.float64), hit.shape + (3,))
    n = np.asarray(normals, dtype=np.float64)
    if n.shape != hit.shape + (3,):
        raise ValueError(f"normals {list(n.shape)} do not match hits {list(hit.shape)} x 3")
    back = hit & (np.einsum("nrk,nrk->nr", n, d) > 0.0)
    return back.sum(axis=1) / hit.shape[1]


def invalid(fraction: np.ndarray, threshold: float = BACK_FACE_THRESHOLD) -> np.ndarray:
    """(N,) bool: points whose back-face share exceeds the threshold (inside geometry)."""
    return np.asarray(fraction, dtype=np.float64) > threshold
