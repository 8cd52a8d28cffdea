"""The fast decimation's mesh: the probes' tetrahedra and hull, each probe's star, every other point's cell, anchor
and error, and how a removal is applied to them (decimation_state.py evaluates what a removal would cost; see
reference_fast.py for the algorithm and why it is exact)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull

from ....core import sh as shmath
from .decimation import initial_mask
from ...metric.hull_projection import HullIndex
from ...metric.location import locate_local
from ...metric.metric import POINT_ERRORS, ReferenceField
from ...metric.tet_geometry import OPPOSITE, edge_frames
from ...metric.triangulation import VERTEX_KEY_BITS, GeometryError, face_keys, tetrahedralize
from .weighing import Weighing


@dataclass
class LocalRemoval:
    """Everything needed to apply one removal without recomputing it."""

    delta: float
    star: np.ndarray  # (S,) tetrahedra removed
    cavity: np.ndarray  # (C, 4) int64 point ids of the tetrahedra filling the hole
    cavity_inverse: np.ndarray  # (C, 3, 3)
    points: np.ndarray  # (A,) affected evaluation points (v included)
    cell: np.ndarray  # (A,) index into cavity, or -1 when anchored on a surviving hull triangle
    kept_cell: np.ndarray  # (A,) surviving tetrahedron owning that triangle (where cell == -1)
    anchor: np.ndarray  # (A, 3) where each point's weights apply
    errors: np.ndarray  # (A,) new errors (leak-weighted when the mesh is: DecimationMesh.weighed)
    shrinks_hull: bool = False


@dataclass
class GlobalRemoval:
    delta: float


class DecimationMesh:
    """The current probe set, its tetrahedra and hull, and every other point's cell, anchor and error.

    initial: the starting probe set (boolean mask or point indices, decimation.initial_mask); None = all.
    leaks: a leak weighting (weighing.Weighing, e.g. placement/leak_aware.LeakWeighting, with its segment memo): every
    error the mesh holds and every removal's new errors are then leak-weighted (weighed), so the greedy sums, compares
    and stops on those.
    """

    def __init__(self, field: ReferenceField, metric: str, initial: np.ndarray | None = None,
                 leaks: Weighing | None = None):
        if field.point_count >= (1 << VERTEX_KEY_BITS):
            raise GeometryError(f"the fast reference handles fewer than {1 << VERTEX_KEY_BITS:,} candidates, "
                                f"got {field.point_count:,}: use a larger cell size")
        self.field = field
        self.leaks = leaks
        self._every_point = np.arange(field.point_count, dtype=np.int64)  # stencils hold point ids (weighed)
        self.values = field.values(metric)
        self.error_of = POINT_ERRORS[metric]
        self.lifted = field.frame.lifted(field.world)
        self.tie = field.frame.tie_heights(field.world)
        self.local = field.local
        n = field.point_count
        start = initial_mask(initial, n)
        self.alive = np.ones(n, dtype=bool) if start is None else start
        self.anchor = field.local.copy()
        self.errors = np.zeros(n)
        self.cell = np.full(n, -1, dtype=np.int64)
        self._rebuild()

    # ---------------------------------------------------------------------------- global state
    def _rebuild(self) -> None:
        """Tetrahedralise the alive probes and locate every other point from scratch."""
        probes = np.flatnonzero(self.alive)
        tri = tetrahedralize(self.field.world[probes], self.field.frame, probes)
        self.tets = probes[tri.tets]
        self.inverse = tri.inverse
        self.volume6 = np.abs(edge_frames(self.local, self.tets)[3])
        self.tet_vertices: list[tuple[int, ...]] = [tuple(t) for t in self.tets.tolist()]  # fast Python access
        self.tet_count = self.tets.shape[0]
        self.live_tets = self.tet_count
        self.star: list[set[int]] = [set() for _ in range(self.field.point_count)]
        flat = self.tets.reshape(-1)
        order = np.argsort(flat, kind="stable")
        for group in np.split(order, np.flatnonzero(np.diff(flat[order])) + 1):
            self.star[int(flat[group[0]])] = set((group // 4).tolist())
        faces = probes[tri.hull_faces]
        self.hull: dict[int, tuple[tuple[int, int, int], int]] = {}
        self.hull_degree = np.zeros(self.field.point_count, dtype=np.int64)  # hull triangles at each probe
        self.hull_of_tet: dict[int, list[int]] = {}
        for key, face, owner in zip(face_keys(faces, self.field.point_count).tolist(), faces.tolist(),
                                    tri.hull_face_tets.tolist()):
            self._add_hull_face(key, face, owner)
        self.members: dict[int, list[int]] = {}
        others = np.flatnonzero(~self.alive)
        self.cell[:] = -1
        self.errors[:] = 0.0
        self.anchor[:] = self.local
        if others.shape[0]:
            stencil = locate_local(tri, self.local[others])
            interpolated = shmath.blend(self.values[probes], stencil.vertices, stencil.weights)
            self.errors[others] = self.weighed(others, probes[stencil.vertices], stencil.weights,
                                               self.error_of(interpolated, self.values[others], self.field.scale))
            self.cell[others] = stencil.cell
            self.anchor[others] = stencil.anchor
            order = np.argsort(stencil.cell, kind="stable")
            for group in np.split(order, np.flatnonzero(np.diff(stencil.cell[order])) + 1):
                self.members[int(stencil.cell[group[0]])] = others[group].tolist()
        self._hull_index: tuple[HullIndex, np.ndarray] | None = None
        self._find_extreme()

    def weighed(self, points: np.ndarray, vertices: np.ndarray, weights: np.ndarray, errors: np.ndarray) -> np.ndarray:
        """The errors (A,) of `points` under the stencils `vertices` (A, 4 point ids) and `weights`: as they are
        without a leak weighting; with one, a leaking point's multiplied by its weight (LeakWeighting.leaking is the
        rule of LeakWeighting.weighted, so the leak-aware default's refinement and this reference sum the same
        errors). A point's weighted error depends on its stencil only, so a removal still changes only its star's
        points'."""
        if self.leaks is None:
            return errors
        leaking = self.leaks.leaking(self.field, points, self._every_point, vertices, weights)
        return np.where(leaking, errors * self.leaks.weight, errors)

    def _add_hull_face(self, key: int, face: list[int], owner: int) -> None:
        self.hull[key] = (tuple(face), owner)
        self.hull_of_tet.setdefault(owner, []).append(key)
        self.hull_degree[face] += 1

    def _drop_hull_face(self, key: int) -> int:
        """Forget a hull triangle (not its owner's list); returns its owner."""
        face, owner = self.hull.pop(key)
        self.hull_degree[list(face)] -= 1
        return owner

    def _find_extreme(self) -> None:
        probes = np.flatnonzero(self.alive)
        self.extreme = np.zeros(self.field.point_count, dtype=bool)
        self.extreme[probes[ConvexHull(self.local[probes]).vertices]] = True

    def _append_tets(self, tets: np.ndarray, inverse: np.ndarray) -> np.ndarray:
        """Store new tetrahedra (capacity doubles: amortised O(1)); returns their ids."""
        start, stop = self.tet_count, self.tet_count + tets.shape[0]
        if stop > self.tets.shape[0]:
            grow = max(stop, 2 * self.tets.shape[0]) - self.tets.shape[0]
            self.tets = np.concatenate([self.tets, np.zeros((grow, 4), dtype=np.int64)])
            self.inverse = np.concatenate([self.inverse, np.zeros((grow, 3, 3))])
            self.volume6 = np.concatenate([self.volume6, np.zeros(grow)])
        self.tets[start:stop] = tets
        self.tet_vertices.extend(tuple(t) for t in tets.tolist())
        self.inverse[start:stop] = inverse
        self.volume6[start:stop] = np.abs(edge_frames(self.local, tets)[3])
        self.tet_count = stop
        return np.arange(start, stop)

    def _star_of(self, v: int) -> np.ndarray:
        return np.fromiter(self.star[v], dtype=np.int64, count=len(self.star[v]))

    def _link_of(self, v: int) -> np.ndarray:
        """v's neighbours, sorted (Python sets: much faster than np.unique on ~20 tetrahedra)."""
        vertices = self.tet_vertices
        link = set().union(*(vertices[t] for t in self.star[v]))
        link.discard(v)
        return np.fromiter(sorted(link), dtype=np.int64, count=len(link))

    def _affected(self, v: int, star: np.ndarray) -> np.ndarray:
        points = [p for t in star.tolist() for p in self.members.get(t, ())]
        points.append(v)
        return np.asarray(points, dtype=np.int64)

    def _hole_boundary(self, v: int, star: np.ndarray, cavity: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray, set[int]]:
        """Hull triangles that appear when v goes (F, 3), each with its owner: a cavity row (else -1)
        and a surviving tetrahedron (else -1); and the keys of hull triangles that the hole closes.

        Two kinds appear: boundary triangles of the hole that do not face the rest of the mesh, and
        (when the hull shrinks) triangles of link(v) that faced star(v) and now face the outside.
        A hull triangle that a hole tetrahedron lands on becomes interior ("closed"): this only
        happens with nearly coplanar hull points (float32 noise), where Qhull's local decision and
        the mesh's disagree at the rounding level; the mesh then follows the local one.
        """
        n = self.field.point_count
        star_set = set(star.tolist())
        faces = cavity[:, OPPOSITE].reshape(-1, 3)
        keys = face_keys(faces, n)
        _, first, counts = np.unique(keys, return_index=True, return_counts=True)
        cavity_keys = set(keys.tolist())
        star_tets = self.tets[star]
        link_faces = star_tets[star_tets != v].reshape(-1, 3)  # each star tetrahedron's face opposite v
        link_keys = face_keys(link_faces, n).tolist()
        inner = {k for k in link_keys if k not in self.hull}  # shared with a surviving tetrahedron
        hole, closed = [], set()
        for i in first[counts == 1].tolist():
            key = int(keys[i])
            if key in inner:
                continue
            if key in self.hull and self.hull[key][1] not in star_set:
                closed.add(key)
            else:
                hole.append(i)
        exposed = [i for i, k in enumerate(link_keys) if k in inner and k not in cavity_keys]
        exposed_owner = []
        for i in exposed:
            a, b, c = link_faces[i].tolist()
            exposed_owner.append(min((self.star[a] & self.star[b] & self.star[c]) - star_set))
        out_faces = np.concatenate([faces[hole].reshape(-1, 3), link_faces[exposed].reshape(-1, 3)])
        owner_cavity = np.concatenate([np.asarray(hole, dtype=np.int64) // 4, np.full(len(exposed), -1)])
        owner_kept = np.concatenate([np.full(len(hole), -1), np.asarray(exposed_owner, dtype=np.int64)])
        return out_faces.astype(np.int64), owner_cavity.astype(np.int64), owner_kept.astype(np.int64), closed

    def _indexed_hull(self) -> tuple[HullIndex, np.ndarray]:
        """The current hull triangles with a search tree (rebuilt only after the hull changed), and owners."""
        if self._hull_index is None:
            entries = list(self.hull.values())
            faces = np.asarray([face for face, _ in entries], dtype=np.int64).reshape(-1, 3)
            owners = np.asarray([owner for _, owner in entries], dtype=np.int64)
            self._hull_index = (HullIndex(self.local, faces), owners)
        return self._hull_index

    # -------------------------------------------------------------------------------- removing
    def remove(self, v: int, removal: LocalRemoval | GlobalRemoval) -> tuple[np.ndarray, np.ndarray, bool]:
        """Apply a fresh removal. Returns the probes whose star or points changed, the tetrahedra
        that died, and whether the hull triangles changed."""
        if isinstance(removal, GlobalRemoval):
            self.alive[v] = False
            self._rebuild()
            return np.flatnonzero(self.alive), np.zeros(0, dtype=np.int64), True
        star = removal.star
        new_faces, new_cavity, new_kept, closed = self._hole_boundary(v, star, removal.cavity)
        link = self._link_of(v)
        for t in star.tolist():
            self.members.pop(t, None)
            for u in self.tet_vertices[t]:
                self.star[u].discard(t)
        new_ids = self._append_tets(removal.cavity, removal.cavity_inverse)
        self.live_tets += removal.cavity.shape[0] - star.shape[0]
        for t, vertices in zip(new_ids.tolist(), removal.cavity.tolist()):
            for u in vertices:
                self.star[u].add(t)
        shrinks = removal.shrinks_hull
        hull_changed = new_faces.shape[0] > 0 or bool(closed)
        for t in star.tolist():
            for key in self.hull_of_tet.pop(t, ()):
                self._drop_hull_face(key)
                hull_changed = True
        for key in closed:
            self.hull_of_tet[self._drop_hull_face(key)].remove(key)
        if hull_changed:
            self._hull_index = None
        new_owner = new_kept.copy()
        new_owner[new_cavity >= 0] = new_ids[new_cavity[new_cavity >= 0]]
        for key, face, owner in zip(face_keys(new_faces, self.field.point_count).tolist(), new_faces.tolist(),
                                    new_owner.tolist()):
            self._add_hull_face(key, face, owner)
        cells = removal.kept_cell.copy()
        cells[removal.cell >= 0] = new_ids[removal.cell[removal.cell >= 0]]
        self.cell[removal.points] = cells
        self.errors[removal.points] = removal.errors
        self.anchor[removal.points] = removal.anchor
        for p, t in zip(removal.points.tolist(), cells.tolist()):
            self.members.setdefault(t, []).append(p)
        self.alive[v] = False
        stale = set(link.tolist())
        if shrinks:
            # Surviving tetrahedra that gained a hull triangle or points anchored on one: their
            # vertices' removal costs change.
            touched = np.concatenate([removal.kept_cell[removal.kept_cell >= 0], new_kept[new_kept >= 0]])
            for t in np.unique(touched).tolist():
                stale.update(self.tets[t].tolist())
            self._find_extreme()
        return np.asarray(sorted(stale), dtype=np.int64), star, hull_changed
