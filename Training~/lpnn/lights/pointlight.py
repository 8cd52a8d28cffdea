"""What q3map2's point lights deliver at free points (not on a surface): the light-grid rule shared by
the re-lit grid (compare.py) and the probe baker (bake.py).

Light j at point p: c = colour_j 7500 I_j / max(|x_j - p|, 16)^2 bytes of normal-incidence light
toward the unit direction (x_j - p) / |x_j - p| (Quake units and axes), no cosine (a free point has no
normal), a contribution of DROPPED_CONTRIBUTION byte or less dropped as q3map2 drops it, and an Embree
shadow ray from p to the light (a light on the point itself is seen).
"""

from __future__ import annotations

import numpy as np

from ..scenes.raycast import EmbreeRaycaster
from .emitters import DROPPED_CONTRIBUTION, clamped_distance_squared

RAY_MIN_LENGTH = 1e-3  # Quake units


def visible_light(points: np.ndarray, lights: np.ndarray, emitted: np.ndarray,
                  raycaster: EmbreeRaycaster | None, inhibit: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """points (C, 3), light positions (J, 3), emitted = colour x intensity x 7500 (J, 3) ->
    bytes (C, J, 3), zero where the light is dropped or shadowed, and unit directions (C, J, 3).
    Occluders closer than `inhibit` units to the point are ignored (q3map2's grid traces,
    light.c TraceGrid: inhibitRadius = half the largest grid cell side; light_trace.c)."""
    offset = lights[None, :, :] - points[:, None, :]  # (C, J, 3)
    distance = np.linalg.norm(offset, axis=2)
    unit = offset / np.maximum(distance, 1e-9)[..., None]
    colour = emitted[None, :, :] / clamped_distance_squared(distance)[..., None]
    counts = colour.max(axis=2) > DROPPED_CONTRIBUTION
    if raycaster is not None:
        point, light = np.nonzero(counts & (distance > max(RAY_MIN_LENGTH, inhibit)))
        length = distance[point, light] - inhibit
        hits, _ = raycaster.cast(points[point] + inhibit * unit[point, light], unit[point, light],
                                 float(length.max(initial=0.0)))
        counts[point[hits < length], light[hits < length]] = False
    return np.where(counts[..., None], colour, 0.0), unit
