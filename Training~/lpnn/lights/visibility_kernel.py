"""The shadow rays a visibility refresh casts (model.ForwardModel.visibility), chosen in one compiled pass.

For every (point, light) pair of a chunk of points: the light is a candidate when it is in front of the point
(n . d > 0) and within its range (|d|^2 <= max_squared[j]); a candidate's ray starts RAY_OFFSET along the
normal and is cast when the light is farther than RAY_OFFSET from that origin. numpy built (points, lights, 3)
temporaries for this at every refresh; this loop computes the same tests pair by pair, in the same order
(points, then lights: numpy's nonzero order), so the rays are the same and in the same order
(tests/lights/test_lights_objective.py compares both). Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ..core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
from numba import njit  # noqa: E402  (after the cache folder is chosen)


@njit(cache=True)
def _count(points, normals, positions, max_squared, start, stop):
    count = 0
    for i in range(start, stop):
        for j in range(positions.shape[0]):
            dx = positions[j, 0] - points[i, 0]
            dy = positions[j, 1] - points[i, 1]
            dz = positions[j, 2] - points[i, 2]
            if dx * normals[i, 0] + dy * normals[i, 1] + dz * normals[i, 2] > 0.0 and \
                    dx * dx + dy * dy + dz * dz <= max_squared[j]:
                count += 1
    return count


@njit(cache=True)
def _fill(points, normals, positions, max_squared, start, stop, offset, point_out, light_out, origins, directions,
          lengths):
    """Writes the candidates' point, light, ray origin, unit direction and length; returns how many."""
    k = 0
    for i in range(start, stop):
        ox = points[i, 0] + offset * normals[i, 0]
        oy = points[i, 1] + offset * normals[i, 1]
        oz = points[i, 2] + offset * normals[i, 2]
        for j in range(positions.shape[0]):
            dx = positions[j, 0] - points[i, 0]
            dy = positions[j, 1] - points[i, 1]
            dz = positions[j, 2] - points[i, 2]
            if not (dx * normals[i, 0] + dy * normals[i, 1] + dz * normals[i, 2] > 0.0 and
                    dx * dx + dy * dy + dz * dz <= max_squared[j]):
                continue
            rx, ry, rz = positions[j, 0] - ox, positions[j, 1] - oy, positions[j, 2] - oz
            length = np.sqrt(rx * rx + ry * ry + rz * rz)
            point_out[k] = i
            light_out[k] = j
            origins[k, 0], origins[k, 1], origins[k, 2] = ox, oy, oz
            lengths[k] = length
            if length > 0.0:
                directions[k, 0], directions[k, 1], directions[k, 2] = rx / length, ry / length, rz / length
            else:
                directions[k, 0], directions[k, 1], directions[k, 2] = 0.0, 0.0, 1.0
            k += 1
    return k


def candidate_rays(points: np.ndarray, normals: np.ndarray, positions: np.ndarray, max_squared: np.ndarray,
                   start: int, stop: int, offset: float):
    """(point, light, origins, directions, lengths) of the candidate pairs of points [start, stop)."""
    arguments = (np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(normals, dtype=np.float64),
                 np.ascontiguousarray(positions, dtype=np.float64), np.ascontiguousarray(max_squared, dtype=np.float64),
                 start, stop)
    count = _count(*arguments)
    point = np.empty(count, dtype=np.int64)
    light = np.empty(count, dtype=np.int64)
    origins = np.empty((count, 3))
    directions = np.empty((count, 3))
    lengths = np.empty(count)
    _fill(*arguments, float(offset), point, light, origins, directions, lengths)
    return point, light, origins, directions, lengths
