"""Scene data and the radiance target (seed Algorithm 4.1) on a synthetic BSP with a lightmap page and
a vertex-lit patch; textures from a pk3 with the documented fallback; levels without baked light."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from lpnn.lights.surfaces import lit_mesh, subdivide
from lpnn.lights.target import barycentric_samples, build_target
from lpnn.lights.textures import load_albedo, uniform_albedo
from lpnn.scenes.bsp import read_bsp
from lpnn.scenes.errors import BspError
from lit_bsp import PAGE_BYTE, PATCH_COLOUR, PER_BYTE, lit_level
from synthetic_bsp import make_level, write_pk3


def test_samples_are_a_uniform_rule() -> None:
    for per_side in (1, 2, 3, 5):
        weights = barycentric_samples(per_side)
        assert len(weights) == per_side ** 2
        np.testing.assert_allclose(weights.sum(axis=1), 1.0)
        np.testing.assert_allclose(weights.mean(axis=0), 1 / 3)  # the centroid: exact for linear functions


def test_mesh_keeps_lit_faces_only() -> None:
    bsp = read_bsp(lit_level().to_bytes(), "lit")
    mesh = lit_mesh(bsp)
    assert set(np.unique(mesh.face_of_triangle)) == {0, 3}  # not sky (1), glass (2), the billboard (4)
    assert set(np.unique(mesh.lightmap_of_triangle[mesh.face_of_triangle == 0])) == {0}
    assert set(np.unique(mesh.lightmap_of_triangle[mesh.face_of_triangle == 3])) == {-1}  # vertex-lit
    assert mesh.excluded["not drawn or see-through"] == 3  # sky, glass, billboard


def test_constant_light_is_projected_exactly() -> None:
    bsp = read_bsp(lit_level().to_bytes(), "lit")
    target = build_target(lit_mesh(bsp), bsp.lightmaps, uniform_albedo(len(bsp.shaders), 0.5))
    on_quad = target.positions[:, 2] == 128
    np.testing.assert_allclose(target.radiance[on_quad], 0.5 * PAGE_BYTE * PER_BYTE, rtol=1e-12)
    np.testing.assert_allclose(target.radiance[~on_quad], np.broadcast_to(0.5 * np.array(PATCH_COLOUR) * PER_BYTE, (81, 3)), rtol=1e-12)
    np.testing.assert_allclose(target.albedo, 0.5)
    assert target.projection_loss == pytest.approx(0.0, abs=1e-12)
    # vertex areas partition the surface: 128 x 256 quad + 64 x 64 patch
    assert target.areas.sum() == pytest.approx(128 * 256 + 64 * 64)


def test_subdivision_recovers_what_the_vertices_lose() -> None:
    texel = np.arange(128)
    spot = 20 + 200 * np.exp(-((texel[:, None] - 40) ** 2 + (texel[None, :] - 40) ** 2) / 60.0)
    bsp = read_bsp(lit_level(np.repeat(spot[..., None], 3, axis=2)).to_bytes(), "spot")
    albedo = uniform_albedo(len(bsp.shaders), 0.5)
    coarse = build_target(lit_mesh(bsp), bsp.lightmaps, albedo)
    fine_mesh = subdivide(lit_mesh(bsp), max_edge=8.0)
    fine = build_target(fine_mesh, bsp.lightmaps, albedo)
    assert fine.point_count > 20 * coarse.point_count
    assert coarse.projection_loss > 0.3  # the quad's 4 corners miss the spot
    assert fine.projection_loss < coarse.projection_loss / 4
    assert fine.areas.sum() == pytest.approx(coarse.areas.sum())
    # the spot's centre (texel 40 -> s = (40.5 - 8) / 64 -> x = 64 + 128 s, y = 256 t) is a bright vertex now
    centre = np.array([64 + 128 * 32.5 / 64, 256 * 32.5 / 64, 128])
    nearest = np.argmin(np.linalg.norm(fine.positions - centre, axis=1))
    assert fine.radiance[nearest, 0] > 0.8 * 0.5 * 220 * PER_BYTE


def test_level_without_baked_light_is_rejected() -> None:
    bsp = read_bsp(make_level().to_bytes(), "unlit.bsp")  # every face lightmap -1, lump 14 empty
    with pytest.raises(BspError, match=r"unlit\.bsp: no surface carries baked light .*q3map2 -light"):
        lit_mesh(bsp)


def test_textures_from_paks_and_the_fallback(tmp_path: Path) -> None:
    from PIL import Image

    def png(colour: tuple[int, int, int], side: int = 64) -> bytes:
        out = io.BytesIO()
        Image.new("RGB", (side, side), colour).save(out, format="PNG")
        return out.getvalue()

    first = write_pk3(tmp_path / "pak0.pk3", {"textures/test/wall.png": png((255, 0, 0)),
                                               "textures/test/broken.jpg": b"not a jpeg"})
    later = write_pk3(tmp_path / "pak1.pk3", {"textures/test/wall.png": png((0, 0, 255))})  # overrides pak0
    (tmp_path / "pak2.pk3").write_bytes(b"not a zip")
    names = ["textures/test/wall", "textures/test/missing", "textures/test/broken"]
    albedo = load_albedo(names, [first, later, tmp_path / "pak2.pk3"])
    assert albedo.found == 1
    np.testing.assert_allclose(albedo.images[0], np.broadcast_to([0, 0, 1.0], (32, 32, 3)))  # box-filtered to 32
    assert albedo.sources[1].startswith("fallback: no plain image")
    assert "cannot be decoded" in albedo.sources[2]
    np.testing.assert_allclose(albedo.fallback, [0, 0, 1.0])  # the mean of the found textures
    sampled = albedo.sample(np.array([0, 1, 2]), np.array([[0.3, 0.7], [0.0, 0.0], [5.5, -2.25]]))
    np.testing.assert_allclose(sampled, [[0, 0, 1.0]] * 3)
    none_found = load_albedo(names[1:], [])
    np.testing.assert_allclose(none_found.fallback, 0.5)
