"""Forward model: radiance of point lights at the target points, its gradient, and visibility.

Light j: position x_j (Quake units), colour c_j (RGB in [0, 1]), intensity I_j (q3map2's `light`
value); one ambient colour b (bytes, RGB) for the whole level. At target point i (position p_i,
unit normal n_i, projected albedo a_i), as q3map2 bakes a luxel (light_ydnar.c: every luxel starts
at the worldspawn ambient, lights add, ColorToBytes clamps to 255 keeping the hue):

    E_i = b + 7500 * sum_j c_j I_j V_ij max(0, n_i . d_ij) / (|d_ij| max(|d_ij|, R0)^2)   (bytes)
    m_i = a_i * (4/255) * clamp(E_i),   clamp(E) = E * min(1, 255 / max_c E_c),
    d_ij = x_j - p_i,   R0 = 16 units,

i.e. q3map2's default point light (inverse square, distance clamped to 16 units, Lambert cosine,
quake3-bsp.md §5) in the linear units of the target (4/255 a byte), so a recovered I is directly
comparable with a level's light entities. Without the clamp, the 1/r^2 peak next to a light is
thousands of bytes where the lightmap holds 255, and that peak decides the whole fit. V_ij in {0, 1}
is an Embree shadow ray from p_i (offset RAY_OFFSET along n_i) to x_j that, as q3map2's lightmap traces, ignores
occluders within SURFACE_INHIBIT_RADIUS of its origin (emitters.py). Visibility is *held fixed*
between refreshes (the optimiser recomputes it every few iterations): the gradient is exact for
fixed V and ignores the movement of shadow edges.

Objective: area-weighted relative squared error (the mass-lumped L2 norm of the seed's target),
    L = sum_i A_i |m_i - r_i|^2 / sum_i A_i |r_i|^2      (1 with no light, 0 at a perfect fit).
Gradients are analytic and evaluated only on the (point, light) pairs with V_ij = 1: one compiled pass
over them (objective_kernel.py); objective_numpy is the same formula over chunks of (pairs, 3) arrays, the
reference the pass is tested against.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..scenes.lightgrid import LINEAR_PER_BYTE
from ..scenes.raycast import EmbreeRaycaster
from . import objective_kernel, visibility_kernel
# q3map2's constants, stated once in emitters.py (the module of q3map2's facts) and shared by every light of the rig:
# the spotlight's soft cone edge, pointScale, the inverse square's 16-unit clamp, the 1-byte contributions dropped;
# and the shadow rays' start RAY_OFFSET units off the surface, so that a ray does not hit its own face
from .emitters import DROPPED_CONTRIBUTION, MIN_DISTANCE, POINT_SCALE, RAY_OFFSET, SPOT_EDGE
from .emitters import (SURFACE_INHIBIT_RADIUS, Suns, clamped_distance_squared, cone_factor, occluded, sun_ray_origins,
                       sunlit)
from .target import RadianceTarget

LINEAR_SCALE = POINT_SCALE * LINEAR_PER_BYTE
BYTE_MAX = 255.0  # a lightmap byte saturates here (q3map2 ColorToBytes keeps the hue)
# Shadow rays are cast only where a light could add at least this many bytes (q3map2 drops
# contributions of 1 or less), assuming up to RANGE_HEADROOM x its intensity (and at least
# RANGE_FLOOR_INTENSITY) before the next refresh.
RANGE_MIN_BYTES = DROPPED_CONTRIBUTION
RANGE_HEADROOM = 4.0
RANGE_FLOOR_INTENSITY = 300.0
POINTS_PER_CHUNK = 4096  # shadow rays are set up this many points at a time
PAIRS_PER_CHUNK = 262_144  # (point, light) pairs evaluated at a time: ~60 MB of temporaries


@dataclass
class Lights:
    positions: np.ndarray  # (J, 3) Quake units
    colours: np.ndarray  # (J, 3) in [0, 1]
    intensities: np.ndarray  # (J,) >= 0
    ambient: np.ndarray = field(default_factory=lambda: np.zeros(3))  # (3,) bytes added everywhere
    # (S,) q3map_surfacelight value of each surface light of the model (ForwardModel.surface_basis), >= 0
    surface_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # spotlights (q3map2's cone, emitters.spot_factor): (J, 3) axis in Quake axes (unit in rigs) and (J,)
    # radiusByDist, 0 for a point light; both empty: every light is a point light
    spot_directions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    radius_by_dist: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # suns (q3map2's EMIT_SUN, emitters.py): (K, 3) direction toward the sun, Quake axes (unit in rigs), (K, 3)
    # colour, (K,) intensity in photons: a luxel that sees the sky along the direction gets
    # colour x intensity x max(0, n . direction) bytes
    sun_directions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    sun_colours: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    sun_intensities: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def count(self) -> int:
        return len(self.positions)

    @property
    def sun_count(self) -> int:
        return len(self.sun_intensities)

    def cones(self) -> tuple[np.ndarray, np.ndarray]:
        """((J, 3) axes, (J,) radiusByDist, 0 for a point light), float64 and contiguous, for every light."""
        if len(self.radius_by_dist) == 0:
            return np.zeros((self.count, 3)), np.zeros(self.count)
        if self.radius_by_dist.shape != (self.count,) or self.spot_directions.shape != (self.count, 3):
            raise ValueError(f"{len(self.radius_by_dist)} spot cones and {len(self.spot_directions)} axes for "
                             f"{self.count} lights")
        return (np.ascontiguousarray(self.spot_directions, dtype=np.float64),
                np.ascontiguousarray(self.radius_by_dist, dtype=np.float64))


@dataclass(frozen=True)
class Gradient:
    value: float
    positions: np.ndarray  # (J, 3)
    colours: np.ndarray  # (J, 3)
    intensities: np.ndarray  # (J,)
    ambient: np.ndarray  # (3,)
    surface_values: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (S,)
    spot_directions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # (J, 3): dL/d(axis), axis as given
    radius_by_dist: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (J,); both 0 for point lights
    sun_directions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # (K, 3): dL/d(direction) as given
    sun_colours: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # (K, 3)
    sun_intensities: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (K,)


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
        # bytes every point receives from light elements held fixed in a fit (spotlights and surface
        # lights of a compile, emitters.py), added before the 255 clamp like the ambient
        self.fixed = np.zeros_like(self.points)
        # (S, N, 3) bytes each surface light (a shader's emitting surfaces, emitters.py) adds at every point per
        # unit of its q3map_surfacelight value: linear in the value, so the fit recovers the value (rig.py)
        self.surface_basis = np.zeros((0, len(self.points), 3))
        # the level's sky triangles: a fitted sun lights a point whose ray toward it hits them first (emitters.sunlit)
        self.sky: EmbreeRaycaster | None = None
        self._sun_lit_of: np.ndarray | None = None  # the visibility matrix the suns' rays were cast with
        self._sun_lit = np.zeros((len(self.points), 0), dtype=bool)
        self.rays = 0
        # threads of the compiled objective: 1, since a second thread waiting for a busy core made it 3x slower
        # on this shared 2-core machine (lights.md §3); the numbers do not depend on it
        self.threads = 1
        self._pairs_of: np.ndarray | None = None  # the visibility matrix whose pairs are cached
        self._pairs: list = []
        self._csr_of: np.ndarray | None = None  # the visibility matrix whose CSR pairs are cached
        self._csr: tuple[np.ndarray, np.ndarray] = (np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64))

    @property
    def point_count(self) -> int:
        return len(self.points)

    @property
    def surface_count(self) -> int:
        return len(self.surface_basis)

    def fixed_bytes(self, lights: Lights, visible: np.ndarray) -> np.ndarray:
        """(N, 3) bytes of the elements that are not point lights: the fixed emitters, the surface lights and the
        lights' suns (their sky rays held fixed with `visible`, sun_lit)."""
        out = self.fixed
        if self.surface_count:
            values = np.asarray(lights.surface_values, dtype=np.float64)
            if values.shape != (self.surface_count,):
                raise ValueError(f"{values.size} surface light values for the model's {self.surface_count} surface "
                                 f"lights")
            out = out + np.einsum("s,snk->nk", values, self.surface_basis)
        if lights.sun_count:
            weight = self.sun_weights(lights, self.sun_lit(lights, visible))  # (N, K)
            out = out + weight @ (lights.sun_colours * lights.sun_intensities[:, None])
        return out

    # ----------------------------------------------------------------------------------- suns

    def sun_visibility(self, lights: Lights) -> np.ndarray:
        """(N, K) bool: point i faces sun k and its ray toward it (from RAY_OFFSET off the surface) meets the sky
        before any shadow caster (emitters.sunlit; without a raycaster every facing point is lit)."""
        lit = np.zeros((self.point_count, lights.sun_count), dtype=bool)
        sky = Suns(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.int64), sky=self.sky)
        for k, direction in enumerate(np.asarray(lights.sun_directions, dtype=np.float64)):
            length = float(np.linalg.norm(direction))
            if length == 0:
                continue
            unit = direction / length
            facing = np.flatnonzero(self.normals @ unit > 0)
            origins = sun_ray_origins(self.points[facing], self.normals[facing], unit)
            lit[facing, k] = sunlit(origins, np.broadcast_to(unit, origins.shape).copy(), sky, self.raycaster)
            if self.raycaster is not None:
                self.rays += 2 * len(facing)
        return lit

    def sun_lit(self, lights: Lights, visible: np.ndarray) -> np.ndarray:
        """The suns' sky rays cast with `visible` (visibility() casts them), or cast now for another matrix: held
        fixed between refreshes like the point lights' shadow rays."""
        if self._sun_lit_of is not visible or self._sun_lit.shape[1] != lights.sun_count:
            self._sun_lit, self._sun_lit_of = self.sun_visibility(lights), visible
        return self._sun_lit

    def sun_weights(self, lights: Lights, lit: np.ndarray) -> np.ndarray:
        """(N, K) lit x max(0, n . direction): the bytes per unit of a sun's colour x intensity."""
        return lit * np.maximum(0.0, self.normals @ np.asarray(lights.sun_directions, dtype=np.float64).T)

    def _sun_gradient(self, lights: Lights, visible: np.ndarray,
                      upstream: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """dL/d(direction, colour, intensity) of every sun from dL/dE (N, 3), its sky rays fixed: with w_ik = lit_ik
        max(0, n_i . d_k) and e_k = colour_k x intensity_k, dL/de_k = sum_i w_ik dL/dE_i and dL/dd_k = sum_i lit_ik
        [n_i . d_k > 0] (dL/dE_i . e_k) n_i (exact for any direction, not only unit ones)."""
        count = lights.sun_count
        if count == 0 or len(upstream) == 0:
            return np.zeros((count, 3)), np.zeros((count, 3)), np.zeros(count)
        lit = self.sun_lit(lights, visible)
        emitted = lights.sun_colours * lights.sun_intensities[:, None]  # (K, 3)
        d_emitted = self.sun_weights(lights, lit).T @ upstream  # (K, 3)
        front = lit & (self.normals @ np.asarray(lights.sun_directions, dtype=np.float64).T > 0)  # (N, K)
        d_direction = (front * (upstream @ emitted.T)).T @ self.normals  # (K, 3)
        return d_direction, d_emitted * lights.sun_intensities[:, None], np.einsum("kc,kc->k", d_emitted,
                                                                                   lights.sun_colours)

    # ------------------------------------------------------------------------------ visibility

    def visibility(self, lights: Lights) -> np.ndarray:
        """(N, J) bool: light j reaches point i (in front of it, within range, no occluder). The candidate pairs
        and their rays are chosen by a compiled pass (visibility_kernel.py), the rays cast by Embree."""
        visible = np.zeros((self.point_count, lights.count), dtype=bool)
        max_squared = _range_squared(lights)
        for start in range(0, self.point_count, POINTS_PER_CHUNK):
            stop = min(start + POINTS_PER_CHUNK, self.point_count)
            point, light, origins, directions, lengths = visibility_kernel.candidate_rays(
                self.points, self.normals, lights.positions, max_squared, start, stop, RAY_OFFSET)
            if point.size == 0:
                continue
            if self.raycaster is None:
                visible[point, light] = True
                continue
            reachable = lengths > RAY_OFFSET
            if not reachable.any():
                continue
            free = ~occluded(self.raycaster, origins[reachable], directions[reachable], lengths[reachable],
                             SURFACE_INHIBIT_RADIUS)
            self.rays += int(reachable.sum())
            visible[point[reachable][free], light[reachable][free]] = True
        if lights.sun_count:  # the suns' sky rays, held with this matrix until the next refresh
            self._sun_lit, self._sun_lit_of = self.sun_visibility(lights), visible
        return visible

    def visibility_numpy(self, lights: Lights) -> np.ndarray:
        """visibility() over (points, lights, 3) numpy arrays: the reference the compiled selection is tested against."""
        visible = np.zeros((self.point_count, lights.count), dtype=bool)
        max_squared = _range_squared(lights)
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
            free = ~occluded(self.raycaster, origins[reachable], directions, lengths[reachable], SURFACE_INHIBIT_RADIUS)
            self.rays += int(reachable.sum())
            visible[start + point[reachable][free], light[reachable][free]] = True
        return visible

    # --------------------------------------------------------------------------------- radiance

    def radiance_of(self, lights: Lights, visible: np.ndarray) -> np.ndarray:
        """(N, 3) modelled radiance m_i."""
        out = np.zeros((self.point_count, 3))
        emitted = lights.colours * lights.intensities[:, None]  # (J, 3)
        fixed = self.fixed_bytes(lights, visible)
        for chunk, pairs in self._chunks(visible):
            t = self._transfer(lights, pairs)
            light = lights.ambient + fixed[chunk] + POINT_SCALE * _sum_by(
                pairs.point - chunk.start, (t.g * t.f)[:, None] * emitted[pairs.light], chunk.stop - chunk.start)
            out[chunk] = self.albedo[chunk] * LINEAR_PER_BYTE * saturate(light)
        return out

    def _chunks(self, visible: np.ndarray):
        """(point slice, its visible pairs) over chunks of points: the sparse form of V.

        Only pairs with V_ij = 1 are evaluated (6-13 % of all pairs on OpenArena levels with the
        default grid), so a chunk costs what its visible pairs cost, not N x J. The pairs of one
        visibility matrix are built once (it is fixed between refreshes) and chunked at point
        boundaries with at most about PAIRS_PER_CHUNK pairs each, bounding the temporaries.
        """
        if self._pairs_of is not visible:
            self._pairs_of, self._pairs = visible, list(self._split(visible))
        return self._pairs

    def _split(self, visible: np.ndarray):
        point, light = np.nonzero(visible)  # row-major: sorted by point
        count = len(point)
        first_pair = 0
        first_point = 0
        while first_point < self.point_count:
            end_pair = min(first_pair + PAIRS_PER_CHUNK, count)
            end_point = self.point_count if end_pair >= count else max(int(point[end_pair]), first_point + 1)
            end_pair = int(np.searchsorted(point, end_point))
            pick = slice(first_pair, end_pair)
            yield slice(first_point, end_point), _Pairs(point=point[pick], light=light[pick],
                                                        positions=self.points[point[pick]],
                                                        normals=self.normals[point[pick]])
            first_pair, first_point = end_pair, end_point

    def _transfer(self, lights: Lights, pairs: "_Pairs") -> "_Transfer":
        """g = cos / (q max(q, R0)^2) per visible pair (0 where the light is behind the point now),
        and the pieces of its gradient: d, q, n.d."""
        d = lights.positions[pairs.light] - pairs.positions  # (P, 3)
        q = np.maximum(np.sqrt(np.einsum("pk,pk->p", d, d)), 1e-9)
        ndot = np.einsum("pk,pk->p", d, pairs.normals)
        front = ndot > 0
        g = np.where(front, ndot / (q * clamped_distance_squared(q)), 0.0)
        axes, cones = lights.cones()
        f = spot_factors(-d, axes[pairs.light], cones[pairs.light])
        return _Transfer(g=g, d=d, q=q, ndot=np.where(front, ndot, 0.0), f=f)

    def objective(self, lights: Lights, visible: np.ndarray, with_gradient: bool = True) -> Gradient:
        """L and dL / d(every light parameter and the ambient), visibility fixed: the compiled pass of
        objective_kernel.py (the formula of objective_numpy, one loop over the visible pairs). `visible` is
        read, never modified: its pairs are cached until another matrix is passed."""
        if visible.shape != (self.point_count, lights.count):
            raise ValueError(f"visibility of shape {visible.shape} does not match {self.point_count} target points "
                             f"x {lights.count} lights")
        if self._csr_of is not visible:
            self._csr_of, self._csr = visible, objective_kernel.csr(visible)
        starts, pair_lights = self._csr
        chunks = objective_kernel.chunks_for(self.point_count)
        values = np.zeros(chunks)
        grad_pos = np.zeros((chunks, lights.count, 3))
        grad_emitted = np.zeros((chunks, lights.count, 3))
        grad_axes = np.zeros((chunks, lights.count, 3))
        grad_cones = np.zeros((chunks, lights.count))
        grad_ambient = np.zeros((chunks, 3))
        axes, cones = lights.cones()
        fixed = self.fixed_bytes(lights, visible)
        # dL/dE per point, for the surface lights' and the suns' gradients (written only when they exist)
        upstream = np.zeros((self.point_count if (self.surface_count or lights.sun_count) and with_gradient else 0, 3))
        emitted = np.ascontiguousarray(lights.colours * lights.intensities[:, None], dtype=np.float64)
        objective_kernel.run(min(self.threads, objective_kernel.threads_for(self.point_count)),
                             *(_f64(a) for a in (self.points, self.normals, self.albedo, self.radiance,
                                                 self.weights, fixed)),
                             np.asarray(lights.ambient, dtype=np.float64),
                             np.ascontiguousarray(lights.positions, dtype=np.float64), emitted, axes, cones, starts,
                             pair_lights, POINT_SCALE, MIN_DISTANCE, SPOT_EDGE, BYTE_MAX, LINEAR_PER_BYTE, self.norm,
                             with_gradient, values, grad_pos, grad_emitted, grad_axes, grad_cones, grad_ambient, upstream)
        # the slices summed in slice order: the same bits on any number of threads
        emitted_sum = _ordered_sum(grad_emitted)
        sun_directions, sun_colours, sun_intensities = self._sun_gradient(lights, visible, upstream)
        return Gradient(
            value=float(_ordered_sum(values)) / self.norm,
            positions=_ordered_sum(grad_pos),
            colours=emitted_sum * lights.intensities[:, None],
            intensities=np.einsum("jk,jk->j", emitted_sum, lights.colours),
            ambient=_ordered_sum(grad_ambient),
            surface_values=self._surface_gradient(upstream),
            spot_directions=_ordered_sum(grad_axes),
            radius_by_dist=_ordered_sum(grad_cones),
            sun_directions=sun_directions, sun_colours=sun_colours, sun_intensities=sun_intensities,
        )

    def _surface_gradient(self, upstream: np.ndarray) -> np.ndarray:
        """dL/d(value) of every surface light from dL/dE (N, 3): sum_i dL/dE_i . basis_s(i)."""
        if self.surface_count == 0 or len(upstream) == 0:
            return np.zeros(self.surface_count)
        return np.einsum("snk,nk->s", self.surface_basis, upstream)

    def objective_numpy(self, lights: Lights, visible: np.ndarray, with_gradient: bool = True) -> Gradient:
        """objective() in numpy, chunk by chunk over (pairs, 3) arrays: the reference the compiled pass is
        tested against (and the former implementation, lights.md §3)."""
        value = 0.0
        grad_pos = np.zeros((lights.count, 3))
        grad_emitted = np.zeros((lights.count, 3))
        grad_axes = np.zeros((lights.count, 3))
        grad_cones = np.zeros(lights.count)
        axes, cones = lights.cones()
        grad_ambient = np.zeros(3)
        upstream_all = np.zeros((self.point_count, 3))
        emitted = lights.colours * lights.intensities[:, None]
        fixed = self.fixed_bytes(lights, visible)
        for chunk, pairs in self._chunks(visible):
            t = self._transfer(lights, pairs)
            local = pairs.point - chunk.start
            albedo = self.albedo[chunk]
            h = t.g * t.f  # the spot's cone times the point light's transfer
            light = lights.ambient + fixed[chunk] + POINT_SCALE * _sum_by(local, h[:, None] * emitted[pairs.light],
                                                                          len(albedo))
            residual = albedo * LINEAR_PER_BYTE * saturate(light) - self.radiance[chunk]
            weight = self.weights[chunk][:, None]
            value += float(np.sum(weight * residual ** 2))
            if not with_gradient:
                continue
            upstream = saturate_backward(light, 2.0 * weight * residual * albedo * LINEAR_PER_BYTE / self.norm)  # dL/dE
            grad_ambient += upstream.sum(axis=0)
            upstream_all[chunk] = upstream
            back = POINT_SCALE * upstream[local]  # dL/d(sum g e), per pair
            grad_emitted += _sum_by(pairs.light, h[:, None] * back, lights.count)
            u = np.einsum("pk,pk->p", back, emitted[pairs.light])  # dL/dg per pair
            # dg/dx for q >= R0: n/q^3 - 3 (n.d) d / q^5; for q < R0: n/(R0^2 q) - (n.d) d/(R0^2 q^3)
            far = t.q >= MIN_DISTANCE
            along_normal = np.where(t.ndot > 0, 1.0 / (t.q * clamped_distance_squared(t.q)), 0.0)
            along_d = t.ndot * np.where(far, 3.0 / t.q ** 5, 1.0 / (MIN_DISTANCE * MIN_DISTANCE * t.q ** 3))
            dg = along_normal[:, None] * pairs.normals - along_d[:, None] * t.d  # dg/dx
            # the cone: dh/dx = f dg/dx - g df/dv (v = p - x), df/dN, df/dk on the soft edge (0 < f < 1)
            d_v, d_axis, d_cone = spot_factor_gradient(-t.d, axes[pairs.light], cones[pairs.light])
            per_pair = u[:, None] * (t.f[:, None] * dg - t.g[:, None] * d_v)
            grad_pos += _sum_by(pairs.light, per_pair, lights.count)
            grad_axes += _sum_by(pairs.light, (u * t.g)[:, None] * d_axis, lights.count)
            grad_cones += np.bincount(pairs.light, weights=u * t.g * d_cone, minlength=lights.count)
        sun_directions, sun_colours, sun_intensities = self._sun_gradient(
            lights, visible, upstream_all if with_gradient else np.zeros((0, 3)))
        return Gradient(
            value=value / self.norm,
            positions=grad_pos,
            colours=grad_emitted * lights.intensities[:, None],
            intensities=np.einsum("jk,jk->j", grad_emitted, lights.colours),
            ambient=grad_ambient,
            surface_values=self._surface_gradient(upstream_all) if with_gradient else np.zeros(self.surface_count),
            spot_directions=grad_axes,
            radius_by_dist=grad_cones,
            sun_directions=sun_directions, sun_colours=sun_colours, sun_intensities=sun_intensities,
        )


def spot_factors(offsets: np.ndarray, axes: np.ndarray, cones: np.ndarray) -> np.ndarray:
    """(P,) q3map2's cone factor (emitters.spot_factor) per pair: offsets v = p - x (P, 3), axes N (P, 3), cones
    radiusByDist k (P,); 1 where k = 0 (a point light). With t = v.N, r = |v - t N|: clamp((k t - r) / 32, 0, 1),
    0 for t <= 0."""
    t = np.einsum("pk,pk->p", offsets, axes)
    r = np.linalg.norm(offsets - t[:, None] * axes, axis=1)
    return np.where(cones > 0, cone_factor(t, r, cones), 1.0)


def spot_factor_gradient(offsets: np.ndarray, axes: np.ndarray,
                         cones: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(df/dv (P, 3), df/dN (P, 3), df/dk (P,)) of spot_factors, nonzero only on the soft edge (0 < f < 1) of
    spotlights: f = (k t - r) / 32, dt/dv = N, dr/dv = (w - (w.N) N) / r, dt/dN = v, dr/dN = -((w.N) v + t w) / r
    with w = v - t N (exact for any axis, not only unit ones)."""
    f = spot_factors(offsets, axes, cones)
    edge = (cones > 0) & (f > 0) & (f < 1)
    t = np.einsum("pk,pk->p", offsets, axes)
    w = offsets - t[:, None] * axes
    r = np.linalg.norm(w, axis=1)
    wn = np.einsum("pk,pk->p", w, axes)
    inv = np.divide(1.0, r, out=np.zeros_like(r), where=r > 1e-12)
    d_v = (cones[:, None] * axes - (w - wn[:, None] * axes) * inv[:, None]) / SPOT_EDGE
    d_axis = (cones[:, None] * offsets + (wn[:, None] * offsets + t[:, None] * w) * inv[:, None]) / SPOT_EDGE
    d_cone = t / SPOT_EDGE
    return np.where(edge[:, None], d_v, 0.0), np.where(edge[:, None], d_axis, 0.0), np.where(edge, d_cone, 0.0)


def _range_squared(lights: Lights) -> np.ndarray:
    """(J,) squared distance within which each light may add RANGE_MIN_BYTES (with RANGE_HEADROOM): the pairs
    beyond it cast no shadow ray."""
    reach = np.maximum(RANGE_HEADROOM * lights.intensities * lights.colours.max(axis=1), RANGE_FLOOR_INTENSITY)
    return POINT_SCALE * reach / RANGE_MIN_BYTES


def saturate(light: np.ndarray) -> np.ndarray:
    """(N, 3) bytes clamped as q3map2's ColorToBytes: scaled down to a largest channel of 255."""
    peak = light.max(axis=1, keepdims=True)
    return np.where(peak > BYTE_MAX, light * (BYTE_MAX / np.maximum(peak, BYTE_MAX)), light)


def saturate_backward(light: np.ndarray, upstream: np.ndarray) -> np.ndarray:
    """dL/dE from dL/d(saturate(E)): for a clamped row with largest channel k,
    d(255 E_c / E_k)/dE_m = (255 / E_k) (delta_cm - delta_mk E_c / E_k)."""
    peak = light.max(axis=1, keepdims=True)
    over = peak[:, 0] > BYTE_MAX
    out = upstream.copy()
    if over.any():
        p, e, b = peak[over], light[over], upstream[over]
        scaled = (BYTE_MAX / p) * b
        top = np.argmax(e, axis=1)
        scaled[np.arange(len(e)), top] -= (BYTE_MAX / p[:, 0]) * np.einsum("nk,nk->n", b, e) / p[:, 0]
        out[over] = scaled
    return out


@dataclass(frozen=True)
class _Pairs:
    point: np.ndarray  # (P,) int64 target point
    light: np.ndarray  # (P,) int64 light
    positions: np.ndarray  # (P, 3) the points' positions
    normals: np.ndarray  # (P, 3) the points' normals


@dataclass(frozen=True)
class _Transfer:
    g: np.ndarray  # (P,)
    d: np.ndarray  # (P, 3)
    q: np.ndarray  # (P,)
    ndot: np.ndarray  # (P,) n.d where the light is in front, else 0
    f: np.ndarray  # (P,) the spotlight's cone factor (1 for a point light)


def _f64(array: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(array, dtype=np.float64)


def _ordered_sum(slices: np.ndarray) -> np.ndarray:
    """The sum over the first axis, one slice after another (not numpy's pairwise order: fixed, simple)."""
    total = np.zeros(slices.shape[1:])
    for part in slices:
        total = total + part
    return total


def _sum_by(index: np.ndarray, values: np.ndarray, length: int) -> np.ndarray:
    """(length, 3): rows of `values` (P, 3) summed by `index` (a scatter-add, one bincount a column)."""
    return np.stack([np.bincount(index, weights=values[:, k], minlength=length) for k in range(3)], axis=1)
