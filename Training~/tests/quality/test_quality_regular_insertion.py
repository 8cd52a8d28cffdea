"""Tetrahedra derived by inserting points (metric/regular_insertion.py, its exact signs, placement/insertion_tetrahedra.py):
the set Qhull's tie-broken tetrahedralisation gives, numbered alike, wherever the derivation is not refused."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.metric import exact_predicates
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.metric.regular_insertion import inserted_tetrahedra
from lpnn.quality.metric.regular_predicates import UNDECIDED_FRACTION, orient, orient_sign
from lpnn.quality.metric.triangulation import Frame, tetrahedralize, tetrahedralized_from
from lpnn.quality.placement import insertion_tetrahedra as module
from lpnn.quality.placement.insertion import InsertionOrder
from lpnn.quality.placement.insertion_tetrahedra import MAX_RESYNCS, with_vertices_reordered
from lpnn.quality.placement.leak_aware import leak_repaired, leak_repaired_with_mesh

from quality_support import WALLED, box_grid, room_capture


def _derived_and_qhulls(world: np.ndarray, first: int, capacity: int | None = None):
    """The tetrahedralisation of all of `world` derived from that of its first `first` rows, and Qhull's."""
    frame = Frame.for_points(world)
    ids = np.arange(world.shape[0])
    start = tetrahedralize(world[:first], frame, ids[:first])
    local = frame.to_local(world)
    tets, refusal = inserted_tetrahedra(start, local, frame.tie_heights(world), np.arange(first, world.shape[0]),
                                        capacity)
    assert refusal is None, refusal
    return tetrahedralized_from(frame, world, local, tets, ids), tetrahedralize(world, frame, ids)


def _lattice(spacing: float, offset: float, seed: int) -> np.ndarray:
    """A 9 x 8 x 6 lattice in random order, stored in float32 as captures store positions (a lattice's ties: points on
    shared faces and cospherical sets, which only the tie heights break)."""
    world = box_grid(9, 8, 6, spacing) + offset
    return world.astype(np.float32).astype(np.float64)[np.random.default_rng(seed).permutation(world.shape[0])]


@pytest.mark.parametrize("spacing, offset", [(1.0, 0.0), (1e-4, 0.0), (1e4, 0.0), (0.5, 1e4), (1.626, -3.3e3)])
def test_a_lattice_grown_by_insertion_has_qhulls_tetrahedra_at_any_scale_and_far_from_the_origin(spacing: float,
                                                                                               offset: float) -> None:
    world = _lattice(spacing, offset, seed=4)
    for first in (5, 40):  # nearly every point outside the first hull, then most of them
        derived, qhull = _derived_and_qhulls(world, first)
        np.testing.assert_array_equal(derived.tets, qhull.tets)
        np.testing.assert_array_equal(derived.neighbours, qhull.neighbours)


@pytest.mark.parametrize("capacity", [None, 1])  # 1: the structure grows from the starting mesh's own size
def test_a_random_cloud_grown_from_its_middle_outwards_has_qhulls_tetrahedra(capacity: int | None) -> None:
    rng = np.random.default_rng(7)
    world = rng.normal(size=(1500, 3))
    world = world[np.argsort(np.linalg.norm(world, axis=1))]  # every new point outside the hull so far
    derived, qhull = _derived_and_qhulls(world, 20, capacity)
    np.testing.assert_array_equal(derived.tets, qhull.tets)


@pytest.mark.parametrize("order, message", [(np.array([5, 6]), "each new position"),
                                            (np.array([4, 4, 5, 6, 7]), "each new position")])
def test_bad_insertion_orders_are_refused_by_name(order: np.ndarray, message: str) -> None:
    world = np.random.default_rng(0).random((8, 3))
    frame = Frame.for_points(world)
    start = tetrahedralize(world[:4], frame, np.arange(4))
    with pytest.raises(ValueError, match=message):
        inserted_tetrahedra(start, frame.to_local(world), frame.tie_heights(world), order)


def test_a_starting_hull_that_is_not_exactly_convex_is_refused_and_growing_from_fewer_points_gives_qhulls() -> None:
    """Qhull's tetrahedra of 300 of these float32 lattice points have a hull vertex beyond another hull face's plane (by
    rounding, checked exactly here): not a regular triangulation to grow. Grown from 5 points instead, the whole set's
    tetrahedra are Qhull's again."""
    world = _lattice(1.626, -3.3e3, seed=4)
    frame = Frame.for_points(world)
    start = tetrahedralize(world[:300], frame, np.arange(300))
    local = frame.to_local(world)
    corners = np.unique(start.hull_faces)
    a, b, c = (start.points[start.hull_faces[:, k]] for k in range(3))
    heights = np.einsum("fk,vfk->vf", np.cross(b - a, c - a), start.points[corners][:, None, :] - a[None])
    near = np.argwhere(heights > -1e-9)  # clearly behind every face elsewhere; only these are decided exactly
    beyond = [(f, v) for v, f in near
              if exact_predicates.orient_sign(start.points, *start.hull_faces[f], corners[v]) > 0]
    assert beyond  # hull faces are counter-clockwise seen from outside: > 0 is beyond
    tets, refusal = inserted_tetrahedra(start, local, frame.tie_heights(world), np.arange(300, world.shape[0]))
    assert tets is None and refusal == "the starting hull not convex"
    derived, qhull = _derived_and_qhulls(world, 5)
    np.testing.assert_array_equal(derived.tets, qhull.tets)


def test_a_crack_in_the_starting_tetrahedra_is_refused_not_derived() -> None:
    world = _lattice(1.0, 0.0, seed=1)[:200]
    frame = Frame.for_points(world)
    start = tetrahedralize(world[:100], frame, np.arange(100))
    cracked = type(start)(**{**start.__dict__, "neighbours": np.where(start.neighbours == start.neighbours.max(), -2,
                                                                       start.neighbours)})
    tets, refusal = inserted_tetrahedra(cracked, frame.to_local(world), frame.tie_heights(world), np.arange(100, 200))
    assert tets is None and "closed manifold" in refusal


def _integer_det(rows: list[list[int]]) -> int:
    """Leibniz's formula in Python integers (or rationals): an exact determinant computed independently of exact_predicates."""
    size = len(rows)
    total = 0
    for permutation in itertools.permutations(range(size)):
        inversions = sum(1 for i in range(size) for j in range(i + 1, size) if permutation[i] > permutation[j])
        product = 1
        for r, c in enumerate(permutation):
            product *= rows[r][c]
        total += -product if inversions % 2 else product
    return total


def _sign(value: int) -> int:
    return (value > 0) - (value < 0)


def test_signs_the_doubles_cannot_decide_are_exact() -> None:
    """Points on a tilted plane or one unit of 2^-45 off it, coordinates up to 2^44 units (exact doubles, but their
    products are not): the double evaluation is within its rounding bound, and the sign comes from the exact path."""
    unit = 2.0 ** -45
    rng = np.random.default_rng(3)
    for _ in range(40):
        b, c = rng.integers(-2**44, 2**44, 3), rng.integers(-2**44, 2**44, 3)
        d = b + c + rng.integers(-1, 2, 3) * np.array([0, 0, 1])  # on the plane of 0, b, c, or one unit off it
        points = np.array([[0, 0, 0], b, c, d], dtype=np.int64)
        local = points.astype(np.float64) * unit
        det, permanent = orient(local, 0, 1, 2, 3)
        assert abs(det) <= UNDECIDED_FRACTION * permanent  # undecided in double
        expected = _sign(_integer_det([list(map(int, points[k] - points[0])) for k in (1, 2, 3)]))
        assert orient_sign(local, 0, 1, 2, 3) == expected == exact_predicates.orient_sign(local, 0, 1, 2, 3)


def test_the_exact_power_sign_is_the_integer_determinants() -> None:
    """Lifted rows (q - p, |q - p|^2 + h(q) - h(p)) of integer coordinates and heights: the exact sign equals the
    integer determinant's, cospherical ties (0) included."""
    rng = np.random.default_rng(5)
    cube = np.array(list(itertools.product([0, 2], repeat=3)), dtype=np.int64)
    for trial in range(60):
        points = cube[rng.choice(8, 5, replace=False)] if trial % 2 else rng.integers(-6, 7, (5, 3))
        heights = np.zeros(5, dtype=np.int64) if trial % 3 == 0 else rng.integers(-2, 3, 5)
        rows = [list(map(int, points[q] - points[4])) + [int(((points[q] - points[4]) ** 2).sum() + heights[q]
                                                           - heights[4])] for q in range(4)]
        assert exact_predicates.power_sign(points.astype(np.float64), heights.astype(np.float64), 0, 1, 2, 3, 4) == \
            _sign(_integer_det(rows))


def test_the_exact_power_circle_sign_is_the_integer_determinants() -> None:
    """power_in_plane_sign's rows (q - a, lifted) for q = b, c, p and the plane's normal, in integers: the sign of the
    integer determinant, points in one tilted plane (inside, on and outside the power circle)."""
    rng = np.random.default_rng(6)
    u, v = np.array([1, 2, 0]), np.array([0, 1, 3])  # the plane spanned by u and v through a
    for _ in range(60):
        a = rng.integers(-5, 6, 3)
        points = np.array([a + i * u + j * v for i, j in rng.integers(-3, 4, (4, 2))], dtype=np.int64)
        heights = rng.integers(-2, 3, 4)
        rows = []
        for q in (1, 2, 3):
            d = points[q] - points[0]
            rows.append(list(map(int, d)) + [int((d ** 2).sum() + heights[q] - heights[0])])
        normal = np.cross(points[1] - points[0], points[2] - points[0])
        rows.append(list(map(int, normal)) + [0])
        assert exact_predicates.power_in_plane_sign(points.astype(np.float64), heights.astype(np.float64),
                                                    0, 1, 2, 3) == _sign(_integer_det(rows))


def _fraction_rows(local: np.ndarray, height: np.ndarray, rows: list[int], o: int) -> list[list[Fraction]]:
    origin = [Fraction(float(v)) for v in local[o]]
    lifted = []
    for q in rows:
        delta = [Fraction(float(v)) - origin[k] for k, v in enumerate(local[q])]
        lifted.append(delta + [sum(d * d for d in delta) + Fraction(float(height[q])) - Fraction(float(height[o]))])
    return lifted


def test_the_exact_signs_of_doubles_of_every_scale_are_the_rational_determinants() -> None:
    """Every sign equals the determinant's in Python's rationals, where the common power of two (2^K on coordinates,
    2^2K on tie heights) is set by the coordinates (exponents 2^-60 to 2^20), or by the heights alone (integer
    coordinates, heights of odd exponents down to 2^-79), and at true ties: a point in the plane of three others, five
    corners of a cube on one sphere with equal heights, a square in a tilted plane on its own circle."""
    rng = np.random.default_rng(11)

    def dyadic(shape: tuple[int, ...], lowest: int = -60) -> np.ndarray:
        return rng.integers(-2**20, 2**20, shape).astype(np.float64) * 2.0 ** rng.integers(lowest, 1, shape)

    cube = np.array(list(itertools.product([0, 2], repeat=3)), dtype=np.float64)
    u, v = np.array([1.0, 2.0, 2.0]), np.array([2.0, 1.0, -2.0])  # perpendicular, both of length 3
    ties = {"orient": 0, "power": 0, "circle": 0}
    for trial in range(240):
        kind = trial % 4
        local, heights = dyadic((5, 3)), dyadic((5,)) if trial % 8 < 4 else np.zeros(5)
        if kind == 1:  # integer coordinates: the heights alone set K
            local = rng.integers(-50, 51, (5, 3)).astype(np.float64)
            heights = rng.integers(-2**20, 2**20, 5).astype(np.float64) * 2.0 ** -rng.choice(np.arange(1, 80, 2), 5)
        elif kind == 2:  # five corners of a cube (one sphere), equal heights: a power tie
            scale = 2.0 ** int(rng.integers(-40, 10))
            local = cube[rng.choice(8, 5, replace=False)] * scale + dyadic((1, 3))
            heights = np.full(5, float(dyadic((1,))[0]))
        elif kind == 3:  # a square in a tilted plane, then a fifth point: in-plane and orientation ties
            scale = 2.0 ** int(rng.integers(-40, 10))
            corner = dyadic((3,))
            local = np.array([corner, corner + scale * u, corner + scale * v, corner + scale * (u + v),
                              corner + scale * 2 * u], dtype=np.float64)
            heights = np.full(5, float(dyadic((1,))[0]))
        orient = _sign(_integer_det([[Fraction(float(value)) - Fraction(float(local[0, k])) for k, value in
                                      enumerate(local[q])] for q in (1, 2, 3)]))
        assert exact_predicates.orient_sign(local, 0, 1, 2, 3) == orient
        power = _sign(_integer_det(_fraction_rows(local, heights, [0, 1, 2, 3], 4)))
        assert exact_predicates.power_sign(local, heights, 0, 1, 2, 3, 4) == power
        m = _fraction_rows(local, heights, [1, 2, 3], 0)
        m.append([m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2],
                  m[0][0] * m[1][1] - m[0][1] * m[1][0], Fraction(0)])
        circle = _sign(_integer_det(m))
        assert exact_predicates.power_in_plane_sign(local, heights, 0, 1, 2, 3) == circle
        ties["orient"] += orient == 0
        ties["power"] += power == 0
        ties["circle"] += circle == 0
    assert min(ties.values()) >= 20, ties  # the ties really occur


def test_reordered_vertices_are_what_tetrahedralize_gives_the_reordered_points() -> None:
    world = _lattice(0.5, 10.0, seed=2)[:200]
    frame = Frame.for_points(world)
    ids = np.random.default_rng(0).permutation(5000)[:200]  # point indices in no particular order
    mesh = tetrahedralize(world, frame, ids)
    order = np.argsort(ids)
    again = tetrahedralize(world[order], frame, ids[order])
    reordered = with_vertices_reordered(mesh, order)
    for name in ("world", "points", "tets", "neighbours", "inverse", "hull_faces", "hull_face_tets"):
        np.testing.assert_array_equal(getattr(reordered, name), getattr(again, name), err_msg=name)


def _field_and_grid(capture: Capture) -> tuple[ReferenceField, EvaluationGrid]:
    return ReferenceField.from_capture(capture), EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)


def test_an_orders_rounds_are_derived_after_one_check_and_rank_as_qhulls_rounds(medium_capture: Capture) -> None:
    field, grid = _field_and_grid(medium_capture)
    derived = InsertionOrder(field, grid)
    tetrahedralised = InsertionOrder(field, grid)
    tetrahedralised.tetrahedra.derive = False
    np.testing.assert_array_equal(derived.prefix(500), tetrahedralised.prefix(500))
    made = derived.tetrahedra
    assert made.derived >= 20 and made.tetrahedralised == 1 and made.agrees and made.resyncs == 0 and not made.refusals
    assert tetrahedralised.tetrahedra.derived == 0
    seed = derived.selection()(300)
    before = made.derived
    np.testing.assert_array_equal(derived.mesh_of(seed).tets, tetrahedralize(field.world[seed], field.frame, seed).tets)
    assert made.derived == before + 1 and not made.refusals  # derived, not Qhull's
    with pytest.raises(ValueError, match="sorted"):
        derived.mesh_of(seed[::-1])


def test_a_derivation_that_differs_takes_qhulls_answer_and_after_three_every_round_is_qhulls(
        monkeypatch, medium_capture: Capture) -> None:
    field, grid = _field_and_grid(medium_capture)
    real = module.inserted_tetrahedra
    monkeypatch.setattr(module, "inserted_tetrahedra", lambda *a: (real(*a)[0][1:], None))  # one tetrahedron short
    order = InsertionOrder(field, grid)
    reference = InsertionOrder(field, grid)
    reference.tetrahedra.derive = False
    np.testing.assert_array_equal(order.prefix(400), reference.prefix(400))  # every round Qhull's
    made = order.tetrahedra
    assert made.resyncs == MAX_RESYNCS and made.derived == 0 and not made.agrees
    assert made.tetrahedralised == reference.tetrahedra.tetrahedralised  # one call a round: the check's answer is used


def test_a_refused_round_is_tetrahedralised_and_the_next_derives_again(monkeypatch, medium_capture: Capture) -> None:
    field, grid = _field_and_grid(medium_capture)
    real = module.inserted_tetrahedra
    calls = []

    def every_third_refused(*arguments):
        calls.append(1)
        return (None, "refused for the test") if len(calls) % 3 == 0 else real(*arguments)

    monkeypatch.setattr(module, "inserted_tetrahedra", every_third_refused)
    order = InsertionOrder(field, grid)
    reference = InsertionOrder(field, grid)
    reference.tetrahedra.derive = False
    np.testing.assert_array_equal(order.prefix(500), reference.prefix(500))
    made = order.tetrahedra
    assert made.refusals and all(r == "refused for the test" for r in made.refusals)
    assert made.derived == len(calls) - len(made.refusals) and made.derived > 10


def test_the_leak_repair_with_derived_tetrahedra_keeps_the_same_probes_and_gives_their_tetrahedra() -> None:
    capture = room_capture(2, (8.0, 2.5, 3.0), 0.5)
    field, grid = _field_and_grid(capture)
    order = InsertionOrder(field, grid)
    seed = order.selection()(60)
    plain = leak_repaired(field, seed, WALLED, rounds=3)
    seed_mesh = order.mesh_of(seed)
    before = order.tetrahedra.derived
    repaired, mesh = leak_repaired_with_mesh(field, seed, WALLED, rounds=3, mesh=seed_mesh, tetrahedra=order.tetrahedra)
    assert plain.shape[0] > seed.shape[0]  # the wall makes leaks to repair
    assert order.tetrahedra.derived > before and not order.tetrahedra.refusals  # the repair's rounds derived
    np.testing.assert_array_equal(repaired, plain)
    np.testing.assert_array_equal(mesh.tets, tetrahedralize(field.world[plain], field.frame, plain).tets)
