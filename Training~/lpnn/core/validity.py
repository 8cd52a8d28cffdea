"""Probe validity: an evaluation point inside geometry must never become a probe (Documentation~/features.md).

The rule of Unity's Adaptive Probe Volumes: a probe's validity is the share of its rays that hit a back face, and a
probe whose share exceeds 0.25 is invalid (Unity-Technologies/Graphics, SRP Core ProbeDilationSettings.SetDefaults:
dilationValidityThreshold = 0.25). A ray hits a back face when the hit surface's oriented normal (the side its
winding calls front) points along the ray. Misses count as rays, not as back faces.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from .selection import degenerate_shape

if TYPE_CHECKING:
    from .capture import Capture
    from .features import Raycaster

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


# --------------------------------------------------------------------- applying the rule to points and captures

# Metres (C#: ProbeValidity.RayLength): longer than any level, so a ray that leaves the scene misses, and a point deep
# inside a thick solid still meets its back faces. The features count hits within 4 cells only; the rule counts all.
RAY_LENGTH = 1e4
# The optional capture section (float32 [N]) with each point's back-face fraction (Documentation~/file-formats.md).
CAPTURE_SECTION = "back_face_fraction"
POINTS_PER_CAST = 16_384  # 26 rays each, as the feature extractor's chunks


def back_face_fractions(positions: np.ndarray, raycaster: "Raycaster") -> np.ndarray:
    """(N,) back-face fraction of each point from the 26 feature directions cast RAY_LENGTH far.

    The raycaster must return the hit surfaces' oriented normals (the side their winding calls front), as
    lpnn.scenes.raycast.EmbreeRaycaster does; a raycaster whose normals always face the ray finds nothing invalid."""
    from .features import RAY_DIRECTIONS  # the same 26 directions as the geometry features

    points = np.asarray(positions, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"positions must be (N, 3), got shape {list(points.shape)}")
    rays = len(RAY_DIRECTIONS)
    fractions = np.empty(len(points))
    for start in range(0, len(points), POINTS_PER_CAST):
        chunk = points[start:start + POINTS_PER_CAST]
        origins = np.repeat(chunk, rays, axis=0)
        directions = np.tile(RAY_DIRECTIONS, (len(chunk), 1))
        distances, normals = raycaster.cast(origins, directions, RAY_LENGTH)
        fractions[start:start + len(chunk)] = back_face_fraction(
            RAY_DIRECTIONS, np.isfinite(distances).reshape(-1, rays), normals.reshape(-1, rays, 3))
    return fractions


def valid_points(capture: "Capture") -> np.ndarray | None:
    """(N,) bool from the capture's optional back-face fractions; None when it has none (an imported level's
    capture: the importer already removed the points in solid or inside geometry)."""
    if CAPTURE_SECTION not in capture.extra_sections:
        return None
    fractions = np.asarray(capture.extra_sections[CAPTURE_SECTION], dtype=np.float64)
    if fractions.shape != (capture.point_count,):
        raise ValueError(f"section '{CAPTURE_SECTION}' has shape {list(fractions.shape)}, expected [{capture.point_count}]")
    bad = ~((fractions >= 0.0) & (fractions <= 1.0))  # also NaN
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        raise ValueError(f"section '{CAPTURE_SECTION}': point {first} has {float(fractions[first])!r}, not a share of rays in "
                         f"[0, 1] ({int(bad.sum()):,} such points): export the capture again")
    return ~invalid(fractions)


def without_invalid(capture: "Capture", valid: np.ndarray | None) -> "Capture":
    """The capture restricted to its valid points (every per-point array, extra sections included), so no selection
    path can pick a point inside geometry. Refuses when the valid points cannot hold a probe group (fewer than 4, or
    all in one plane: Unity tetrahedralises the probes)."""
    if valid is None or valid.all():
        return capture
    ids = capture.ids[valid]
    shape = degenerate_shape(ids)
    if shape is not None:
        raise ValueError(
            f"only {len(ids):,} of {capture.point_count:,} points are valid ({shape}); the other "
            f"{capture.point_count - len(ids):,} are inside geometry (more than {BACK_FACE_THRESHOLD:.0%} of their rays hit "
            f"back faces), and a probe group needs at least 4 points not in one plane: export the capture from a volume "
            f"that covers open space, or check that the scene's meshes are closed and face outwards")
    return replace(
        capture, ids=capture.ids[valid], positions=capture.positions[valid], sh=capture.sh[valid],
        features=capture.features[valid], labels=None if capture.labels is None else capture.labels[valid],
        extra_sections={name: array[valid] for name, array in capture.extra_sections.items()})
