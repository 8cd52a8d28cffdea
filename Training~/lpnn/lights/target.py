"""The radiance target: texture x baked light projected onto the mesh vertices (seed, Algorithm 4.1).

Mass-lumped L2 projection onto piecewise-linear functions: for vertex i with shape function phi_i,
    r_i = (1 / A_i) * sum over triangles k of i: (A_k / n) * sum_l r(x_l) * phi_i(x_l),
    A_i = sum over those triangles of A_k / 3,
with n uniform samples x_l per triangle (the centroids of its regular m x m subdivision, all of equal
area). r(x) = albedo(x) * light(x), light = the lightmap (bilinear on its page) or the vertex colours
(interpolated as the renderer does), in linear units of "texture at full brightness": 4/255 per
byte (quake3-bsp.md §3, overbright). The albedo is projected the same way, so the forward model
can multiply its irradiance by a per-vertex albedo.

Information lost at the vertices (the seed's main limit): the relative L2 distance between r at
the samples and the piecewise-linear r~ built from the vertex values, sqrt(sum |r~ - r|^2 dA) /
sqrt(sum |r|^2 dA). Subdividing the mesh (surfaces.subdivide) lowers it at the cost of more points.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scenes.bsp import LIGHTMAP_SIDE
from ..scenes.lightgrid import LINEAR_PER_BYTE
from ..scenes.surfaces import triangle_areas
from .surfaces import COLOR, LIGHTMAP_ST, ST, LitMesh
from .textures import Albedo

DEFAULT_SAMPLES_PER_SIDE = 3  # 9 samples a triangle
TRIANGLES_PER_CHUNK = 32_768


@dataclass(frozen=True)
class RadianceTarget:
    positions: np.ndarray  # (V, 3) Quake units
    normals: np.ndarray  # (V, 3) unit
    areas: np.ndarray  # (V,) vertex-associated area A_i, square Quake units (> 0)
    radiance: np.ndarray  # (V, 3) r_i: albedo x light, linear
    albedo: np.ndarray  # (V, 3) projected albedo
    projection_loss: float  # relative L2 distance between r and its piecewise-linear projection
    samples_per_triangle: int

    @property
    def point_count(self) -> int:
        return len(self.positions)


def barycentric_samples(per_side: int) -> np.ndarray:
    """(per_side^2, 3) barycentric centroids of the regular subdivision of a triangle: a uniform rule."""
    if per_side < 1:
        raise ValueError(f"samples per side {per_side} must be at least 1")
    i, j = np.meshgrid(np.arange(per_side), np.arange(per_side), indexing="ij")
    up = (i + j <= per_side - 1)
    down = (i + j <= per_side - 2)
    uv = np.concatenate([np.stack([i[up] + 1 / 3, j[up] + 1 / 3], 1), np.stack([i[down] + 2 / 3, j[down] + 2 / 3], 1)])
    uv = uv / per_side
    return np.column_stack([1.0 - uv.sum(axis=1), uv])


def sample_lightmaps(pages: np.ndarray, page: np.ndarray, st: np.ndarray) -> np.ndarray:
    """Bilinear lightmap bytes (N, 3) at lightmap coordinates st (N, 2) in [0, 1] of the given pages."""
    side = LIGHTMAP_SIDE
    x = np.clip(st[:, 0] * side - 0.5, 0.0, side - 1.0)
    y = np.clip(st[:, 1] * side - 0.5, 0.0, side - 1.0)
    x0 = np.minimum(np.floor(x).astype(np.int64), side - 2)
    y0 = np.minimum(np.floor(y).astype(np.int64), side - 2)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    texel = lambda row, column: pages[page, row, column].astype(np.float64)  # noqa: E731
    return ((1 - fy) * ((1 - fx) * texel(y0, x0) + fx * texel(y0, x0 + 1))
            + fy * ((1 - fx) * texel(y0 + 1, x0) + fx * texel(y0 + 1, x0 + 1)))


def build_target(mesh: LitMesh, lightmaps: np.ndarray, albedo: Albedo,
                 samples_per_side: int = DEFAULT_SAMPLES_PER_SIDE) -> RadianceTarget:
    weights = barycentric_samples(samples_per_side)  # (n, 3)
    n = len(weights)
    vertex_count = mesh.vertex_count
    areas = triangle_areas(mesh.positions, mesh.triangles)
    vertex_area = np.bincount(mesh.triangles.ravel(), weights=np.repeat(areas / 3.0, 3), minlength=vertex_count)
    radiance_sum = np.zeros((vertex_count, 3))
    albedo_sum = np.zeros((vertex_count, 3))
    for start in range(0, len(mesh.triangles), TRIANGLES_PER_CHUNK):
        chunk = slice(start, start + TRIANGLES_PER_CHUNK)
        radiance, colour, corners, phi, weight = _samples(mesh, chunk, weights, areas[chunk], lightmaps, albedo)
        radiance_share = np.einsum("ts,tsc,tsk->tck", weight, phi, radiance).reshape(-1, 3)
        albedo_share = np.einsum("ts,tsc,tsk->tck", weight, phi, colour).reshape(-1, 3)
        for c in range(3):
            radiance_sum[:, c] += np.bincount(corners.ravel(), weights=radiance_share[:, c], minlength=vertex_count)
            albedo_sum[:, c] += np.bincount(corners.ravel(), weights=albedo_share[:, c], minlength=vertex_count)
    safe_area = np.where(vertex_area > 0, vertex_area, 1.0)[:, None]
    radiance_at = radiance_sum / safe_area
    albedo_at = albedo_sum / safe_area

    # the loss of the projection, measured at the same samples
    error, norm = 0.0, 0.0
    for start in range(0, len(mesh.triangles), TRIANGLES_PER_CHUNK):
        chunk = slice(start, start + TRIANGLES_PER_CHUNK)
        radiance, _, corners, phi, weight = _samples(mesh, chunk, weights, areas[chunk], lightmaps, albedo)
        projected = np.einsum("tsc,tck->tsk", phi, radiance_at[corners])
        error += float(np.sum(weight[..., None] * (projected - radiance) ** 2))
        norm += float(np.sum(weight[..., None] * radiance ** 2))
    loss = float(np.sqrt(error / norm)) if norm > 0 else 0.0
    return RadianceTarget(positions=mesh.positions.copy(), normals=mesh.normals.copy(), areas=vertex_area,
                          radiance=radiance_at, albedo=albedo_at, projection_loss=loss, samples_per_triangle=n)


def _samples(mesh: LitMesh, chunk: slice, weights: np.ndarray, areas: np.ndarray, lightmaps: np.ndarray,
             albedo: Albedo) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per sample of the chunk's triangles: radiance (t, n, 3), albedo (t, n, 3), the corners (t, 3),
    phi (t, n, 3) and the quadrature weight A_k / n (t, 1)."""
    corners = mesh.triangles[chunk]
    t, n = len(corners), len(weights)
    at = np.einsum("sc,tca->tsa", weights, mesh.attributes[corners]).reshape(t * n, -1)
    page = np.repeat(mesh.lightmap_of_triangle[chunk], n)
    lit_by_map = page >= 0
    light = at[:, COLOR].copy()  # vertex-lit: interpolated vertex colours
    if lit_by_map.any():
        light[lit_by_map] = sample_lightmaps(lightmaps, page[lit_by_map], at[lit_by_map, LIGHTMAP_ST])
    colour = albedo.sample(np.repeat(mesh.shader_of_triangle[chunk], n), at[:, ST])
    radiance = colour * light * LINEAR_PER_BYTE
    phi = np.broadcast_to(weights, (t, n, 3))
    return (radiance.reshape(t, n, 3), colour.reshape(t, n, 3), corners, phi,
            (areas / n)[:, None] * np.ones((1, n)))
