"""The compiled metric and walk (metric_kernel.py) give the numpy formulas' numbers bit for bit:
the placement errors and the cells a walk reaches, on a lattice (points on shared faces and edges,
where the tie rule of quality.md §1 decides) and on jittered points (no ties)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from lpnn.core import sh as shmath
from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.grid import EvaluationGrid
from lpnn.core.spread import spread_ranking
from lpnn.quality.metric import location
from lpnn.quality.metric.hull_projection import project_to_hull
from lpnn.quality.metric.metric_kernel import PARALLEL_ROWS, chunk_count
from lpnn.quality.metric.metric import POINT_ERRORS, ReferenceField, point_errors, probe_stencil, stencil_point_errors
from lpnn.quality.placement.policies import prefix_selection
from lpnn.quality.metric.triangulation import HULL, tetrahedralize


def _numpy_tie_rule(tri, query, cell):
    """quality.md §1 "Ties" over every tetrahedron at once: a point whose smallest coordinate in `cell` is within the
    inside tolerance of 0 belongs to the tetrahedron it is clearly inside if any, else to the lowest-index one it is
    inside within the tolerance (the walk's boundary_owner searches only the faces around it)."""
    tolerance = location.INSIDE_TOLERANCE
    rows = np.flatnonzero(cell >= 0)
    rows = rows[np.abs(location.barycentric(tri, cell[rows], query[rows]).min(axis=1)) <= tolerance]
    ruled = cell.copy()
    every = np.arange(tri.tets.shape[0])[None, :]
    for part in np.array_split(rows, max(1, rows.shape[0] // 64)):  # (rows, T, 4) coordinates, a slice at a time
        smallest = location.barycentric(tri, every, query[part, None, :]).min(axis=2)
        clear = smallest > tolerance
        lowest = np.argmax(smallest >= -tolerance, axis=1)
        ruled[part] = np.where(clear.any(axis=1), np.argmax(clear, axis=1), lowest)
    return ruled


def _numpy_walk(tri, query):
    """location._walk as numpy passes over every active point (the code the compiled walk replaced), then the tie
    rule."""
    centroids = tri.points[tri.tets].mean(axis=1)
    cell = np.asarray(cKDTree(centroids).query(query, k=1)[1], dtype=np.int64).reshape(-1)
    result = np.full(query.shape[0], -1, dtype=np.int64)
    resolved = np.zeros(query.shape[0], dtype=bool)
    active = np.arange(query.shape[0])
    for _ in range(location.WALK_STEP_LIMIT):
        if active.shape[0] == 0:
            break
        lam = location.barycentric(tri, cell[active], query[active])
        worst = np.argmin(lam, axis=1)
        inside = lam[np.arange(active.shape[0]), worst] >= -location.INSIDE_TOLERANCE
        result[active[inside]] = cell[active[inside]]
        resolved[active[inside]] = True
        moving = active[~inside]
        step = tri.neighbours[cell[moving], worst[~inside]]
        resolved[moving[step == HULL]] = True  # through a crack (INNER_BOUNDARY): left to the brute force
        cell[moving] = step
        active = moving[step >= 0]
    return _numpy_tie_rule(tri, query, result), resolved


def _numpy_errors(field, indices, others, stencil, metric):
    values = field.values(metric)
    errors = np.zeros(field.point_count)
    interpolated = shmath.blend(values[indices], stencil.vertices, stencil.weights)
    errors[others] = POINT_ERRORS[metric](interpolated, values[others], field.scale)
    return errors


@pytest.fixture(scope="module", params=["lattice", "jittered"])
def scene(request):
    capture = AnalyticScene.random(7, cell_size=0.25, room_size=(4.0, 2.5, 3.0)).capture(name="room")  # ~8,000 points
    positions = capture.positions.astype(np.float64)
    if request.param == "jittered":
        positions = positions + np.random.default_rng(3).uniform(-0.05, 0.05, positions.shape)
    field = ReferenceField.from_sh(positions, capture.sh, capture.lighting_scale)
    scores = np.random.default_rng(5).uniform(size=capture.point_count)
    ranking = spread_ranking(positions.astype(np.float32), scores)
    return field, prefix_selection(EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids), ranking)


@pytest.mark.parametrize("count", [6, 60, 600, 3000])
def test_the_compiled_walk_reaches_the_numpy_walks_cells(scene, count: int) -> None:
    field, select = scene
    tri = tetrahedralize(field.world[select(count)], field.frame)
    expected = _numpy_walk(tri, field.local)
    actual = location._walk(tri, field.local)
    np.testing.assert_array_equal(actual[0], expected[0])
    np.testing.assert_array_equal(actual[1], expected[1])
    inside = np.flatnonzero(expected[0] >= 0)  # the walk's last coordinates are `barycentric`'s
    np.testing.assert_array_equal(actual[2][inside], location.barycentric(tri, expected[0][inside], field.local[inside]))
    if count == 6:  # a hull of few probes: some points are walked out of it
        assert np.count_nonzero(expected[0] < 0) > 0


def test_the_walk_in_parallel_slices_reaches_each_points_cell(scene) -> None:
    """metric_kernel.walk runs chunk_count's slices in parallel, each coherent slice from its own first point's nearest
    centroid: every point's cell is still the numpy walk's, in every mode (the tie rule makes it start-independent)."""
    field, select = scene
    tri = tetrahedralize(field.world[select(600)], field.frame)
    copies = 3 * PARALLEL_ROWS // field.point_count + 1  # every point several times, in both orders
    query = np.ascontiguousarray(np.concatenate([field.local[::(-1) ** k] for k in range(copies)]))
    assert chunk_count(query.shape[0]) >= 3
    expected = _numpy_walk(tri, query)
    inside = np.flatnonzero(expected[0] >= 0)
    # Starts given in runs (batched refinement's refill starts: the points of one star in a row), each run's walks
    # continuing from the previous point's cell.
    runs = np.repeat(np.random.default_rng(5).integers(0, tri.tets.shape[0], query.shape[0] // 7 + 1), 7)
    for coherent, start in ((False, None), (True, None), (False, runs[:query.shape[0]])):
        cell, resolved, coordinates = location._walk(tri, query, coherent, start)
        np.testing.assert_array_equal(cell, expected[0])
        np.testing.assert_array_equal(resolved, expected[1])
        np.testing.assert_array_equal(coordinates[inside], location.barycentric(tri, expected[0][inside], query[inside]))


@pytest.mark.parametrize("count", [5, 90, 2000])
def test_the_compiled_errors_equal_the_numpy_formulas(scene, count: int) -> None:
    field, select = scene
    indices, others, stencil = probe_stencil(field, select(count))
    for metric in ("irradiance", "smape"):
        expected = _numpy_errors(field, indices, others, stencil, metric)
        np.testing.assert_array_equal(stencil_point_errors(field, indices, others, stencil, metric), expected)


@pytest.mark.parametrize("count", [6, 90, 2000])
def test_the_coherent_walk_finds_the_same_stencils(scene, count: int) -> None:
    # point_errors walks each point from where the previous one ended (location.locate_local's coherent walk): the
    # same tetrahedron, weights and errors, points on shared faces and edges included (the tie rule, quality.md §1).
    # ~8,000 points make one parallel slice, so the coherent walk starts from nearest_centroids (location.FEW_STARTS)
    # and the other from the k-d tree.
    field, select = scene
    indices, others, nearest = probe_stencil(field, select(count))
    _, _, coherent = probe_stencil(field, indices, coherent=True)
    np.testing.assert_array_equal(coherent.cell, nearest.cell)
    np.testing.assert_array_equal(coherent.outside, nearest.outside)
    np.testing.assert_array_equal(coherent.weights, nearest.weights)
    for metric in ("irradiance", "smape"):
        np.testing.assert_array_equal(point_errors(field, indices, metric),
                                      _numpy_errors(field, indices, others, nearest, metric))


def test_einsum_sums_three_products_as_the_walk_does() -> None:
    # The walk's barycentric step relies on einsum's order for a 3-term contraction, (a0 + a2) + a1.
    rng = np.random.default_rng(0)
    inverse, d = rng.normal(size=(20_000, 3, 3)), rng.normal(size=(20_000, 3))
    a = inverse * d[:, None, :]
    np.testing.assert_array_equal(np.einsum("...ij,...j->...i", inverse, d), (a[..., 0] + a[..., 2]) + a[..., 1])


def _numpy_most_inside(tri, query):
    """location._brute_force as numpy passes over every point-tetrahedron pair (the code the compiled loop replaced),
    then the tie rule."""
    lam = location.barycentric(tri, np.arange(tri.tets.shape[0])[None, :], query[:, None, :])  # (M, T, 4)
    smallest = lam.min(axis=2)
    pick = np.argmax(smallest, axis=1)
    largest = smallest[np.arange(query.shape[0]), pick]
    return _numpy_tie_rule(tri, query, np.where(largest >= -location.INSIDE_TOLERANCE, pick, -1)), largest


@pytest.mark.parametrize("jitter", [0.0, 0.3])
def test_compiled_brute_force_equals_numpy(jitter: float) -> None:
    """On lattice probes and points (ties between tetrahedra sharing faces and edges) and jittered ones, inside and
    outside the hull: the same tetrahedron and the same smallest coordinate, bit for bit."""
    rng = np.random.default_rng(9)
    axes = np.arange(4.0)
    probes = np.stack(np.meshgrid(axes, axes[:3], axes[:3], indexing="ij"), axis=-1).reshape(-1, 3)
    probes = probes + rng.uniform(-jitter, jitter, probes.shape) * 0.3
    tri = tetrahedralize(probes)
    grid_points = np.stack(np.meshgrid(np.arange(-1.0, 4.5, 0.5), np.arange(-1.0, 3.5, 0.5), np.arange(-1.0, 3.5, 0.5),
                                       indexing="ij"), axis=-1).reshape(-1, 3)
    query = tri.frame.to_local(np.concatenate([grid_points, rng.uniform(-1.0, 4.0, (400, 3))]))
    expected_cell, expected_min = _numpy_most_inside(tri, query)
    cell, smallest = location._brute_force(tri, query)
    inside = expected_cell >= 0
    every = location.barycentric(tri, np.arange(tri.tets.shape[0])[None, :], query[inside, None, :]).min(axis=2)
    shared = np.count_nonzero(every >= -location.INSIDE_TOLERANCE, axis=1) > 1  # inside several: the rule decides
    assert jitter > 0.0 or np.count_nonzero(shared) > 0
    np.testing.assert_array_equal(cell[inside], expected_cell[inside])
    np.testing.assert_array_equal(smallest, expected_min)


@pytest.mark.parametrize("coherent", [False, True])
def test_compiled_stencils_equal_numpy(scene, coherent: bool) -> None:
    """locate_local's inside stencils (metric_kernel.inside_stencils) are the numpy formulation's: the walk's cell and
    coordinates (the brute force's recomputed with `barycentric`), clamped to >= 0 and normalised, bit for bit."""
    field, select = scene
    probes = select(300)
    tri = tetrahedralize(field.world[probes], field.frame)
    query = np.ascontiguousarray(field.local[np.setdiff1d(np.arange(field.point_count), probes)])
    cell, walked, coordinates = location._walk(tri, query, coherent)
    stencil = location.locate_local(tri, query, coherent)
    inside = np.flatnonzero(cell >= 0)
    lam = np.clip(coordinates[inside], 0.0, None)
    np.testing.assert_array_equal(stencil.weights[inside], lam / lam.sum(axis=1, keepdims=True))
    np.testing.assert_array_equal(stencil.vertices[inside], tri.tets[cell[inside]])
    # The brute force's rows (a small query): coordinates from `barycentric`.
    few = query[:40]
    small = location.locate_local(tri, few)
    best, smallest = location._brute_force(tri, few)
    rows = np.flatnonzero(smallest >= -location.INSIDE_TOLERANCE)
    lam = np.clip(location.barycentric(tri, best[rows], few[rows]), 0.0, None)
    np.testing.assert_array_equal(small.weights[rows], lam / lam.sum(axis=1, keepdims=True))


def test_compiled_outside_stencils_equal_numpy(scene) -> None:
    """locate_local's stencils outside the hull (metric_kernel.outside_stencils) are the numpy formulation they
    replaced: the projection's triangle and weights, the owning tetrahedron's fourth vertex with weight 0, that
    tetrahedron as the cell and the projection's anchor."""
    field, _ = scene
    probes = np.sort(np.random.default_rng(2).choice(field.point_count, 60, replace=False))  # corners left outside
    tri = tetrahedralize(field.world[probes], field.frame)
    query = np.ascontiguousarray(field.local[np.setdiff1d(np.arange(field.point_count), probes)])
    stencil = location.locate_local(tri, query)
    far = np.flatnonzero(stencil.outside)
    assert far.shape[0] > 0
    projection = project_to_hull(tri.points, tri.hull_faces, query[far], owners=tri.hull_face_tets)
    owner = tri.hull_face_tets[projection.face]
    corners = tri.hull_faces[projection.face]
    owner_vertices = tri.tets[owner]
    fourth = owner_vertices[~(owner_vertices[:, :, None] == corners[:, None, :]).any(axis=2)].reshape(-1)
    np.testing.assert_array_equal(stencil.vertices[far], np.concatenate([corners, fourth[:, None]], axis=1))
    np.testing.assert_array_equal(stencil.weights[far], np.concatenate([projection.weights, np.zeros((far.shape[0], 1))],
                                                                       axis=1))
    np.testing.assert_array_equal(stencil.cell[far], owner)
    np.testing.assert_array_equal(stencil.anchor[far], projection.anchor)


@pytest.mark.parametrize("queries", [1, 17, 64])
def test_a_few_walk_starts_are_the_nearest_centroids_a_k_d_tree_finds(queries: int) -> None:
    """location.FEW_STARTS: one compiled pass over the tetrahedra instead of a k-d tree over their centroids; the same
    nearest distances (a tie may pick another tetrahedron, which the walk's tie rule makes irrelevant)."""
    from lpnn.quality.metric.metric_kernel import nearest_centroids

    rng = np.random.default_rng(queries)
    tri = tetrahedralize(rng.random((300, 3)) * [4.0, 2.0, 3.0] + 1.0e5)
    query = rng.random((queries, 3)) * 1.2 - 0.1
    found = np.full(queries, -1, dtype=np.int64)
    nearest_centroids(tri.points, tri.tets, query, found)
    centroids = tri.points[tri.tets].mean(axis=1)
    distance, _ = cKDTree(centroids).query(query, k=1)
    np.testing.assert_allclose(np.linalg.norm(centroids[found] - query, axis=1), distance, rtol=1e-12, atol=1e-15)

