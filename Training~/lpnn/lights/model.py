"""Forward model: radiance of point lights at the target points, its gradient, and visibility.

Light j: position x_j (Quake units), colour c_j (RGB in [0, 1]), intensity I_j (q3map2's `light`
value). At target point i (position p_i, unit normal n_i, projected albedo a_i):

    m_i = a_i * S * sum_j c_j * I_j * V_ij * max(0, n_i . d_ij) / (|d_ij| * max(|d_ij|, R0)^2),
    d_ij = x_j - p_i,   S = POINT_SCALE * LINEAR_PER_BYTE = 7500 * 4/255,   R0 = 16 units,

i.e. q3map2's default point light (inverse square, distance clamped to 16 units, Lambert cosine,
quake3-bsp.md §5) in the linear units of the target, so a recovered I is directly comparable with a
level's light entities. V_ij in {0, 1} is an Embree shadow ray from p_i (offset RAY_OFFSET along
n_i) to x_j. Visibility is *held fixed* between refreshes (the optimiser recomputes it every few
iterations): the gradient is exact for fixed V and ignores the movement of shadow edges.

Objective: area-weighted relative squared error (the mass-lumped L2 norm of the seed's target),
    L = sum_i A_i |m_i - r_i|^2 / sum_i A_i |r_i|^2      (1 with no light, 0 at a perfect fit).
Gradients are analytic, accumulated over chunks of points so memory stays bounded.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scenes.lightgrid import LINEAR_PER_BYTE
from ..scenes.raycast import EmbreeRaycaster
from .target import RadianceTarget

POINT_SCALE = 7500.0  # q3map2 pointScale
MIN_DISTANCE = 16.0  # q3map2 clamps the distance of point lights to 16 units
LINEAR_SCALE = POINT_SCALE * LINEAR_PER_BYTE
RAY_OFFSET = 0.5  # units off the surface, so a shadow ray does not hit its own face
# Shadow rays are cast only where a light could add at least this many bytes (q3map2 drops
# contributions of 1 or less), assuming up to RANGE_HEADROOM x its intensity (and at least
# RANGE_FLOOR_INTENSITY) before the next refresh.
RANGE_MIN_BYTES = 1.0
RANGE_HEADROOM = 4.0
RANGE_FLOOR_INTENSITY = 300.0
POINTS_PER_CHUNK = 4096


@dataclass
class Lights:
    positions: np.ndarray  # (J, 3) Quake units
    colours: np.ndarray  # (J, 3) in [0, 1]
    intensities: np.ndarray  # (J,) >= 0

    @property
    def count(self) -> int:
        return len(self.positions)


@dataclass(frozen=True)
class Gradient:
    value: float
    positions: np.ndarray  # (J, 3)
    colours: np.ndarray  # (J, 3)
    intensities: np.ndarray  # (J,)


class ForwardModel:
    def __init__(self, target: RadianceTarget, raycaster: EmbreeRaycaster | None) -> None:
        self.points = target.positions
        self.normals = target.normals
        self.albedo = target.albedo
        self.radiance = target.radiance
        total_area = float(target.areas.sum())
        self.weights = target.areas / total_area if total_area > 0 else np.zeros_like(target.areas)
        norm = float(np.sum(self.weights[:, None] * self.radiance ** 2))
        # an all-black target: any light is error; normalise by 1 instead of dividing by zero
        self.norm = norm if norm > 0 else 1.0
        self.raycaster = raycaster
        self.rays = 0

    @property
    def point_count(self) -> int:
        return len(self.points)

    # ------------------------------------------------------------------------------ visibility

    def visibility(self, lights: Lights) -> np.ndarray:
        """(N, J) bool: light j reaches point i (in front of it, within range, no occluder)."""
        visible = np.zeros((self.point_count, lights.count), dtype=bool)
        reach = np.maximum(RANGE_HEADROOM * lights.intensities * lights.colours.max(axis=1), RANGE_FLOOR_INTENSITY)
        max_squared = POINT_SCALE * reach / RANGE_MIN_BYTES
        for start in range(0, self.point_count, POINTS_PER_CHUNK):
            chunk = slice(start, start + POINTS_PER_CHUNK)
            d = lights.positions[None, :, :] - self.points[chunk, None, :]
            squared = np.einsum("cjk,cjk->cj", d, d)
            candidate = (np.einsum("cjk,ck->cj", d, self.normals[chunk]) > 0) & (squared <= max_squared[None, :])
            point, light = np.nonzero(candidate)
            if point.size == 0:
                continue
            if self.raycaster is None:
                visible[start + point, light] = True
                continue
            origins = self.points[chunk][point] + RAY_OFFSET * self.normals[chunk][point]
            offsets = lights.positions[light] - origins
            lengths = np.linalg.norm(offsets, axis=1)
            reachable = lengths > RAY_OFFSET
            directions = offsets[reachable] / lengths[reachable, None]
            distances, _ = self.raycaster.cast(origins[reachable], directions, float(lengths[reachable].max()))
            self.rays += int(reachable.sum())
            free = np.isinf(distances) | (distances >= lengths[reachable] - RAY_OFFSET)
            visible[start + point[reachable][free], light[reachable][free]] = True
        return visible

    # --------------------------------------------------------------------------------- radiance

    def radiance_of(self, lights: Lights, visible: np.ndarray) -> np.ndarray:
        """(N, 3) modelled radiance m_i."""
        out = np.zeros((self.point_count, 3))
        emitted = lights.colours * lights.intensities[:, None]  # (J, 3)
        for start in range(0, self.point_count, POINTS_PER_CHUNK):
            chunk = slice(start, start + POINTS_PER_CHUNK)
            g, _, _, _ = self._transfer(lights, visible, chunk)
            out[chunk] = self.albedo[chunk] * LINEAR_SCALE * (g @ emitted)
        return out

    def _transfer(self, lights: Lights, visible: np.ndarray, chunk: slice
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """g (C, J) = V cos / (q max(q, R0)^2) and the pieces of its gradient: d, q, n.d."""
        d = lights.positions[None, :, :] - self.points[chunk, None, :]  # (C, J, 3)
        q = np.sqrt(np.einsum("cjk,cjk->cj", d, d))
        q = np.maximum(q, 1e-9)
        ndot = np.einsum("cjk,ck->cj", d, self.normals[chunk])
        lit = visible[chunk] & (ndot > 0)
        clamped_sq = np.maximum(q * q, MIN_DISTANCE * MIN_DISTANCE)
        g = np.where(lit, ndot / (q * clamped_sq), 0.0)
        return g, d, q, np.where(lit, ndot, 0.0)

    def objective(self, lights: Lights, visible: np.ndarray, with_gradient: bool = True) -> Gradient:
        """L and dL / d(every light parameter), visibility fixed."""
        value = 0.0
        grad_pos = np.zeros((lights.count, 3))
        grad_colour = np.zeros((lights.count, 3))
        emitted = lights.colours * lights.intensities[:, None]
        for start in range(0, self.point_count, POINTS_PER_CHUNK):
            chunk = slice(start, start + POINTS_PER_CHUNK)
            g, d, q, ndot = self._transfer(lights, visible, chunk)
            albedo = self.albedo[chunk]
            residual = albedo * LINEAR_SCALE * (g @ emitted) - self.radiance[chunk]
            weight = self.weights[chunk][:, None]
            value += float(np.sum(weight * residual ** 2))
            if not with_gradient:
                continue
            back = 2.0 * weight * residual * albedo * LINEAR_SCALE / self.norm  # dL/dm * dm/d(g @ emitted)
            grad_colour += g.T @ back  # d/d(emitted), (J, 3); split into colour / intensity below
            u = back @ emitted.T  # (C, J): dL/dg
            # dg/dx for q >= R0: n/q^3 - 3 (n.d) d / q^5; for q < R0: n/(R0^2 q) - (n.d) d/(R0^2 q^3)
            far = q >= MIN_DISTANCE
            clamped_sq = np.where(far, q * q, MIN_DISTANCE * MIN_DISTANCE)
            along_normal = np.where(ndot > 0, 1.0 / (q * clamped_sq), 0.0)
            along_d = ndot * np.where(far, 3.0 / q ** 5, 1.0 / (MIN_DISTANCE * MIN_DISTANCE * q ** 3))
            grad_pos += (u * along_normal).T @ self.normals[chunk] - np.einsum("cj,cjk->jk", u * along_d, d)
        grad_emitted = grad_colour
        return Gradient(
            value=value / self.norm,
            positions=grad_pos,
            colours=grad_emitted * lights.intensities[:, None],
            intensities=np.einsum("jk,jk->j", grad_emitted, lights.colours),
        )
