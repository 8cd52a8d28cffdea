"""The fast decimation's state: its mesh (decimation_mesh.py) and the exact local cost of removing each probe
(see reference_fast.py for the algorithm and why it is exact)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ....core import sh as shmath
from .decimation_mesh import DecimationMesh, GlobalRemoval, LocalRemoval
from .hole_wrap import wrap_holes
from ...metric.hull_projection import HullProjection, nearest_on_candidates
from ...metric.location import INSIDE_TOLERANCE, locate_local
from ...metric.tet_geometry import OPPOSITE, barycentric_in, best_per_group, edge_frames, orient_and_invert, segment_pairs
from ...metric.triangulation import GeometryError, face_keys, flatness, lower_hull, tetrahedralize

VOLUME_TOLERANCE = 1e-9  # the hole's volume must equal the star's to this relative tolerance
NEAREST_STAR_TETS = 6  # star tetrahedra a hole centroid tries first (by centroid distance)
ANCHOR_ON_FACE = 1e-12  # barycentric weight of v at most this: the anchor lies on the face opposite v
CONFLICT_SLACK = 1e-9  # lifted units (extent ~1): conflicts closer to 0 than this count as possible


def _within(weights: np.ndarray) -> np.ndarray:
    """Inside test from the weights (..., 3) of a, b, c in tetrahedra (v, a, b, c) (v's weight is 1 - sum)."""
    return (weights.min(axis=-1) >= -INSIDE_TOLERANCE) & (weights.sum(axis=-1) <= 1.0 + INSIDE_TOLERANCE)


class DecimationState(DecimationMesh):
    """The mesh with the exact cost of removing any probe: the hole's new tetrahedra and every affected point's new
    stencil and error, evaluated against the current mesh without changing it (DecimationMesh.remove applies one)."""

    # ------------------------------------------------------------------------------ evaluation
    def evaluation_weight(self, v: int) -> float:
        """Rough cost of evaluating v's removal in interior-removal units (to share work between
        replicas): hull probes re-project the points of their star."""
        if not (self.extreme[v] or self.hull_degree[v]):
            return 1.0
        star = self.star[v]
        return 4.0 + len(star) / 10.0 + sum(len(self.members.get(t, ())) for t in star) / 25.0

    def _hole_candidates(self, v: int, star: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """Tetrahedra of link(v)'s triangulation (global ids) and how strongly each conflicts with v
        (> 0: v lies inside its circumsphere, in lifted units).

        The tetrahedra filling the hole all conflict with v (otherwise they would be in the mesh
        already); when v keeps the hull they are exactly the conflicting ones. None when Qhull cannot
        triangulate a solid link (use the safe path); no tetrahedra when the link is flat.
        """
        link = self._link_of(v)
        try:
            tets, planes = lower_hull(self.lifted[link])
        except GeometryError:
            if flatness(self.local[link]) is None:
                return None
            return np.zeros((0, 4), dtype=np.int64), np.zeros(0)
        return link[tets], planes[:, :4] @ self.lifted[v] + planes[:, 4]

    def _fill_hole(self, v: int, star: np.ndarray, candidates: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The candidate tetrahedra whose centroid lies in star(v): tets, inverses, 6 x volumes (used
        when the hull shrinks and the hole is only part of the star, or the link is near-degenerate).

        Hull vertices can have stars of hundreds of tetrahedra, re-evaluated after every neighbour's
        removal: each centroid first tries the star tetrahedra with the nearest centroids, and only
        the centroids found in none of them are tested against the whole star.
        """
        cavity, inverse, volume6, _ = orient_and_invert(self.local, candidates)
        tets = self.tets[star]
        origin = self.local[v]  # a corner of every star tetrahedron
        edges = self.local[tets[tets != v].reshape(-1, 3)] - origin  # (S, 3, 3): rows a-v, b-v, c-v
        to_weights = np.linalg.inv(np.transpose(edges, (0, 2, 1)))  # weights of a, b, c from x - v
        centroids = self.local[cavity].mean(axis=1) - origin
        inside = np.zeros(cavity.shape[0], dtype=bool)
        unresolved = np.arange(cavity.shape[0])
        if star.shape[0] > 2 * NEAREST_STAR_TETS and cavity.shape[0]:
            near = cKDTree(edges.sum(axis=1) / 4.0).query(centroids, k=NEAREST_STAR_TETS)[1]
            inside = _within(np.einsum("ckyx,cx->cky", to_weights[near], centroids)).any(axis=1)
            unresolved = np.flatnonzero(~inside)
        if unresolved.shape[0]:
            inside[unresolved] = _within(np.einsum("cx,syx->csy", centroids[unresolved], to_weights)).any(axis=1)
        return cavity[inside], inverse[inside], volume6[inside]

    def removals(self, vertices: list[int]) -> list[LocalRemoval | GlobalRemoval]:
        """Removal costs of several probes (evaluated independently, each against the current state).

        Holes of probes that are not hull vertices are refilled by gift wrapping (hole_wrap.py); hull
        vertices, and holes the wrapping cannot close, use the lower hull of the lifted link (one Qhull
        call each).
        """
        results: list[LocalRemoval | GlobalRemoval | None] = [None] * len(vertices)
        stars = [self._star_of(v) for v in vertices]
        inside = [p for p, v in enumerate(vertices) if not self.extreme[v]]
        wrapped = dict(zip(inside, wrap_holes(self.local, self.tie, [vertices[p] for p in inside],
                                              [self.tets[stars[p]] for p in inside],
                                              [bool(self.hull_degree[vertices[p]]) for p in inside])))
        holes_of: dict[int, tuple[np.ndarray, np.ndarray] | None] = {}
        batch: list[int] = []
        cavities: list[np.ndarray] = []
        for position, v in enumerate(vertices):
            cavity = wrapped.get(position)
            if cavity is None:
                holes = holes_of[position] = self._hole_candidates(v, stars[position])
                if self.extreme[v]:
                    # Near-zero conflicts are numerically ambiguous: keep them, the centroid test sorts them out.
                    results[position] = self._extreme_removal(
                        v, stars[position], None if holes is None else holes[0][holes[1] > -CONFLICT_SLACK])
                    continue
                if holes is None:
                    results[position] = self._global_removal(v)
                    continue
                cavity = holes[0][holes[1] > 0.0]
            batch.append(position)
            cavities.append(cavity)
        if batch:
            for position, result in zip(batch, self._interior_removals([vertices[p] for p in batch],
                                                                       [stars[p] for p in batch], cavities)):
                if result is None:
                    v = vertices[position]
                    holes = holes_of[position] if position in holes_of else self._hole_candidates(v, stars[position])
                    result = self._retried_removal(v, stars[position], holes)
                results[position] = result
        return results  # type: ignore[return-value]

    def _retried_removal(self, v: int, star: np.ndarray, holes: tuple[np.ndarray, np.ndarray] | None
                         ) -> LocalRemoval | GlobalRemoval:
        """Cost of a removal whose hole did not check out (volume or point location)."""
        if holes is None:
            return self._global_removal(v)
        if self.hull_degree[v] > 0:
            # v lies on a flat part of the hull; with float32 positions it sticks out by a hair
            # (Qhull calls it coplanar, not extreme), so the hull does shrink a little.
            return self._extreme_removal(v, star, holes[0][holes[1] > -CONFLICT_SLACK])
        cavity, _, _ = self._fill_hole(v, star, holes[0])  # near-degenerate link: select the hole by centroids
        result = self._interior_removals([v], [star], [cavity])[0]
        return result if result is not None else self._global_removal(v)

    def _interior_removals(self, vertices: list[int], stars: list[np.ndarray], cavities: list[np.ndarray]
                           ) -> list[LocalRemoval | None]:
        """Batched costs of removals that keep the hull (the hole is exactly the star)."""
        segments = len(vertices)
        raw_segment = np.repeat(np.arange(segments), [c.shape[0] for c in cavities])
        cavity, inverse, volume6, kept = orient_and_invert(self.local, np.concatenate(cavities))
        segment = raw_segment[kept]
        star_ids = np.concatenate(stars)
        star_segment = np.repeat(np.arange(segments), [s.shape[0] for s in stars])
        star_volume6 = np.bincount(star_segment, self.volume6[star_ids], segments)
        filled = np.abs(np.bincount(segment, volume6, segments) - star_volume6) <= VOLUME_TOLERANCE * star_volume6
        affected = [self._affected(v, star) for v, star in zip(vertices, stars)]
        points = np.concatenate(affected)
        point_segment = np.repeat(np.arange(len(vertices)), [a.shape[0] for a in affected])
        cavity_count = np.bincount(segment, minlength=len(vertices))
        cavity_start = np.cumsum(cavity_count) - cavity_count
        left, right = segment_pairs(point_segment, cavity_start, cavity_count)
        lam = barycentric_in(self.local, cavity[right], inverse[right], self.anchor[points[left]])
        pick, best = best_per_group(left, lam.min(axis=1), points.shape[0])
        located = best >= -INSIDE_TOLERANCE
        ok = filled & (np.bincount(point_segment, ~located, len(vertices)) == 0)
        pick = np.where(located, pick, 0)
        weights = np.clip(lam[pick], 0.0, None)
        weights /= weights.sum(axis=1, keepdims=True)
        cell = right[pick]
        errors = self.weighed(points, cavity[cell], weights, self.error_of(
            shmath.blend(self.values, cavity[cell], weights), self.values[points], self.field.scale))
        delta = np.bincount(point_segment, errors - self.errors[points], len(vertices))
        point_end = np.cumsum([a.shape[0] for a in affected])
        out: list[LocalRemoval | None] = []
        for k, star in enumerate(stars):
            if not ok[k]:
                out.append(None)
                continue
            mine = slice(cavity_start[k], cavity_start[k] + cavity_count[k])
            rows = slice(point_end[k] - affected[k].shape[0], point_end[k])
            out.append(LocalRemoval(
                delta=float(delta[k]), star=star, cavity=cavity[mine], cavity_inverse=inverse[mine],
                points=affected[k], cell=cell[rows] - cavity_start[k], kept_cell=np.full(affected[k].shape[0], -1),
                anchor=self.anchor[affected[k]], errors=errors[rows]))
        return out

    def _extreme_removal(self, v: int, star: np.ndarray, holes: np.ndarray | None) -> LocalRemoval | GlobalRemoval:
        """Cost of removing a hull vertex: the hull shrinks, points left outside are re-projected."""
        if holes is None:
            return self._global_removal(v)
        if holes.shape[0]:
            cavity, inverse, _ = self._fill_hole(v, star, holes)
        else:  # v was an "ear": its whole star leaves the hull
            cavity, inverse = np.zeros((0, 4), dtype=np.int64), np.zeros((0, 3, 3))
        if cavity.shape[0] == 0 and star.shape[0] == self.live_tets:
            return GlobalRemoval(delta=float("inf"))  # every tetrahedron goes: the rest is flat
        affected = self._affected(v, star)
        settled, settled_cell = self._on_surviving_hull_faces(v, affected, cavity)
        points = affected[~settled]
        query = self.local[points]  # positions, not anchors: the hull itself changes
        count = points.shape[0]
        weights = np.zeros((count, 4))
        vertices = np.zeros((count, 4), dtype=np.int64)
        cell = np.full(count, -1, dtype=np.int64)
        inside = np.zeros(count, dtype=bool)
        if cavity.shape[0]:
            lam = barycentric_in(self.local, np.tile(cavity, (count, 1)),
                                 np.tile(inverse, (count, 1, 1)), np.repeat(query, cavity.shape[0], axis=0))
            lam = lam.reshape(count, cavity.shape[0], 4)
            smallest = lam.min(axis=2)
            cell = np.argmax(smallest, axis=1)
            inside = smallest[np.arange(count), cell] >= -INSIDE_TOLERANCE
            chosen = np.clip(lam[np.arange(count), cell], 0.0, None)
            weights[inside] = chosen[inside] / chosen[inside].sum(axis=1, keepdims=True)
            vertices[inside] = cavity[cell[inside]]
        kept_cell = np.full(count, -1, dtype=np.int64)
        anchor = query.copy()
        outside = np.flatnonzero(~inside)
        if outside.shape[0]:
            projection, faces, owner_cavity, owner_kept = self._project_onto_shrunken_hull(
                v, star, cavity, query[outside])
            vertices[outside, :3] = faces[projection.face]
            weights[outside, :3] = projection.weights
            anchor[outside] = projection.anchor
            cell[outside] = owner_cavity[projection.face]
            kept_cell[outside] = owner_kept[projection.face]
        cell[~inside & (kept_cell >= 0)] = -1
        errors = self.weighed(points, vertices, weights, self.error_of(
            shmath.blend(self.values, vertices, weights), self.values[points], self.field.scale))
        kept = affected[settled]  # same stencil and error, new owner
        return LocalRemoval(delta=float(errors.sum() - self.errors[points].sum()), star=star, cavity=cavity,
                            cavity_inverse=inverse, points=np.concatenate([points, kept]),
                            cell=np.concatenate([cell, settled_cell]),
                            kept_cell=np.concatenate([kept_cell, np.full(kept.shape[0], -1, dtype=np.int64)]),
                            anchor=np.concatenate([anchor, self.anchor[kept]]),
                            errors=np.concatenate([errors, self.errors[kept]]), shrinks_hull=True)

    def _on_surviving_hull_faces(self, v: int, points: np.ndarray, cavity: np.ndarray
                                 ) -> tuple[np.ndarray, np.ndarray]:
        """Which affected points keep their stencil when hull vertex v goes (mask), and their new
        owners (cavity rows, in the order of the masked points).

        A point outside the hull anchored on a hull triangle without v keeps it: the triangle stays
        on the smaller hull, and the nearest point of a smaller convex set that still contains the old
        nearest point is that point. Only its owner changes, to the hole tetrahedron on that triangle.
        Most points of hull-shrinking removals are of this kind (they gather on large hull
        triangles), so this saves most of the re-projection.
        """
        settled = np.zeros(points.shape[0], dtype=bool)
        cells = self.cell[points]
        rows = np.flatnonzero((cells >= 0) & np.any(self.anchor[points] != self.local[points], axis=1))
        if rows.shape[0] == 0 or cavity.shape[0] == 0:
            return settled, np.zeros(0, dtype=np.int64)
        tets = self.tets[cells[rows]]  # star tetrahedra: each holds v once
        lam = barycentric_in(self.local, tets, self.inverse[cells[rows]], self.anchor[points[rows]])
        on_face = lam[tets == v] <= ANCHOR_ON_FACE
        rows, tets = rows[on_face], tets[on_face]
        faces = tets[tets != v].reshape(-1, 3)
        keys = face_keys(faces, self.field.point_count)
        on_hull = np.fromiter((key in self.hull for key in keys.tolist()), dtype=bool, count=keys.shape[0])
        cavity_keys = face_keys(cavity[:, OPPOSITE].reshape(-1, 3), self.field.point_count)
        order = np.argsort(cavity_keys, kind="stable")
        found = order[np.minimum(np.searchsorted(cavity_keys[order], keys), order.shape[0] - 1)]
        apex = cavity[found // 4, found % 4]
        # The hole tetrahedron on the triangle must lie on v's side of it (else the hole closed it).
        sides = [edge_frames(self.local, np.column_stack([faces, corner]))[3] for corner in (apex, np.full_like(apex, v))]
        match = on_hull & (cavity_keys[found] == keys) & (sides[0] * sides[1] > 0.0)
        settled[rows[match]] = True
        return settled, found[match] // 4

    def _project_onto_shrunken_hull(self, v: int, star: np.ndarray, cavity: np.ndarray, query: np.ndarray
                                    ) -> tuple[HullProjection, np.ndarray, np.ndarray, np.ndarray]:
        """Nearest points on the hull without v: the triangles not owned by star(v), plus the new ones.

        Tries the triangles touching link(v) first (certified by the supporting-plane test against the
        remaining extreme probes and link(v)); points that fail it use every hull triangle.
        Returns the projection, the triangles (F, 3), and per triangle its cavity owner (or -1) and
        surviving owner (or -1)."""
        new_faces, new_cavity, new_kept, closed = self._hole_boundary(v, star, cavity)
        link = self._link_of(v)
        star_set = set(star.tolist())
        nearby = {t for u in link.tolist() for t in self.star[u]} - star_set
        keys = [key for t in nearby for key in self.hull_of_tet.get(t, ()) if key not in closed]
        kept_faces = np.asarray([self.hull[key][0] for key in keys], dtype=np.int64).reshape(-1, 3)
        kept_owner = np.asarray([self.hull[key][1] for key in keys], dtype=np.int64)
        touching = np.isin(kept_faces, link).any(axis=1)  # the triangles around the hole
        kept_faces, kept_owner = kept_faces[touching], kept_owner[touching]
        hull_points = np.union1d(np.flatnonzero(self.extreme), link)
        hull_points = self.local[hull_points[hull_points != v]]
        faces = np.concatenate([kept_faces, new_faces])
        owner_cavity = np.concatenate([np.full(kept_faces.shape[0], -1), new_cavity])
        owner_kept = np.concatenate([kept_owner, new_kept])
        projection, certified = nearest_on_candidates(self.local, faces, query, hull_points)
        if not np.all(certified):
            index, owners = self._indexed_hull()
            allowed = ~np.isin(owners, star) & ~np.isin(face_keys(index.faces, self.field.point_count),
                                                         np.fromiter(closed, dtype=np.int64, count=len(closed)))
            everywhere = index.nearest(query[~certified], allowed, new_faces)
            faces = np.concatenate([faces, index.faces])
            owner_cavity = np.concatenate([owner_cavity, np.full(index.faces.shape[0], -1)])
            owner_kept = np.concatenate([owner_kept, owners])
            # everywhere numbers the indexed triangles first, then new_faces.
            remap = np.concatenate([np.arange(index.faces.shape[0]) + kept_faces.shape[0] + new_faces.shape[0],
                                    kept_faces.shape[0] + np.arange(new_faces.shape[0])])
            face = projection.face.copy()
            weights, anchor, distance = projection.weights.copy(), projection.anchor.copy(), projection.distance.copy()
            rows = np.flatnonzero(~certified)
            face[rows], weights[rows] = remap[everywhere.face], everywhere.weights
            anchor[rows], distance[rows] = everywhere.anchor, everywhere.distance
            projection = HullProjection(face=face, weights=weights, anchor=anchor, distance=distance)
        return projection, faces, owner_cavity, owner_kept

    def _global_removal(self, v: int) -> GlobalRemoval:
        """Cost by re-tetrahedralising everything (the safe path); inf if the rest would be flat."""
        self.alive[v] = False
        probes = np.flatnonzero(self.alive)
        try:
            tri = tetrahedralize(self.field.world[probes], self.field.frame, probes)
        except GeometryError:
            return GlobalRemoval(delta=float("inf"))
        finally:
            self.alive[v] = True
        points = self._affected(v, self._star_of(v))
        stencil = locate_local(tri, self.local[points])
        interpolated = shmath.blend(self.values[probes], stencil.vertices, stencil.weights)
        errors = self.weighed(points, probes[stencil.vertices], stencil.weights,
                              self.error_of(interpolated, self.values[points], self.field.scale))
        return GlobalRemoval(delta=float(errors.sum() - self.errors[points].sum()))
