"""Quake -> Unity mapping and Bezier patch tessellation."""

from __future__ import annotations

import numpy as np

from lpnn.scenes.coords import METRES_PER_UNIT, QUAKE_TO_UNITY, quake_to_unity, unity_to_quake
from lpnn.scenes.patches import bernstein_weights, patch_triangles, tessellate_patches
from lpnn.scenes.surfaces import triangle_areas


def test_mapping_is_the_documented_axis_permutation() -> None:
    assert np.linalg.det(QUAKE_TO_UNITY) == -1.0
    assert quake_to_unity(np.array([1.0, 2.0, 3.0])).tolist() == [-2 * 0.0254, 3 * 0.0254, 1 * 0.0254]
    # Quake up (+Z) is Unity up (+Y); directions keep unit length
    assert quake_to_unity(np.array([[0.0, 0.0, 1.0]]), scale=1.0).tolist() == [[0.0, 1.0, 0.0]]


def test_mapping_round_trips_and_preserves_lengths() -> None:
    rng = np.random.default_rng(1)
    points = rng.normal(size=(100, 3)) * 1000
    assert np.allclose(unity_to_quake(quake_to_unity(points)), points, rtol=0, atol=1e-9)
    directions = rng.normal(size=(100, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    assert np.allclose(np.linalg.norm(quake_to_unity(directions, scale=1.0), axis=1), 1.0)
    assert np.allclose(np.linalg.norm(quake_to_unity(points), axis=1), METRES_PER_UNIT * np.linalg.norm(points, axis=1))


def test_mapping_flips_handedness() -> None:
    # a right-handed Quake frame (x, y, x*y = z) becomes a left-handed triple in Unity: (a x b).c = -1
    a, b, c = quake_to_unity(np.eye(3), scale=1.0)
    assert np.dot(np.cross(a, b), c) == -1.0


def test_bernstein_weights_partition_unity() -> None:
    weights = bernstein_weights(8)
    assert weights.shape == (9, 3)
    assert np.allclose(weights.sum(axis=1), 1.0)
    assert weights[0].tolist() == [1, 0, 0] and weights[-1].tolist() == [0, 0, 1]


def test_flat_patch_covers_its_square() -> None:
    control = np.array([(x, y, 5.0) for y in (0, 1, 2) for x in (0, 1, 2)], dtype=float)
    vertices, triangles, owner = tessellate_patches(control, [0], [3], [3], level=4)
    assert vertices.shape == (25, 3) and triangles.shape == (32, 3)
    assert np.all(vertices[:, 2] == 5.0) and owner.tolist() == [0] * 32
    assert np.isclose(triangle_areas(vertices, triangles).sum(), 4.0)


def test_curved_patch_lies_on_the_bezier() -> None:
    # an arch along x: the middle column is lifted by 4, so the surface is z = 2*4*t*(1-t)
    control = np.array([(x, y, 4.0 if x == 1 else 0.0) for y in (0, 1, 2) for x in (0, 1, 2)], dtype=float)
    vertices, _, _ = tessellate_patches(control, [0], [3], [3], level=8)
    t = vertices[:, 0] / 2.0
    assert np.allclose(vertices[:, 2], 8.0 * t * (1.0 - t))
    assert np.isclose(vertices[:, 2].max(), 2.0)  # B1(1/2) * 4 = 2


def test_control_grid_with_two_patches_shares_its_seam() -> None:
    # W = 5 columns, H = 3 rows: two patches side by side sharing column 2
    rng = np.random.default_rng(3)
    control = np.concatenate([np.zeros((7, 3)), rng.normal(size=(15, 3))])  # offset first_vert
    vertices, triangles, owner = tessellate_patches(control, [7], [5], [3], level=3)
    assert vertices.shape == (2 * 16, 3) and triangles.shape == (2 * 18, 3)
    grid = vertices.reshape(2, 4, 4, 3)  # patch, row k, column l
    assert np.array_equal(grid[0, :, -1], grid[1, :, 0])  # bit-identical seam: watertight
    corners = control[7:].reshape(3, 5, 3)
    assert np.array_equal(grid[0, 0, 0], corners[0, 0]) and np.array_equal(grid[1, -1, -1], corners[2, 4])


def test_patch_triangle_winding_matches_q3() -> None:
    triangles = patch_triangles(1)  # 2x2 vertices: (0,0)=0 (0,1)=1 (1,0)=2 (1,1)=3
    assert triangles.tolist() == [[0, 2, 1], [1, 2, 3]]
