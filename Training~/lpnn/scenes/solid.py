"""Point in solid / outside the map, vectorised over points (the engine's CM_PointContents).

A point is walked down the world BSP from node 0 to its leaf (front child when n.p - dist > 0).
It is *outside the map* when the leaf's cluster is < 0 (the void beyond the level and the opaque
leaves inside structural brushes), and *in solid* when it lies inside one of the leaf's brushes
(n.p <= dist for every side) whose contents include CONTENTS_SOLID; detail brushes are only
caught by that brush test, because they do not split the tree.

Surfaces are solid: the engine's brush test is closed (a point on a face is inside), and we keep
that. Lattice points often sit exactly on a floor or wall plane (cells are multiples of 64 units,
like the brushes), and the metre round trip moves them ~1e-5 units either way. So a point within
ON_PLANE units of a split plane descends into *both* children (the leaf on either side of a wall
face may be the air one), and it is solid when any leaf it reaches is. A point on a surface is
thus removed deterministically instead of by rounding; kept, it would start rays at distance 0
and read the light grid inside the wall.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .bsp import Bsp
from .errors import BspError
from .ranges import concatenated_ranges
from .surfaces import CONTENTS_SOLID

ON_PLANE = 0.01  # Quake units (0.25 mm); brushes are at least 1 unit thick
# Bounds the (point, brush) pair arrays: terrain levels list up to ~300 brushes in a leaf.
POINTS_PER_CHUNK = 16_384


class SolidTester:
    def __init__(self, bsp: Bsp) -> None:
        self.name = bsp.name
        self.plane_normals = bsp.planes["normal"].astype(np.float64)
        self.plane_dists = bsp.planes["dist"].astype(np.float64)
        self.node_planes = bsp.nodes["plane"].astype(np.int64)
        self.node_children = bsp.nodes["children"].astype(np.int64)
        self.leaf_clusters = bsp.leafs["cluster"].astype(np.int64)
        self.leaf_first_brush = bsp.leafs["first_leaf_brush"].astype(np.int64)
        self.leaf_brush_count = bsp.leafs["num_leaf_brushes"].astype(np.int64)
        self.leaf_brushes = bsp.leaf_brushes.astype(np.int64)
        contents = bsp.shaders["content_flags"][bsp.brushes["shader"]]
        self.brush_is_solid = (contents & CONTENTS_SOLID) != 0
        self.brush_first_side = bsp.brushes["first_side"].astype(np.int64)
        self.brush_side_count = bsp.brushes["num_sides"].astype(np.int64)
        self.side_planes = bsp.brush_sides["plane"].astype(np.int64)
        self.brush_mins, self.brush_maxs = self._brush_bounds()

    def _brush_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Axis-aligned bounds per brush, to skip the side test for brushes nowhere near a point.

        The compilers write a brush's six axial sides first (-x, +x, -y, +y, -z, +z) and the engine
        relies on it (cm_load.c CM_BoundBrush); a brush that breaks the pattern gets infinite bounds.
        """
        count = len(self.brush_first_side)
        mins = np.full((count, 3), -np.inf)
        maxs = np.full((count, 3), np.inf)
        axial = self.brush_side_count >= 6
        sides = self.brush_first_side[axial, None] + np.arange(6)
        normals = self.plane_normals[self.side_planes[sides]]  # (B, 6, 3)
        dists = self.plane_dists[self.side_planes[sides]]  # (B, 6)
        expected = np.repeat(np.eye(3), 2, axis=0) * np.tile([-1.0, 1.0], 3)[:, None]
        ordered = np.all(normals == expected, axis=(1, 2))
        brushes = np.flatnonzero(axial)[ordered]
        mins[brushes] = -dists[ordered][:, 0::2]
        maxs[brushes] = dists[ordered][:, 1::2]
        return mins, maxs

    def leaves_near(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every leaf within ON_PLANE of each point: (point index, leaf index) pairs, point-major.

        Descends from node 0 (front child when n.p - dist > ON_PLANE, back when < -ON_PLANE, both
        in between). Points far from every split plane reach exactly one leaf.
        """
        points = np.asarray(points, dtype=np.float64)
        point = np.arange(len(points))
        node = np.zeros(len(points), dtype=np.int64)
        done_point, done_leaf = [], []
        # A valid tree is at most len(nodes) deep; more steps means a cycle in a damaged file.
        for _ in range(len(self.node_planes) + 1):
            reached = node < 0
            done_point.append(point[reached])
            done_leaf.append(-(node[reached] + 1))
            point, node = point[~reached], node[~reached]
            if point.size == 0:
                pairs_point = np.concatenate(done_point)
                order = np.argsort(pairs_point, kind="stable")
                return pairs_point[order], np.concatenate(done_leaf)[order]
            plane = self.node_planes[node]
            distance = np.einsum("ij,ij->i", points[point], self.plane_normals[plane]) - self.plane_dists[plane]
            front = distance > -ON_PLANE
            back = distance < ON_PLANE
            point = np.concatenate([point[front], point[back]])
            node = np.concatenate([self.node_children[node[front], 0], self.node_children[node[back], 1]])
        raise BspError(f"{self.name}: lump 3 (nodes): the BSP tree has a cycle (a point never reaches a leaf)")

    def in_solid_brush(self, points: np.ndarray, pair_point: np.ndarray, pair_leaf: np.ndarray) -> np.ndarray:
        """(N,) bool: within ON_PLANE of a CONTENTS_SOLID brush listed in one of the point's leaves."""
        counts = self.leaf_brush_count[pair_leaf]
        brush_point = np.repeat(pair_point, counts)
        brush = self.leaf_brushes[concatenated_ranges(self.leaf_first_brush[pair_leaf], counts)]
        solid = self.brush_is_solid[brush]
        brush_point, brush = brush_point[solid], brush[solid]
        near = points[brush_point]
        within = np.all((near >= self.brush_mins[brush] - ON_PLANE) & (near <= self.brush_maxs[brush] + ON_PLANE), axis=1)
        brush_point, brush = brush_point[within], brush[within]

        side_counts = self.brush_side_count[brush]
        side_owner = np.repeat(np.arange(len(brush)), side_counts)
        plane = self.side_planes[concatenated_ranges(self.brush_first_side[brush], side_counts)]
        distance = np.einsum("ij,ij->i", points[brush_point[side_owner]], self.plane_normals[plane]) - self.plane_dists[plane]
        # outside a brush = in front of at least one of its sides
        outside = np.bincount(side_owner, weights=distance > ON_PLANE, minlength=len(brush)) > 0
        return np.bincount(brush_point[~outside], minlength=len(points)) > 0

    def solid_or_outside(self, points: np.ndarray,
                         progress: Callable[[int, int], None] | None = None) -> np.ndarray:
        """(N,) bool for points (N, 3) in Quake units: in a solid brush or outside the playable volume.

        progress(done, total), if given, is called after every chunk of points.
        """
        points = np.asarray(points, dtype=np.float64)
        if points.ndim != 2 or points.shape[1] != 3 or not np.isfinite(points).all():
            raise ValueError(f"solid test positions must be finite (N, 3), got shape {points.shape}")
        result = np.zeros(len(points), dtype=bool)
        for start in range(0, len(points), POINTS_PER_CHUNK):
            chunk = points[start:start + POINTS_PER_CHUNK]
            pair_point, pair_leaf = self.leaves_near(chunk)
            outside = np.bincount(pair_point, weights=self.leaf_clusters[pair_leaf] < 0, minlength=len(chunk)) > 0
            result[start:start + len(chunk)] = outside | self.in_solid_brush(chunk, pair_point, pair_leaf)
            if progress is not None:
                progress(start + len(chunk), len(points))
        return result
