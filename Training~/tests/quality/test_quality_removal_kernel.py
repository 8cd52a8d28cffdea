"""The compiled passes of a mesh derived after a removal (metric/removal_kernel.py) against the numpy expressions they
replace; the whole derived mesh against one assembled afresh is test_quality_trial_fills.py's."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.metric import removal_kernel
from lpnn.quality.metric.tet_geometry import OPPOSITE
from lpnn.quality.metric.triangulation import (HULL, INNER_BOUNDARY, VERTEX_KEY_BITS, _face_pairs, face_keys, on_hull,
                                               tetrahedralize)



@pytest.fixture(scope="module")
def cloud_mesh():
    rng = np.random.default_rng(3)
    return tetrahedralize(rng.normal(size=(400, 3)) * [2.0, 1.0, 0.5] + 5e3)


def _pair_set(first: np.ndarray, second: np.ndarray) -> set[tuple[int, int]]:
    return {(min(a, b), max(a, b)) for a, b in zip(first.tolist(), second.tolist())}


def test_hashed_face_pairs_are_the_sorted_keys_pairs(cloud_mesh) -> None:
    """Every face of every tetrahedron, shuffled: the hash table pairs exactly the faces the sort pairs, each
    interior face once, and a face listed in a third tetrahedron is refused."""
    tets = cloud_mesh.tets
    positions = np.random.default_rng(1).permutation(4 * tets.shape[0]).astype(np.int64)
    first, second, ok = removal_kernel.paired_faces(tets, positions, VERTEX_KEY_BITS)
    assert ok
    expected = _face_pairs(face_keys(tets[:, OPPOSITE].reshape(-1, 3)[positions], cloud_mesh.point_count))
    assert _pair_set(positions[first], positions[second]) == _pair_set(positions[expected[0]], positions[expected[1]])
    assert len(first) == np.count_nonzero(cloud_mesh.neighbours >= 0) // 2
    tripled = np.concatenate([tets, tets[:1]])
    everything = np.arange(4 * tripled.shape[0], dtype=np.int64)
    assert not removal_kernel.paired_faces(tripled, everything, VERTEX_KEY_BITS)[2]


def test_the_kept_rows_are_copied_renumbered_and_their_lost_faces_listed(cloud_mesh) -> None:
    """copy_kept against the numpy expressions it replaces: vertices through the map, transforms kept, neighbours
    renumbered (HULL where the tetrahedron across went, the old marker where there was none), the opened faces."""
    mesh = cloud_mesh
    removed_vertex = np.zeros(mesh.point_count, dtype=bool)
    removed_vertex[[5, 77, 140, 300]] = True
    keep = np.empty(mesh.tets.shape[0], dtype=bool)
    kept_count = removal_kernel.kept_tetrahedra(mesh.tets, removed_vertex, keep)
    np.testing.assert_array_equal(keep, ~removed_vertex[mesh.tets].any(axis=1))
    vertex_map = np.full(mesh.point_count, -1, dtype=np.int64)
    vertex_map[~removed_vertex] = np.arange(np.count_nonzero(~removed_vertex))
    marked = mesh.neighbours.copy()
    marked[np.flatnonzero(keep)[3], 0] = INNER_BOUNDARY  # a crack's marker is kept as it is
    tets = np.empty((kept_count, 4), dtype=np.int64)
    neighbours = np.empty((kept_count, 4), dtype=np.int64)
    inverse = np.empty((kept_count, 3, 3))
    was_hull = np.zeros(4 * kept_count, dtype=bool)
    opened = np.empty(4 * kept_count, dtype=np.int64)
    count, bad = removal_kernel.copy_kept(mesh.tets, marked, mesh.inverse, keep, vertex_map, HULL, tets, neighbours,
                                          inverse, was_hull, opened)
    assert not bad
    kept = np.flatnonzero(keep)
    renumbered = np.full(mesh.tets.shape[0] + 1, -1, dtype=np.int64)
    renumbered[kept] = np.arange(kept.shape[0])
    before = marked[kept]
    expected = np.where(before >= 0, renumbered[np.where(before >= 0, before, -1)], before)
    np.testing.assert_array_equal(tets, vertex_map[mesh.tets[kept]])
    np.testing.assert_array_equal(inverse, mesh.inverse[kept])
    np.testing.assert_array_equal(neighbours, expected)
    np.testing.assert_array_equal(was_hull, (before == HULL).reshape(-1))
    np.testing.assert_array_equal(opened[:count], np.flatnonzero(((before >= 0) & (expected < 0)).reshape(-1)))
    assert count > 0 and INNER_BOUNDARY in neighbours
    # A kept row whose vertex the map calls removed is reported.
    assert removal_kernel.copy_kept(mesh.tets, marked, mesh.inverse, keep, np.full_like(vertex_map, -1), HULL, tets,
                                    neighbours, inverse, was_hull, opened)[1]


def test_faces_boundary_vertices_used_and_markers_counted_as_numpy_does(cloud_mesh) -> None:
    mesh = cloud_mesh
    positions = np.array([0, 3, 6, 4 * mesh.tets.shape[0] - 1], dtype=np.int64)
    np.testing.assert_array_equal(removal_kernel.face_vertices(mesh.tets, positions),
                                  mesh.tets[:, OPPOSITE].reshape(-1, 3)[positions])
    boundary = removal_kernel.boundary_faces(mesh.neighbours)
    np.testing.assert_array_equal(boundary, np.flatnonzero(mesh.neighbours < 0))
    np.testing.assert_array_equal(removal_kernel.face_vertices(mesh.tets, boundary), mesh.hull_faces)
    assert removal_kernel.count_marker(mesh.neighbours, HULL) == np.count_nonzero(mesh.neighbours == HULL) > 0
    assert removal_kernel.uses_every_vertex(mesh.tets, mesh.point_count)
    assert not removal_kernel.uses_every_vertex(mesh.tets, mesh.point_count + 1)


def test_the_hull_built_of_the_boundary_corners_alone_answers_as_the_whole_hull(cloud_mesh) -> None:
    """on_hull(outer=corners of the boundary faces): every hull vertex is one, so the same answers, on hull faces and
    on faces through the inside."""
    mesh = cloud_mesh
    faces = np.concatenate([mesh.hull_faces, mesh.tets[:, [1, 2, 3]], mesh.tets[:, [0, 3, 2]]])
    outer = np.unique(mesh.hull_faces)
    assert outer.shape[0] < mesh.point_count
    expected = on_hull(mesh.points, faces)
    np.testing.assert_array_equal(on_hull(mesh.points, faces, outer=outer), expected)
    assert expected[:mesh.hull_faces.shape[0]].all() and not expected.all()
