"""First-hit rays against a triangle soup with Embree (a real BVH), for feature extraction.

Implements the `lpnn.core.features.Raycaster` protocol (features.md "Inputs"):
    cast(origins (R,3) float64, directions (R,3) float64 unit, max_distance)
      -> distances (R,) float64, np.inf when nothing is hit within max_distance,
         normals (R,3) float64: the hit triangle's geometric unit normal, any orientation; zeros on a miss.
Both facings are hit (Embree culls nothing by default), as Unity's `hitBackfaces = true`.

We drive the embreex scene that trimesh's `RayMeshIntersector` wraps directly: trimesh's wrapper
has no maximum distance (rays would traverse the whole level) and recomputes hit points by a
second plane intersection; embreex's `run(..., dists=tfar, output=1)` returns the triangle and
distance of the first hit in one pass. Embree works in float32, so vertices and ray origins are
recentred on the mesh's bounding-box centre first (as trimesh does) to keep precision.
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

# Big enough to amortise the call, small enough to split evenly over the cores.
RAYS_PER_CHUNK = 65_536


class EmbreeRaycaster:
    """Rays against fixed geometry. Vertices in any unit; distances come back in the same unit."""

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray, threads: int | None = None) -> None:
        from embreex import rtcore_scene  # heavy native import, only when rays are needed
        from embreex.mesh_construction import TriangleMesh

        vertices = np.asarray(vertices, dtype=np.float64)
        triangles = np.asarray(triangles, dtype=np.int64)
        if vertices.ndim != 2 or vertices.shape[1] != 3 or triangles.ndim != 2 or triangles.shape[1] != 3:
            raise ValueError(f"vertices (V,3) and triangles (T,3) expected, got {vertices.shape} and {triangles.shape}")
        self.triangle_count = len(triangles)
        self.threads = max(1, threads or os.cpu_count() or 1)
        corners = vertices[triangles]
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        lengths = np.linalg.norm(normals, axis=1, keepdims=True)
        # a zero-area triangle keeps a zero normal (the feature extractor ignores zero normals)
        self.face_normals = np.divide(normals, lengths, out=np.zeros_like(normals), where=lengths > 0)
        self._centre = (vertices.min(axis=0) + vertices.max(axis=0)) / 2 if len(vertices) else np.zeros(3)
        self._scene = None
        self.rays_cast = 0  # totals over every cast() call, for throughput figures
        self.cast_seconds = 0.0
        if self.triangle_count:
            self._scene = rtcore_scene.EmbreeScene()
            TriangleMesh(scene=self._scene, vertices=(vertices - self._centre).astype(np.float32),
                         indices=triangles.astype(np.int32))

    def cast(self, origins: np.ndarray, directions: np.ndarray, max_distance: float) -> tuple[np.ndarray, np.ndarray]:
        distances, triangles = self.first_hits(origins, directions, max_distance)
        normals = np.zeros((len(distances), 3))
        hit = triangles >= 0
        normals[hit] = self.face_normals[triangles[hit]]
        return distances, normals

    def first_hit_distances(self, origins: np.ndarray, directions: np.ndarray,
                            max_distances: np.ndarray) -> np.ndarray:
        """distances (R,) float64 of rays each ending at its own max_distances (R,) (np.inf on a miss): what
        lpnn.core.segments casts a segment with, so that its answer depends on that segment alone."""
        return self.first_hits(origins, directions, max_distances)[0]

    def first_hits(self, origins: np.ndarray, directions: np.ndarray,
                   max_distance: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """distances (R,) float64 (np.inf on a miss) and the hit triangle's index (R,) int64 (-1 on a miss);
        `max_distance` one for every ray or (R,) one each."""
        origins = np.asarray(origins, dtype=np.float64)
        directions = np.asarray(directions, dtype=np.float64)
        if origins.ndim != 2 or origins.shape[1] != 3 or directions.shape != origins.shape:
            raise ValueError(f"origins and directions must both be (R,3), got {origins.shape} and {directions.shape}")
        _require_rays(origins, directions)
        count = len(origins)
        limit = _checked_max_distances(max_distance, count)
        started = time.perf_counter()
        distances = np.full(count, np.inf)
        triangles = np.full(count, -1, dtype=np.int64)
        if count == 0 or self._scene is None:
            return distances, triangles
        chunks = [slice(start, min(start + RAYS_PER_CHUNK, count)) for start in range(0, count, RAYS_PER_CHUNK)]
        local_origins = (origins - self._centre).astype(np.float32)
        directions32 = directions.astype(np.float32)
        # Embree's ray end is float32: round it up so no hit within max_distance is cut off,
        # then drop the hits that lie beyond max_distance in double.
        ray_end = limit.astype(np.float32)
        short = ray_end < limit
        ray_end[short] = np.nextafter(ray_end[short], np.float32(np.inf))

        def run(chunk: slice) -> None:
            result = self._scene.run(local_origins[chunk], directions32[chunk], dists=ray_end[chunk], output=1)
            triangle = result["primID"].astype(np.int64)
            t = result["tfar"].astype(np.float64)
            hit = (triangle >= 0) & (t <= limit[chunk])
            distances[chunk] = np.where(hit, t, np.inf)
            triangles[chunk] = np.where(hit, triangle, -1)

        if self.threads == 1 or len(chunks) == 1:
            for chunk in chunks:
                run(chunk)
        else:
            # embreex releases the GIL while tracing; the committed scene is safe to share.
            with ThreadPoolExecutor(max_workers=self.threads) as pool:
                list(pool.map(run, chunks))
        self.rays_cast += count
        self.cast_seconds += time.perf_counter() - started
        return distances, triangles


def _checked_max_distances(max_distance: float | np.ndarray, count: int) -> np.ndarray:
    """(count,) float64 ray ends from one distance or one per ray; ValueError naming the first bad one."""
    if np.ndim(max_distance) == 0:
        value = float(max_distance)
        if not (np.isfinite(value) and value >= 0):
            raise ValueError(f"max_distance {max_distance!r} must be finite and >= 0")
        return np.full(count, value)
    limit = np.asarray(max_distance, dtype=np.float64)
    if limit.shape != (count,):
        raise ValueError(f"max distances must be one number or one per ray ({count}), got shape {list(limit.shape)}")
    bad = ~(np.isfinite(limit) & (limit >= 0))
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        raise ValueError(f"ray {first}'s max distance {limit[first]!r} must be finite and >= 0 "
                         f"({int(bad.sum()):,} such rays)")
    return limit


def _require_rays(origins: np.ndarray, directions: np.ndarray) -> None:
    """Finite origins and unit directions (Embree would silently scale distances by |d|)."""
    from .raycast_kernel import bad_rays  # numba, as the rays' other heavy imports, only when rays are cast

    bad_origins, first_origin, not_unit, first_direction = bad_rays(np.ascontiguousarray(origins),
                                                                    np.ascontiguousarray(directions))
    if bad_origins:
        raise ValueError(f"ray {first_origin} has a non-finite origin {origins[first_origin].tolist()} "
                         f"({bad_origins:,} such rays)")
    if not_unit:
        length = float(np.linalg.norm(directions[first_direction]))
        raise ValueError(f"ray directions must be unit vectors: ray {first_direction} has length {length!r} "
                         f"({not_unit:,} such rays)")
