"""The flat-tetrahedron rule: relative to each tetrahedron's own edges, so fine grids keep their tetrahedra."""

from __future__ import annotations

import numpy as np

from lpnn.quality.metric.tet_geometry import orient_and_invert
from lpnn.quality.metric.triangulation import HULL, corners_of_faces, tetrahedralize


def test_a_cell_sized_tetrahedron_of_a_very_fine_grid_is_kept_and_a_flat_one_dropped() -> None:
    """Local frame of extent 1 with 100,000 cells along x: a one-cell tetrahedron has 6 x volume 1e-15."""
    h = 1e-5
    points = np.array([[0, 0, 0], [h, 0, 0], [0, h, 0], [0, 0, h], [h, h, 0], [1, 0, 0]], dtype=np.float64)
    tets, _, volume6, kept = orient_and_invert(points, np.array([[0, 1, 2, 3], [0, 1, 2, 4]]))
    assert kept.tolist() == [True, False]  # the second is four points of one plane
    np.testing.assert_allclose(volume6, [h**3], rtol=1e-9)


def test_a_grid_far_finer_than_46000_cells_per_axis_tetrahedralises() -> None:
    """Probes one cell apart at one end of a 100,000-cell-long set, plus one at the far end."""
    near = np.array([[i, j, k] for i in range(2) for j in range(2) for k in range(2)], dtype=np.float64)
    world = np.vstack([near, [[100_000.0, 0.5, 0.5]]])
    mesh = tetrahedralize(world)
    assert np.isin(np.arange(len(world)), mesh.tets).all()
    inside = np.abs(np.linalg.det(np.stack([mesh.points[mesh.tets[:, m]] - mesh.points[mesh.tets[:, 0]]
                                            for m in (1, 2, 3)], axis=2)))
    assert inside.sum() > 0.0


def test_the_hull_test_against_every_point_answers_as_against_the_hull_vertices() -> None:
    """on_hull(every_point=True) (a derived mesh's few opened faces) gives on_hull's answers: the boundary faces of a
    lattice with its centre removed and refilled are hull faces, and faces through the inside (every tetrahedron face
    of a random cloud) are not, unless they are on the hull."""
    from lpnn.quality.metric.triangulation import on_hull

    rng = np.random.default_rng(5)
    lattice = np.array([[i, j, k] for i in range(4) for j in range(4) for k in range(3)], dtype=np.float64)
    cloud = rng.normal(size=(300, 3)) * [3.0, 1.0, 0.2] + 1e4  # flat and far from the origin
    for points in (lattice, cloud):
        mesh = tetrahedralize(points)
        faces = np.concatenate([mesh.hull_faces, mesh.tets[:, [1, 2, 3]], mesh.tets[:, [0, 3, 2]]])
        expected = on_hull(mesh.points, faces)
        assert np.array_equal(on_hull(mesh.points, faces, every_point=True), expected)
        assert expected[:mesh.hull_faces.shape[0]].all() and not expected.all()


def test_the_corners_of_flagged_faces_are_every_vertex_of_each_face() -> None:
    """A tetrahedron with two hull faces puts all four of its vertices on the hull (each face holds the three vertices
    other than the one it is opposite); a masked in-place `|=` over repeated rows would keep only the last face's."""
    tets = np.array([[10, 11, 12, 13], [20, 21, 22, 23]])
    faces = np.array([[True, True, False, False], [False, False, False, True]])
    assert sorted(set(corners_of_faces(tets, faces).tolist())) == [10, 11, 12, 13, 20, 21, 22]
    assert corners_of_faces(tets, np.zeros((2, 4), dtype=bool)).shape == (0,)


def test_a_single_tetrahedron_has_every_vertex_on_its_hull() -> None:
    mesh = tetrahedralize(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]))
    assert sorted(set(corners_of_faces(mesh.tets, mesh.neighbours == HULL).tolist())) == [0, 1, 2, 3]
