"""The compiled nearest-triangle loop (hull_kernel.py) gives the numpy formulation's numbers bit for bit: on points
around a lattice's hull (projections onto faces, edges and vertices; ties between triangles sharing them) and on
random triangles (every region of Ericson's test), with and without a mask of allowed triangles; and so does its tie
rule (quality.md §1 "Ties"), against a numpy formulation over every hull triangle."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.metric.hull_projection import (HULL_TIE, PROJECTION_TOLERANCE, SMALL_HULL_FACES, WHOLE_SEARCH_PAIRS,
                                                  HullIndex,
                                                 _is_projection, _nearest_among, every_triangle, lowest_owner_at_ties,
                                                 project_to_hull)
from lpnn.quality.metric import hull_projection, location
from lpnn.quality.metric.triangulation import tetrahedralize


def _safe_ratio(numerator, denominator):
    return numerator / np.where(denominator != 0.0, denominator, 1.0)


def _numpy_closest(p, a, b, c):
    """Ericson RTCD §5.1.5 over whole arrays: the numpy code the compiled loop replaced."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.sum(ab * ap, axis=-1), np.sum(ac * ap, axis=-1)
    bp = p - b
    d3, d4 = np.sum(ab * bp, axis=-1), np.sum(ac * bp, axis=-1)
    cp = p - c
    d5, d6 = np.sum(ab * cp, axis=-1), np.sum(ac * cp, axis=-1)
    vc, vb, va = d1 * d4 - d3 * d2, d5 * d2 - d1 * d6, d3 * d6 - d5 * d4
    conditions = [(d1 <= 0.0) & (d2 <= 0.0), (d3 >= 0.0) & (d4 <= d3), (vc <= 0.0) & (d1 >= 0.0) & (d3 <= 0.0),
                  (d6 >= 0.0) & (d5 <= d6), (vb <= 0.0) & (d2 >= 0.0) & (d6 <= 0.0),
                  (va <= 0.0) & ((d4 - d3) >= 0.0) & ((d5 - d6) >= 0.0)]
    t_ab, t_ac = _safe_ratio(d1, d1 - d3), _safe_ratio(d2, d2 - d6)
    t_bc = _safe_ratio(d4 - d3, (d4 - d3) + (d5 - d6))
    total = va + vb + vc
    v_face, w_face = _safe_ratio(vb, total), _safe_ratio(vc, total)
    zero, one = np.zeros_like(d1), np.ones_like(d1)
    u = np.select(conditions, [one, zero, 1.0 - t_ab, zero, 1.0 - t_ac, zero], 1.0 - v_face - w_face)
    v = np.select(conditions, [zero, one, t_ab, zero, zero, 1.0 - t_bc], v_face)
    w = np.select(conditions, [zero, zero, zero, one, t_ac, t_bc], w_face)
    weights = np.clip(np.stack([u, v, w], axis=-1), 0.0, None)
    return weights / np.sum(weights, axis=-1, keepdims=True)


def _numpy_nearest_among(query, corners, candidates, allowed):
    tri = corners[candidates]  # (m, k, 3, 3)
    p = query[:, None, :]
    weights = _numpy_closest(p, tri[:, :, 0], tri[:, :, 1], tri[:, :, 2])
    anchor = np.einsum("rkv,rkvx->rkx", weights, tri)
    distance = np.sqrt(np.sum((anchor - p) ** 2, axis=-1))
    if allowed is not None:
        distance = np.where(allowed[candidates], distance, np.inf)
    pick = np.argmin(distance, axis=1)
    row = np.arange(query.shape[0])
    return candidates[row, pick], weights[row, pick], anchor[row, pick], distance[row, pick]


def _assert_same(expected, actual):
    for e, a in zip(expected, actual):
        np.testing.assert_array_equal(a, e)


@pytest.mark.parametrize("masked", [False, True])
def test_kernel_equals_numpy_around_a_lattice_hull(masked: bool) -> None:
    axes = [np.arange(4.0), np.arange(3.0), np.arange(3.0)]
    probes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    tri = tetrahedralize(probes)
    corners = tri.points[tri.hull_faces]
    rng = np.random.default_rng(11)
    # Lattice-aligned points outside: projections land exactly on shared edges and vertices (ties between triangles).
    outside = np.stack(np.meshgrid(np.arange(-2.0, 6.0), np.arange(-2.0, 5.0), np.arange(-2.0, 5.0),
                                   indexing="ij"), axis=-1).reshape(-1, 3)
    query = tri.frame.to_local(np.concatenate([outside, rng.uniform(-3.0, 6.0, (500, 3))]))
    every = np.broadcast_to(np.arange(corners.shape[0]), (query.shape[0], corners.shape[0]))
    allowed = rng.uniform(size=corners.shape[0]) < 0.7 if masked else None
    _assert_same(_numpy_nearest_among(query, corners, every, allowed), _nearest_among(query, corners, every, allowed))


def test_kernel_equals_numpy_on_random_triangles_in_every_region() -> None:
    rng = np.random.default_rng(5)
    corners = rng.normal(size=(40, 3, 3))
    corners[0, 2] = corners[0, 1]  # a degenerate triangle (two equal corners): the guarded ratios
    query = rng.normal(scale=2.0, size=(3000, 3))
    candidates = rng.integers(0, corners.shape[0], size=(query.shape[0], 6))
    _assert_same(_numpy_nearest_among(query, corners, candidates, None),
                 _nearest_among(query, corners, candidates, None))


def test_no_allowed_candidate_gives_an_infinite_distance_and_the_first_candidate() -> None:
    corners = np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0.0, 0, 1], [1, 0, 1], [0, 1, 1]]])
    face, _, _, distance = _nearest_among(np.array([[0.2, 0.2, 3.0]]), corners, np.array([[1, 0]]),
                                          np.array([False, False]))
    assert face.tolist() == [1] and np.isinf(distance[0])


def test_projection_onto_a_box_is_the_clamped_point() -> None:
    """Independent of both formulations: the nearest point of the box [0, 2]^3 is the point clamped to it."""
    axes = np.arange(3.0)
    probes = np.stack(np.meshgrid(axes, axes, axes, indexing="ij"), axis=-1).reshape(-1, 3)
    tri = tetrahedralize(probes)
    query = np.random.default_rng(2).uniform(-3.0, 5.0, (2000, 3))
    query = query[np.any((query < 0.0) | (query > 2.0), axis=1)]
    projection = project_to_hull(tri.points, tri.hull_faces, tri.frame.to_local(query))
    np.testing.assert_allclose(tri.frame.to_world(projection.anchor), np.clip(query, 0.0, 2.0), atol=1e-12)


def test_the_certificate_accepts_exactly_the_nearest_hull_points() -> None:
    """hull_kernel.certified against the supporting-plane test in numpy: true nearest points of a box's hull pass,
    points moved off them along the surface fail, infinite distances fail."""
    axes = np.arange(3.0)
    probes = np.stack(np.meshgrid(axes, axes, axes, indexing="ij"), axis=-1).reshape(-1, 3)
    tri = tetrahedralize(probes)
    rng = np.random.default_rng(6)
    query = tri.frame.to_local(rng.uniform(-3.0, 5.0, (3000, 3)))
    query = query[np.any((query < tri.points.min(axis=0)) | (query > tri.points.max(axis=0)), axis=1)]
    nearest = np.clip(query, tri.points.min(axis=0), tri.points.max(axis=0))
    shifted = nearest + rng.normal(scale=0.05, size=nearest.shape) * (nearest != query)  # off the true projection
    shifted = np.clip(shifted, tri.points.min(axis=0), tri.points.max(axis=0))
    vertices = tri.points[np.unique(tri.hull_faces)]
    for anchor in (nearest, shifted):
        distance = np.linalg.norm(query - anchor, axis=1)
        r = query - anchor
        reach = r @ vertices.T - np.sum(r * anchor, axis=1)[:, None]
        expected = reach.max(axis=1) <= PROJECTION_TOLERANCE * distance + 1e-15
        np.testing.assert_array_equal(_is_projection(query, anchor, distance, vertices), expected)
    assert _is_projection(query, nearest, np.linalg.norm(query - nearest, axis=1), vertices).all()
    assert not _is_projection(query[:1], nearest[:1], np.array([np.inf]), vertices)[0]


def _numpy_ties(points, faces, owners, query, projection):
    """hull_projection.lowest_owner_at_ties over every hull triangle at once (no prefilter, no ring): the tie set (within a
    relative HULL_TIE of the nearest distance), its lowest owner (then smallest sorted corners), the nearest point
    snapped onto the corners of the nearest triangle that every tied triangle holds (one: that vertex; two: the edge,
    its ends by probe index; three: no tie; none: the chosen triangle's own weights)."""
    m, h = query.shape[0], faces.shape[0]
    every = np.broadcast_to(np.arange(h), (m, h))
    tri = points[faces][every]  # (m, h, 3, 3)
    p = query[:, None, :]
    weights = _numpy_closest(p, tri[:, :, 0], tri[:, :, 1], tri[:, :, 2])
    anchor = np.einsum("rkv,rkvx->rkx", weights, tri)
    distance = np.sqrt(np.sum((anchor - p) ** 2, axis=-1))
    tied = distance <= projection.distance[:, None] * (1.0 + HULL_TIE)
    ordered = np.sort(faces, axis=1)
    rank = np.empty(h, dtype=np.int64)
    rank[np.lexsort((ordered[:, 2], ordered[:, 1], ordered[:, 0], owners))] = np.arange(h)
    chosen = np.argmin(np.where(tied, rank[None, :], h), axis=1)
    nearest_corners = faces[projection.face]  # (m, 3)
    holds = (faces[None, :, :, None] == nearest_corners[:, None, None, :]).any(axis=2)  # (m, h, 3)
    held = np.all(holds | ~tied[:, :, None], axis=1)  # (m, 3): corners of the nearest triangle every tied one holds
    common = held.sum(axis=1)
    row = np.arange(m)
    own = weights[row, chosen]
    on_common = (faces[chosen][:, :, None] == np.where(held, nearest_corners, -1)[:, None, :]).any(axis=2)  # (m, 3)
    first = np.argmax(on_common, axis=1)
    second = 2 - np.argmax(on_common[:, ::-1], axis=1)
    swap = faces[chosen, second] < faces[chosen, first]
    first, second = np.where(swap, second, first), np.where(swap, first, second)
    start, end = points[faces[chosen, first]], points[faces[chosen, second]]
    edge = end - start
    t = np.clip(_safe_ratio(np.sum((query - start) * edge, axis=-1), np.sum(edge * edge, axis=-1)), 0.0, 1.0)
    snapped = np.zeros((m, 3))
    snapped[row, first] = np.where(common == 1, 1.0, 1.0 - t)
    snapped[row, second] += np.where(common == 1, 0.0, t)
    result = np.where((common == 0)[:, None], own, snapped)
    result = np.where((common == 3)[:, None], projection.weights, result)
    face = np.where(common == 3, projection.face, chosen)
    corners = points[faces[face]]
    result_anchor = np.einsum("rv,rvx->rx", result, corners)
    result_distance = np.sqrt(np.sum((result_anchor - query) ** 2, axis=-1))
    keep = common == 3
    result_anchor[keep], result_distance[keep] = projection.anchor[keep], projection.distance[keep]
    return face, result, result_anchor, result_distance


@pytest.mark.parametrize("offset, cell", [(0.0, 0.5), (-2300.6, 0.85), (1000.37, 0.3)])
def test_ties_go_to_the_lowest_owner_snapped_as_numpy_finds_them_over_every_triangle(offset: float, cell: float) -> None:
    """The hull of 40 points of a lattice, and the lattice's other points outside it (and random ones): near the origin
    nearest points fall exactly on shared edges and vertices; in float32 far from the origin the corners bend the hull by
    their rounding, and nearest points fall a hair off an edge, where the distances differ by about their rounding. The
    kernel's choice and weights are the numpy formulation's, which looks at every hull triangle, so the kernel's
    prefilter and its search around the nearest triangle's corners miss no tie."""
    axes = [np.arange(9.0), np.arange(8.0), np.arange(6.0)]
    lattice = offset + cell * np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    lattice = lattice.astype(np.float32).astype(np.float64)
    rng = np.random.default_rng(3)
    probes = rng.choice(lattice.shape[0], 40, replace=False)
    tri = tetrahedralize(lattice[probes])
    others = np.delete(lattice, probes, axis=0)
    query = tri.frame.to_local(np.concatenate([others, offset + rng.uniform(-cell, 9.0 * cell, (300, 3))]))
    query = query[location.locate_cells(tri, np.ascontiguousarray(query))[0] < 0]
    plain = HullIndex(tri.points, tri.hull_faces).nearest(query)
    ruled = lowest_owner_at_ties(tri.points, tri.hull_faces, tri.hull_face_tets, query, plain)
    expected = _numpy_ties(tri.points, tri.hull_faces, tri.hull_face_tets, query, plain)
    _assert_same(expected, (ruled.face, ruled.weights, ruled.anchor, ruled.distance))
    assert np.count_nonzero(tri.hull_face_tets[ruled.face] != tri.hull_face_tets[plain.face]) > 0  # ties decided
    snapped = np.abs(ruled.distance - plain.distance)
    assert np.all(snapped <= 1e-9 * plain.distance)
    assert offset == 0.0 or np.count_nonzero(snapped) > 0  # near-ties snapped onto their edge or vertex


@pytest.mark.parametrize("offset, cell", [(0.0, 0.5), (-2300.6, 0.85)])
def test_small_hulls_searched_whole_give_the_tree_searchs_answer(offset: float, cell: float) -> None:
    """A hull of at most SMALL_HULL_FACES triangles is searched whole (every_triangle) instead of through the centroid
    tree and the certificate: after the tie rule both give the same triangle, weights, anchor and distance bit for bit,
    for lattice points (many nearest points exactly on a shared edge or vertex, where the raw searches pick different
    triangles of equal distance) and random ones far outside."""
    axes = [np.arange(12.0), np.arange(10.0), np.arange(7.0)]
    lattice = offset + cell * np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    lattice = lattice.astype(np.float32).astype(np.float64)
    rng = np.random.default_rng(11)
    probes = rng.choice(lattice.shape[0], 9, replace=False)
    tri = tetrahedralize(lattice[probes])
    assert 4 <= tri.hull_faces.shape[0] <= SMALL_HULL_FACES
    others = np.delete(lattice, probes, axis=0)
    query = tri.frame.to_local(np.concatenate([others, offset + rng.uniform(-20 * cell, 30 * cell, (500, 3))]))
    query = np.ascontiguousarray(query[location.locate_cells(tri, np.ascontiguousarray(query))[0] < 0])
    tree = HullIndex(tri.points, tri.hull_faces).nearest(query)
    whole = every_triangle(tri.points, tri.hull_faces, query)
    assert np.count_nonzero(whole.face != tree.face) > 0  # exact ties: the raw searches differ
    expected = lowest_owner_at_ties(tri.points, tri.hull_faces, tri.hull_face_tets, query, tree)
    actual = project_to_hull(tri.points, tri.hull_faces, query, owners=tri.hull_face_tets)
    _assert_same((expected.face, expected.weights, expected.anchor, expected.distance),
                 (actual.face, actual.weights, actual.anchor, actual.distance))


def test_few_points_outside_a_larger_hull_are_searched_whole_with_the_tree_searchs_answer(monkeypatch) -> None:
    """Fewer than WHOLE_SEARCH_PAIRS point-triangle pairs outside a hull of more than SMALL_HULL_FACES triangles (a
    refinement round's few points outside) are searched whole too: after the tie rule the same triangle, weights, anchor
    and distance as the centroid tree's, bit for bit, on lattice points with exact ties."""
    axes = [np.arange(14.0), np.arange(11.0), np.arange(8.0)]
    lattice = 0.5 * np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    rng = np.random.default_rng(5)
    probes = rng.choice(lattice.shape[0], 60, replace=False)
    tri = tetrahedralize(lattice[probes])
    faces = tri.hull_faces.shape[0]
    assert faces > SMALL_HULL_FACES
    query = tri.frame.to_local(np.delete(lattice, probes, axis=0))
    query = np.ascontiguousarray(query[location.locate_cells(tri, np.ascontiguousarray(query))[0] < 0])
    query = query[:WHOLE_SEARCH_PAIRS // faces]
    assert query.shape[0] >= 20
    tree = HullIndex(tri.points, tri.hull_faces).nearest(query)
    whole = every_triangle(tri.points, tri.hull_faces, query)
    assert np.count_nonzero(whole.face != tree.face) > 0  # exact ties: the raw searches differ
    expected = lowest_owner_at_ties(tri.points, tri.hull_faces, tri.hull_face_tets, query, tree)
    searched_whole = []
    monkeypatch.setattr(hull_projection, "every_triangle",
                        lambda *args: searched_whole.append(1) or every_triangle(*args))
    actual = project_to_hull(tri.points, tri.hull_faces, query, owners=tri.hull_face_tets)
    assert searched_whole == [1]
    _assert_same((expected.face, expected.weights, expected.anchor, expected.distance),
                 (actual.face, actual.weights, actual.anchor, actual.distance))
