"""Point location finds a point inside the hull wherever its walk starts (quality.md §1 "Inside the hull", "Ties").

A tetrahedralisation can have a crack: faces no tetrahedron shares inside the hull, where a flat tetrahedron was dropped
(triangulation.py; five float32 lattice points of a ramp on ctf_compromise). A walk reaching such a face from the wrong
side used to conclude "outside" (the point then took a hull triangle metres away) or, for a point on the crack, settle
its tie among the tetrahedra of one side only; the metric's coherent walk, starting where the previous point's ended,
met it far more often than a walk from the nearest centroid. Expected cells come from an independent numpy statement of
the rule over every tetrahedron, not from the compiled kernels.
"""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.metric import location
from lpnn.quality.metric.tet_geometry import orient_and_invert
from lpnn.quality.metric.triangulation import HULL, INNER_BOUNDARY, Frame, assembled, tetrahedralize

# A square a b c d at z = 0 between an apex e above and a pyramid below (apex f, inner vertex g). Above, the square is
# cut along a-c; below, along b-d: the flat tetrahedron a b c d that would join the two sides is missing (the crack).
SQUARE_AND_APEXES = np.array([
    [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],  # a b c d
    [0.5, 0.5, 1.0],  # e
    [0.5, 0.5, -1.0],  # f
    [0.5, 0.5, -0.4],  # g, inside the lower pyramid
])
A, B, C, D, E, F, G = range(7)
ABOVE = [[A, B, C, E], [A, C, D, E]]
BELOW = [[A, B, D, G], [B, C, D, G], [A, B, F, G], [B, C, F, G], [C, D, F, G], [D, A, F, G]]


def _crack_mesh():
    world = SQUARE_AND_APEXES * 4.0 + np.array([10.0, 2.0, -3.0])
    frame = Frame.for_points(world)
    tets, _, _, kept = orient_and_invert(frame.to_local(world), np.array(ABOVE + BELOW))
    assert kept.all()
    return assembled(world, frame, tets)


def _rule(tri, query: np.ndarray) -> np.ndarray:
    """quality.md §1 over every tetrahedron: the one a point is clearly inside (smallest coordinate > tolerance), else
    the lowest-index one it is inside within the tolerance, else -1 (outside)."""
    tolerance = location.INSIDE_TOLERANCE
    cell = np.empty(query.shape[0], dtype=np.int64)
    every = np.arange(tri.tets.shape[0])[None, :]
    for rows in np.array_split(np.arange(query.shape[0]), max(1, query.shape[0] * tri.tets.shape[0] // 2_000_000)):
        smallest = location.barycentric(tri, every, query[rows, None, :]).min(axis=2)  # (rows, T)
        clear = smallest > tolerance
        candidate = smallest >= -tolerance
        cell[rows] = np.where(clear.any(axis=1), np.argmax(clear, axis=1),
                              np.where(candidate.any(axis=1), np.argmax(candidate, axis=1), -1))
    return cell


def test_the_faces_of_a_crack_are_inner_boundary_and_the_rest_of_the_surface_hull() -> None:
    tri = _crack_mesh()
    inner = np.argwhere(tri.neighbours == INNER_BOUNDARY)
    assert inner.shape[0] == 4  # a-b-c and a-c-d above, a-b-d and b-c-d below
    crack_faces = {tuple(sorted(set(tri.tets[t].tolist()) - {int(tri.tets[t, face])})) for t, face in inner}
    assert crack_faces == {(A, B, C), (A, C, D), (A, B, D), (B, C, D)}
    assert np.count_nonzero(tri.neighbours == HULL) == 8  # the 4 sides of each pyramid


@pytest.fixture()
def walk_always(monkeypatch):
    """Small queries are settled by the brute force; these must take the walk."""
    monkeypatch.setattr(location, "BRUTE_FORCE_PAIRS", 0)


ABOVE_THE_SQUARE = [0.3, 0.6, 0.5]  # in a-c-d-e
BELOW_THE_SQUARE = [0.8, 0.6, -0.1]  # in b-c-d-g


@pytest.mark.parametrize("previous", [ABOVE_THE_SQUARE, BELOW_THE_SQUARE])
@pytest.mark.parametrize("coherent", [True, False])
def test_a_point_on_an_interior_edge_beyond_a_crack_is_inside_from_any_previous_point(walk_always, previous,
                                                                                      coherent: bool) -> None:
    """The point lies on the interior edge g-f (shared by the four lower side tetrahedra), a quarter of the way from g;
    walked from above, the walk meets the crack first (it used to return "outside")."""
    tri = _crack_mesh()
    on_edge = 0.75 * SQUARE_AND_APEXES[G] + 0.25 * SQUARE_AND_APEXES[F]
    query = tri.frame.to_local(np.array([previous, on_edge]) * 4.0 + np.array([10.0, 2.0, -3.0]))
    cell, _, _ = location.locate_cells(tri, query, coherent)
    sharing_the_edge = [t for t in range(tri.tets.shape[0]) if {F, G} <= set(tri.tets[t].tolist())]
    assert len(sharing_the_edge) == 4
    assert cell[1] == min(sharing_the_edge) == _rule(tri, query)[1]
    stencil = location.locate_local(tri, query, coherent)
    assert not stencil.outside[1]
    weights = dict(zip(stencil.vertices[1].tolist(), stencil.weights[1].tolist()))
    assert weights[G] == pytest.approx(0.75, abs=1e-12) and weights[F] == pytest.approx(0.25, abs=1e-12)


@pytest.mark.parametrize("previous", [ABOVE_THE_SQUARE, BELOW_THE_SQUARE])
@pytest.mark.parametrize("coherent", [True, False])
def test_a_point_on_the_crack_gets_the_lowest_index_tetrahedron_of_both_sides(walk_always, previous,
                                                                             coherent: bool) -> None:
    """A point of the square's diagonal a-c lies in both tetrahedra above and in a-b-d-g below: the lowest index of
    all three, wherever the walk arrives from (a tie search from below used to see the lower side only)."""
    tri = _crack_mesh()
    on_crack = 0.75 * SQUARE_AND_APEXES[A] + 0.25 * SQUARE_AND_APEXES[C]
    query = tri.frame.to_local(np.array([previous, on_crack]) * 4.0 + np.array([10.0, 2.0, -3.0]))
    cell, _, _ = location.locate_cells(tri, query, coherent)
    assert cell[1] == _rule(tri, query)[1] == 0  # a-b-c-e, listed first


def _lattice(counts, spacing: float) -> np.ndarray:
    """Lattice points (N, 3) in grid order (x fastest), as captures list them."""
    k, j, i = np.meshgrid(*(np.arange(n) for n in counts[::-1]), indexing="ij")
    return np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1) * spacing


def _float32(world: np.ndarray) -> np.ndarray:
    return world.astype(np.float32).astype(np.float64)


def _point_set(kind: str, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Probe positions and query points (grid order where there is a grid) of one kind of set."""
    rng = np.random.default_rng(seed)
    offset = rng.uniform(-100.0, 100.0, 3)
    if kind == "random":
        probes = rng.uniform(0.0, 10.0, (300, 3))
        return probes, _lattice((21, 21, 21), 0.55) - 0.5
    if kind == "lattice":  # float32 capture positions (cell 1.6256 as ctf_compromise), half of them probes
        grid = _float32(_lattice((8, 6, 7), 1.6256) + offset)
        probes = np.sort(rng.choice(grid.shape[0], grid.shape[0] // 2, replace=False))
        return grid[probes], np.delete(grid, probes, axis=0)
    if kind == "ramp":
        # A lattice sheared along x as sloped floors are: float32 rounding puts its points within Qhull's precision of
        # one sphere, the source of cracks. Queries: the half-cell lattice (on the probes' edges and faces) around it.
        slope = [0.125, 0.25, 1.0 / 3.0, 0.5][seed % 4]
        counts = tuple(int(n) for n in rng.integers(5, 9, 3))
        probes, points = _lattice(counts, 1.6256), _lattice(tuple(2 * n + 1 for n in counts), 0.8128) - 0.8128 / 2
        for grid in (probes, points):
            grid[:, 1] += slope * grid[:, 0]
        return _float32(probes + offset), _float32(points + offset)
    if kind == "coplanar":  # three planes of scattered probes; queries on a lattice through and around them
        probes = np.concatenate([np.column_stack([rng.uniform(0, 8, (60, 2)), np.full(60, z)]) for z in (0.0, 2.0, 4.0)])
        return probes + offset, _lattice((17, 17, 11), 0.5) - 0.25 + offset
    if kind == "cospherical":  # two concentric spheres and their centre
        directions = rng.normal(size=(160, 3))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
        probes = np.concatenate([directions * 5.0, directions[:60] * 2.5, [[0.0, 0.0, 0.0]]])
        return probes + offset, _lattice((15, 15, 15), 0.75) - 5.25 + offset
    raise ValueError(kind)


@pytest.mark.parametrize("kind,seed", [(kind, seed) for kind in ("random", "lattice", "coplanar", "cospherical")
                                       for seed in (1, 2)] + [("ramp", seed) for seed in range(8)])
def test_coherent_and_nearest_start_locations_agree_with_the_rule(walk_always, kind: str, seed: int) -> None:
    probes, points = _point_set(kind, seed)
    tri = tetrahedralize(probes)
    query = np.ascontiguousarray(tri.frame.to_local(points))
    expected = _rule(tri, query)
    coherent = location.locate_local(tri, query, coherent=True)
    nearest = location.locate_local(tri, query, coherent=False)
    np.testing.assert_array_equal(coherent.cell[expected >= 0], expected[expected >= 0])
    np.testing.assert_array_equal(coherent.outside, expected < 0)
    np.testing.assert_array_equal(coherent.cell, nearest.cell)
    np.testing.assert_array_equal(coherent.weights, nearest.weights)
    assert np.count_nonzero(expected >= 0) > 0 and np.count_nonzero(expected < 0) > 0


@pytest.mark.parametrize("kind,seed", [("random", 3), ("lattice", 3), ("coplanar", 3), ("cospherical", 3)]
                         + [("ramp", seed) for seed in range(8)])
def test_walks_from_given_starts_give_the_rule_s_stencils(walk_always, kind: str, seed: int) -> None:
    """A caller's starts (batched refinement's refills) change no cell, weight or projection, wherever they are: here
    random tetrahedra, far from most points."""
    probes, points = _point_set(kind, seed)
    tri = tetrahedralize(probes)
    query = np.ascontiguousarray(tri.frame.to_local(points))
    expected = _rule(tri, query)
    start = np.random.default_rng(seed).integers(0, tri.tets.shape[0], query.shape[0])
    started = location.locate_local(tri, query, start=start)
    coherent = location.locate_local(tri, query, coherent=True)
    np.testing.assert_array_equal(started.cell[expected >= 0], expected[expected >= 0])
    np.testing.assert_array_equal(started.outside, expected < 0)
    for name in ("cell", "vertices", "weights", "anchor"):
        np.testing.assert_array_equal(getattr(started, name), getattr(coherent, name), err_msg=name)


def test_walk_starts_must_be_one_tetrahedron_per_point(walk_always) -> None:
    tri = _crack_mesh()
    query = tri.frame.to_local(np.array([ABOVE_THE_SQUARE, BELOW_THE_SQUARE]) * 4.0 + np.array([10.0, 2.0, -3.0]))
    with pytest.raises(ValueError, match="one tetrahedron per point"):
        location.locate_local(tri, query, start=np.zeros(3, dtype=np.int64))
    with pytest.raises(ValueError, match="outside the 8 tetrahedra"):
        location.locate_local(tri, query, start=np.array([0, 8]))
    with pytest.raises(ValueError, match="outside the 8 tetrahedra"):
        location.locate_local(tri, query, start=np.array([-1, 0]))


def test_walk_starts_are_checked_where_the_brute_force_decides_too() -> None:
    """Small problems skip the walk; a bad start is still an error, not ignored."""
    tri = _crack_mesh()
    query = tri.frame.to_local(np.array([ABOVE_THE_SQUARE, BELOW_THE_SQUARE]) * 4.0 + np.array([10.0, 2.0, -3.0]))
    assert query.shape[0] * tri.tets.shape[0] <= location.BRUTE_FORCE_PAIRS
    with pytest.raises(ValueError, match="outside the 8 tetrahedra"):
        location.locate_local(tri, query, start=np.array([0, 9]))


def test_the_ramps_of_the_property_test_have_cracks() -> None:
    """The ramp sets above exercise cracks (else they would test nothing new)."""
    cracked = [seed for seed in range(8) if np.any(tetrahedralize(_point_set("ramp", seed)[0]).neighbours == INNER_BOUNDARY)]
    assert len(cracked) >= 2
