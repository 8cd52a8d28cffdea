"""Insertion's rounds located incrementally (insertion.py, quality.md §5): a probe set's stencils and errors at every
other point, carried from one round to the next.

    located = located_set(field, probes, metric)            # every other point located (the start)
    located = with_inserted(field, located, batch, metric, tetrahedra)  # walked again only where a tetrahedron broke
    mean = mean_error(field, located)                        # the placement's mean error (metric.mean_placement_error)

Why only there. Inserting probes re-triangulates only the tetrahedra they break (metric/triangulation.py: the tie-broken
Delaunay is unique); every other tetrahedron is in the new tetrahedralisation too, with the same four vertices. A point
clearly inside such a tetrahedron (smallest coordinate > location.INSIDE_TOLERANCE) is still inside it and in no other,
so it needs no walk: only its barycentric coordinates are computed in the new tetrahedralisation (the same numbers a
walk computes on arriving there), then every stencil's error. A point on its boundary (a face, edge or vertex it may
share) takes the tie rule's tetrahedron (quality.md §1 "Ties": the lowest-index one holding it, which an insertion can
change), searched from there as a walk's end is. The walk runs only for the points whose tetrahedron broke and the
points outside the hull (the hull may have grown). So every point gets exactly a fresh location's stencil, as in the C#
core's InsertionRounds. On whole levels a round of growth 0.1 leaves 60-67 % of the points in unbroken tetrahedra
(ctf_compromise, validation).

The walks are coherent (location.locate_local): those points ascend, in grid order, and each walk starts where the
previous one ended, instead of at the nearest tetrahedron centroid, which took a k-d tree over every centroid, built
and queried anew each round (benchmarks.md "Scale: whole levels" times the change). The tie rule makes a point's
tetrahedron independent of where its walk starts, so the stencils are the same (the same probes on every validation
level and crop, leak-aware and not: benchmarks.md "Scale: whole levels", 2026-11-28).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .batched_state import tet_keys
from .insertion_kernel import carried_points, located_again, rows_of
from .insertion_tetrahedra import InsertionTetrahedra
from ..metric.location import Stencil, keep_located, locate_cells, stencils_of_cells
from ..metric.metric import ReferenceField, probe_mesh, stencil_point_errors
from ..metric.triangulation import Tetrahedralization


@dataclass(frozen=True)
class Placed:
    """What the next round needs of a probe set: the probes (point indices in insertion order), their
    tetrahedralisation, the other points (ascending) and each one's tetrahedron (-1: outside the hull). ~12 bytes a
    point: InsertionOrder keeps a few rounds' of them for the tolerance search."""

    probes: np.ndarray
    mesh: Tetrahedralization
    others: np.ndarray
    inside: np.ndarray


@dataclass(frozen=True)
class LocatedSet(Placed):
    """A Placed set with the other points' stencils (vertices are positions in `probes`) and errors (M,)."""

    stencil: Stencil
    errors: np.ndarray

    def placed(self) -> Placed:
        return Placed(probes=self.probes, mesh=self.mesh, others=self.others, inside=self.inside.astype(np.int32))


def _finished(field: ReferenceField, probes: np.ndarray, mesh: Tetrahedralization, others: np.ndarray,
              stencil: Stencil, metric: str) -> LocatedSet:
    errors = stencil_point_errors(field, probes, others, stencil, metric)[others]
    inside = np.where(stencil.outside, -1, stencil.cell)  # stencil.cell is a hull owner outside
    return LocatedSet(probes=probes, mesh=mesh, others=others, inside=inside, stencil=stencil, errors=errors)


def located_set(field: ReferenceField, probes: np.ndarray, metric: str) -> LocatedSet:
    """Every point but the probes located from scratch (metric.probe_mesh: coherent walks, module text)."""
    ordered, others, mesh, stencil = probe_mesh(field, probes, coherent=True)
    return _finished(field, ordered, mesh, others, stencil, metric)


def with_inserted(field: ReferenceField, located: Placed, added: np.ndarray, metric: str,
                  tetrahedra: InsertionTetrahedra) -> LocatedSet:
    """`located` with the points `added` (none of them probes yet) made probes: walked only where needed (module
    text). `tetrahedra`: the order's InsertionTetrahedra, which derives the new tetrahedralisation from located.mesh
    (with derive=False: Qhull's)."""
    # Probes in insertion order (positions in `probes`); the tetrahedra are numbered by point index (tet_numbering),
    # as metric.probe_stencil numbers them, whatever the order.
    probes = np.concatenate([located.probes, np.asarray(added, dtype=np.int64)])
    mesh = tetrahedra.of(field, located.mesh, probes)
    ordered = np.sort(probes)
    old_keys = tet_keys(located.probes[located.mesh.tets], ordered)
    new_keys = tet_keys(probes[mesh.tets], ordered)
    by_key = np.argsort(new_keys, kind="stable")
    position = np.minimum(np.searchsorted(new_keys[by_key], old_keys), by_key.shape[0] - 1)
    survivor = np.where(new_keys[by_key[position]] == old_keys, by_key[position], -1)  # old tetrahedron -> new
    is_added = np.zeros(field.point_count, dtype=bool)
    is_added[added] = True
    # The others not added, each with its surviving tetrahedron (-1: broken or outside the hull) and local coordinates:
    # one compiled pass (insertion_kernel.carried_points).
    others, cell, local = carried_points(located.others, located.inside, is_added, survivor,
                                         np.ascontiguousarray(field.local))
    walked, coordinates = keep_located(mesh, local, cell)  # kept cells, or the tie rule's around them
    again = np.flatnonzero(cell < 0)  # broken tetrahedra and points outside the hull
    if again.shape[0]:
        located_again(again, cell, walked, coordinates, *locate_cells(mesh, rows_of(local, again), coherent=True))
    stencil = stencils_of_cells(mesh, local, cell, walked, coordinates)
    return _finished(field, probes, mesh, others, stencil, metric)


def mean_error(field: ReferenceField, located: LocatedSet) -> float:
    """The set's mean error over every point, the probes' zeros included, summed as metric.mean_placement_error."""
    errors = np.zeros(field.point_count)
    errors[located.others] = located.errors
    return float(np.mean(errors))
