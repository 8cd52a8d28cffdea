"""Rays (Embree) against synthetic geometry, which faces are geometry, and the solid test."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.features import Raycaster
from lpnn.scenes.bsp import read_bsp
from lpnn.scenes.coords import METRES_PER_UNIT, quake_to_unity
from lpnn.scenes.errors import BspError
from lpnn.scenes.raycast import RAYS_PER_CHUNK, EmbreeRaycaster
from lpnn.scenes.raycast_kernel import bad_rays
from lpnn.scenes.solid import ON_PLANE, POINTS_PER_CHUNK, SolidTester
from lpnn.scenes.surfaces import ray_geometry, select_ray_faces
from synthetic_bsp import make_level

QUAD = np.array([[-1, -1, 5], [1, -1, 5], [1, 1, 5], [-1, 1, 5]], dtype=float)
QUAD_TRIANGLES = np.array([[0, 1, 2], [0, 2, 3]])


def unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# ------------------------------------------------------------------------------------------- rays

def test_raycaster_implements_the_feature_protocol() -> None:
    assert isinstance(EmbreeRaycaster(QUAD, QUAD_TRIANGLES), Raycaster)


@pytest.mark.parametrize("offset", [0.0, 1000.0])
def test_quad_hits_at_the_analytic_distance_from_both_sides(offset: float) -> None:
    caster = EmbreeRaycaster(QUAD + offset, QUAD_TRIANGLES)
    origins = np.array([[0.2, 0.3, 0], [0.2, 0.3, 10], [0, 0, 0], [0.2, 0.3, 0], [0, 0, 0]]) + offset
    directions = unit([[0, 0, 1], [0, 0, -1], [1, 1, 10], [0, 0, -1], [1, 0, 0]])
    distances, normals = caster.cast(origins, directions, 50.0)
    expected = [5.0, 5.0, 5.0 * np.sqrt(102) / 10, np.inf, np.inf]
    assert np.allclose(distances[:3], expected[:3], rtol=0, atol=2e-4 * (1 + offset / 100))
    assert np.isinf(distances[3:]).all()
    assert np.allclose(np.abs(normals[:3]), [[0, 0, 1]] * 3)
    assert np.all(normals[3:] == 0.0)


def test_hits_beyond_max_distance_are_misses() -> None:
    caster = EmbreeRaycaster(QUAD, QUAD_TRIANGLES)
    distances, normals = caster.cast(np.zeros((2, 3)), unit([[0, 0, 1], [0, 0, 1]]), 4.999)
    assert np.isinf(distances).all() and np.all(normals == 0)
    distances, _ = caster.cast(np.zeros((1, 3)), unit([[0, 0, 1]]), 5.001)
    assert np.isclose(distances[0], 5.0)


def test_threaded_chunks_give_the_same_answer_as_one_thread() -> None:
    rng = np.random.default_rng(0)
    count = 2 * RAYS_PER_CHUNK + 123
    origins = rng.uniform(-1, 1, size=(count, 3)) * [1, 1, 3]
    directions = unit(rng.normal(size=(count, 3)))
    one = EmbreeRaycaster(QUAD, QUAD_TRIANGLES, threads=1).cast(origins, directions, 20.0)
    two = EmbreeRaycaster(QUAD, QUAD_TRIANGLES, threads=2).cast(origins, directions, 20.0)
    assert np.array_equal(one[0], two[0]) and np.array_equal(one[1], two[1])
    assert 0 < np.isfinite(one[0]).mean() < 1


def test_bad_rays_are_refused_and_empty_geometry_misses() -> None:
    caster = EmbreeRaycaster(QUAD, QUAD_TRIANGLES)
    with pytest.raises(ValueError, match="unit vectors"):
        caster.cast(np.zeros((1, 3)), np.array([[0, 0, 2.0]]), 1.0)
    with pytest.raises(ValueError, match="non-finite origin"):
        caster.cast(np.array([[np.nan, 0, 0]]), np.array([[0, 0, 1.0]]), 1.0)
    empty = EmbreeRaycaster(np.zeros((0, 3)), np.zeros((0, 3), dtype=int))
    distances, normals = empty.cast(np.zeros((2, 3)), unit([[0, 0, 1], [1, 0, 0]]), 10.0)
    assert np.isinf(distances).all() and normals.shape == (2, 3)


def test_the_compiled_ray_check_refuses_the_rays_numpys_check_refuses() -> None:
    """raycast_kernel.bad_rays against numpy's formulas: non-finite origins, directions off unit length by more than
    1e-6 (either side of the border, NaN and inf included), counted and the first of each named."""
    rng = np.random.default_rng(11)
    origins = rng.uniform(-1e4, 1e4, size=(5000, 3))
    directions = unit(rng.normal(size=(5000, 3)))
    origins[[17, 900, 4000], [0, 2, 1]] = [np.nan, np.inf, -np.inf]
    directions[[5, 6, 7, 3000]] *= np.array([1.0 + 2e-6, 1.0 - 2e-6, 1.0 + 5e-7, 0.0])[:, None]
    directions[[8, 9]] = [[np.nan, 0.0, 1.0], [np.inf, 0.0, 0.0]]
    bad_origin = ~np.isfinite(origins).all(axis=1)
    not_unit = ~(np.abs(np.linalg.norm(directions, axis=1) - 1.0) <= 1e-6)
    expected = (int(bad_origin.sum()), int(np.flatnonzero(bad_origin)[0]), int(not_unit.sum()),
                int(np.flatnonzero(not_unit)[0]))
    assert bad_rays(origins, directions) == expected == (3, 17, 5, 5)
    assert bad_rays(origins[:0], directions[:0]) == (0, -1, 0, -1)
    with pytest.raises(ValueError, match=r"ray 5 has length 1\.00000\d* \(5 such rays\)"):
        EmbreeRaycaster(QUAD, QUAD_TRIANGLES).cast(np.zeros((5000, 3)), directions, 1.0)


def test_each_ray_may_end_at_its_own_distance() -> None:
    caster = EmbreeRaycaster(QUAD, QUAD_TRIANGLES, threads=2)
    rng = np.random.default_rng(1)
    count = RAYS_PER_CHUNK + 77  # two chunks: each must read its own slice of the ends
    origins = rng.uniform(-1, 1, size=(count, 3)) * [1, 1, 3]
    directions = unit(rng.normal(size=(count, 3)))
    ends = rng.uniform(0.0, 12.0, size=count)
    distances, triangles = caster.first_hits(origins, directions, ends)
    assert np.array_equal(caster.first_hit_distances(origins, directions, ends), distances)
    # the answer of each ray alone, cast to its own end (a few rays: one call each)
    for k in rng.choice(count, size=40, replace=False).tolist():
        alone = caster.first_hits(origins[k:k + 1], directions[k:k + 1], float(ends[k]))
        assert alone[0][0] == distances[k] and alone[1][0] == triangles[k]
    # a hit is reported only within the ray's own end
    assert np.all(distances[np.isfinite(distances)] <= ends[np.isfinite(distances)])
    far = caster.first_hits(origins, directions, np.full(count, 12.0))[0]
    cut = np.isfinite(far) & (far > ends)
    assert cut.any() and np.isinf(distances[cut]).all()
    assert np.array_equal(distances[~cut], far[~cut])


@pytest.mark.parametrize("ends, message", [(np.array([1.0, -1.0]), "ray 1's max distance"),
                                           (np.array([np.nan, 1.0]), "ray 0's max distance"),
                                           (np.array([1.0, 2.0, 3.0]), "one per ray"), (-2.0, "must be finite")])
def test_bad_ray_ends_are_refused(ends, message: str) -> None:
    caster = EmbreeRaycaster(QUAD, QUAD_TRIANGLES)
    with pytest.raises(ValueError, match=message):
        caster.first_hits(np.zeros((2, 3)), unit([[0, 0, 1], [0, 0, 1]]), ends)


# ----------------------------------------------------------------------------------- level faces

def test_ray_faces_exclude_sky_translucent_and_billboards(level_bytes: bytes) -> None:
    bsp = read_bsp(level_bytes, "synthetic.bsp")
    selection = select_ray_faces(bsp)
    assert selection.is_geometry.tolist() == [True, False, False, True, False]
    assert selection.excluded == {"billboard": 1, "sky": 1, "nodraw": 0, "translucent or liquid/fog": 1}
    soup = ray_geometry(bsp)
    assert soup.triangle_count == 2 + 2 * 8 * 8  # the opaque quad + the patch at level 8
    assert set(soup.face_of_triangle.tolist()) == {0, 3}


def test_rays_in_unity_metres_against_the_level(level_bytes: bytes) -> None:
    soup = ray_geometry(read_bsp(level_bytes, "synthetic.bsp"))
    caster = EmbreeRaycaster(quake_to_unity(soup.vertices), soup.triangles)
    up = quake_to_unity(np.array([0.0, 0.0, 1.0]), scale=1.0)
    plus_x = quake_to_unity(np.array([1.0, 0.0, 0.0]), scale=1.0)
    origins = quake_to_unity(np.array([[100, 100, 50], [100, 100, 150], [32, 32, 150], [50, 100, 50]], dtype=float))
    directions = np.array([up, up, up, plus_x])
    distances, normals = caster.cast(origins, directions, 500 * METRES_PER_UNIT)
    assert np.allclose(distances[0], 78 * METRES_PER_UNIT, atol=1e-5)  # the opaque quad at z = 128
    assert np.isinf(distances[1])  # only the sky is above: open
    assert np.allclose(distances[2], 10 * METRES_PER_UNIT, atol=1e-5)  # the patch at z = 160
    assert np.isinf(distances[3])  # through the translucent quad at x = 100
    assert np.allclose(np.abs(normals[0]), np.abs(up))


# ------------------------------------------------------------------------------------------ solid

def test_solid_and_outside(level_bytes: bytes) -> None:
    tester = SolidTester(read_bsp(level_bytes, "synthetic.bsp"))
    points = np.array([
        [32, 32, 32],  # inside the cube brush
        [64, 32, 32],  # on its face: surfaces are solid
        [32, 32, 64 + ON_PLANE / 2],  # within the tolerance of its top
        [32, 32, 64 + 2 * ON_PLANE],  # just above it
        [96, 32, 32],  # air
        [200, 32, 32],  # beyond the node plane: cluster -1, outside the map
        [192, 100, 100],  # on the node plane: reaches the outside leaf too
        [191.9, 100, 100],  # air
    ], dtype=float)
    assert tester.solid_or_outside(points).tolist() == [True, True, True, False, False, True, True, False]
    pair_point, pair_leaf = tester.leaves_near(points[[0, 5, 6]])
    assert sorted(zip(pair_point.tolist(), pair_leaf.tolist())) == [(0, 0), (1, 1), (2, 0), (2, 1)]


def test_only_solid_contents_count() -> None:
    level = make_level()
    level.shaders[0] = ("textures/test/water", 0, 0x20)  # the brush becomes water
    tester = SolidTester(read_bsp(level.to_bytes(), "synthetic.bsp"))
    assert tester.solid_or_outside(np.array([[32.0, 32, 32]])).tolist() == [False]


def test_solid_test_is_chunked_and_vectorised(level_bytes: bytes) -> None:
    tester = SolidTester(read_bsp(level_bytes, "synthetic.bsp"))
    rng = np.random.default_rng(5)
    points = rng.uniform(-20, 260, size=(70_000, 3))  # more than one chunk
    expected = ((points <= 64 + ON_PLANE) & (points >= -ON_PLANE)).all(axis=1) | (points[:, 0] >= 192 - ON_PLANE)
    calls = []
    assert np.array_equal(tester.solid_or_outside(points, lambda done, total: calls.append((done, total))), expected)
    assert calls[-1] == (70_000, 70_000) and len(calls) == -(-70_000 // POINTS_PER_CHUNK)


def test_brush_bounds_come_from_the_axial_sides_or_are_infinite() -> None:
    tester = SolidTester(read_bsp(make_level().to_bytes(), "synthetic.bsp"))
    assert tester.brush_mins.tolist() == [[0, 0, 0]] and tester.brush_maxs.tolist() == [[64, 64, 64]]
    level = make_level()
    level.brush_sides = level.brush_sides[::-1]  # not in the compilers' order: no bounds, same answers
    shuffled = SolidTester(read_bsp(level.to_bytes(), "synthetic.bsp"))
    assert np.isinf(shuffled.brush_mins).all() and np.isinf(shuffled.brush_maxs).all()
    points = np.random.default_rng(2).uniform(-20, 100, size=(5000, 3))
    assert np.array_equal(shuffled.solid_or_outside(points), tester.solid_or_outside(points))


def test_a_cyclic_tree_is_reported() -> None:
    level = make_level()
    level.nodes = [(6, 0, -1)]  # the front child is the node itself
    tester = SolidTester(read_bsp(level.to_bytes(), "synthetic.bsp"))
    with pytest.raises(BspError, match="cycle"):
        tester.solid_or_outside(np.array([[200.0, 0, 0]]))
