"""Each insertion round's tetrahedralisation for one InsertionOrder (quality.md §5.1 step 6), derived from the last
round's by inserting the new probes instead of a Qhull call per round.

    tetrahedra = InsertionTetrahedra()
    mesh = tetrahedra.of(field, last_mesh, probes)   # probes = last round's probes + the new batch

Why. A whole level's insertion rounds and tolerance search made ~75 Qhull calls of the whole probe set (ctf_compromise:
1.5 s of its 11 s, benchmarks.md "Scale: whole levels"); inserting a round's batch into the last round's tetrahedra
(metric/regular_insertion.py) costs a few milliseconds and gives the same tetrahedra, numbered alike (tet_numbering:
a function of the set), so the same rounds. The C# core's InsertionTetrahedra, the same rule:
- A derivation that is refused (regular_insertion's reasons: a crack in the last round's tetrahedra, a starting hull
  that is not exactly convex, a true tie, ...) tetrahedralises that round; the next derives from its answer.
- Derived rounds are compared with Qhull's answer for the same probes until one agrees; later ones are trusted, not
  compared (a regular triangulation is unique: where Qhull's would differ, by a facet it merged, Qhull's is the one
  off). A round that differs takes Qhull's answer (a re-synchronisation) and the next derives again; after MAX_RESYNCS
  disagreements before any agreement every later round is tetrahedralised (C#: DerivationCheck.MaxResyncs).
"""

from __future__ import annotations

import numpy as np

from ..metric.metric import ReferenceField
from ..metric.regular_insertion import inserted_tetrahedra
from ..metric.triangulation import Tetrahedralization, tetrahedralize, tetrahedralized_from

MAX_RESYNCS = 3  # disagreements before any agreement after which every later round is tetrahedralised (module text)


class InsertionTetrahedra:
    """The rounds' tetrahedralisations of one insertion order, and what it took: `derived` rounds, `tetrahedralised`
    ones (Qhull calls, checks included), `resyncs` (derived rounds Qhull's answer replaced), `refusals` (why a round
    could not be derived). `derive=False`: every round tetrahedralised (for comparison)."""

    def __init__(self, derive: bool = True) -> None:
        self.derive = derive
        self.agrees = False
        self.derived = 0
        self.tetrahedralised = 0
        self.resyncs = 0
        self.refusals: list[str] = []

    def of(self, field: ReferenceField, last: Tetrahedralization | None, probes: np.ndarray) -> Tetrahedralization:
        """The tetrahedralisation of `probes` (point indices: `last`'s probes, in its vertex order, then the new ones),
        numbered by point index as triangulation.tetrahedralize numbers it. `last`: the previous round's (None: none)."""
        if last is not None and last.point_count == probes.shape[0]:  # nothing new: the same probes in the same order
            return last
        world = field.world[probes]
        if not self.derive or self.resyncs >= MAX_RESYNCS or last is None:
            return self._tetrahedralized(field, world, probes)
        local = field.local[probes]  # the field's own frame coordinates: tetrahedralize's to_local(world), row for row
        added = np.arange(last.point_count, probes.shape[0])
        order = added[np.argsort(probes[added], kind="stable")]  # grid order: short walks (the answer is the same)
        tets, refusal = inserted_tetrahedra(last, local, field.frame.tie_heights(world), order)
        if tets is None:
            self.refusals.append(refusal)
            return self._tetrahedralized(field, world, probes)
        derived = tetrahedralized_from(field.frame, world, local, tets, probes)
        if not self.agrees:
            fresh = self._tetrahedralized(field, world, probes)
            if not np.array_equal(derived.tets, fresh.tets):  # tetrahedralized_from numbers both alike
                self.resyncs += 1
                return fresh
            self.agrees = True
        self.derived += 1
        return derived

    def of_superset(self, field: ReferenceField, last: Tetrahedralization, last_probes: np.ndarray,
                    probes: np.ndarray) -> Tetrahedralization:
        """The tetrahedralisation of the sorted point indices `probes`, a superset of `last_probes` (the point indices of
        `last`'s vertices, in its vertex order), derived from `last` as a round is (of); its vertex i is probes[i], as
        triangulation.tetrahedralize(field.world[probes], field.frame, probes) gives it (metric.probe_mesh's `mesh`)."""
        added = np.setdiff1d(probes, last_probes)
        if probes.shape[0] != last_probes.shape[0] + added.shape[0] or np.any(probes[1:] <= probes[:-1]):
            raise ValueError("probes must be sorted, distinct and hold every one of last_probes")
        in_order = np.concatenate([np.asarray(last_probes, dtype=np.int64), added])
        return with_vertices_reordered(self.of(field, last, in_order), np.argsort(in_order, kind="stable"))

    def _tetrahedralized(self, field: ReferenceField, world: np.ndarray, probes: np.ndarray) -> Tetrahedralization:
        self.tetrahedralised += 1
        return tetrahedralize(world, field.frame, probes)


def with_vertices_reordered(mesh: Tetrahedralization, order: np.ndarray) -> Tetrahedralization:
    """The same tetrahedralisation with vertex i the old vertex order[i] (`order` a permutation of its vertices): the
    same tetrahedra, rows, corner order, neighbours and hull, so the numbering and orientation by point index
    (tet_numbering) are kept — what tetrahedralize gives the reordered positions with their point indices."""
    position = np.empty(order.shape[0], dtype=np.int64)
    position[order] = np.arange(order.shape[0])
    return Tetrahedralization(frame=mesh.frame, world=mesh.world[order], points=mesh.points[order],
                              tets=position[mesh.tets], neighbours=mesh.neighbours, inverse=mesh.inverse,
                              hull_faces=position[mesh.hull_faces], hull_face_tets=mesh.hull_face_tets)
