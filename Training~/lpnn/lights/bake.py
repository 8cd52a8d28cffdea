"""Probe lighting from a light rig: Unity SH L2 at arbitrary points (Documentation~/lights.md §8).

At every point p (Unity metres in, Quake units inside), in the linear units of the light grid and the
lightmaps (4/255 per byte, "texture at full brightness"), the stored SH is the sum of
  - the rig's ambient b (bytes added to every luxel): DC += b 4/255;
  - direct light: every light j visible from p (pointlight.py: q3map2's 7500 I / max(r, 16)^2 bytes, no
    cosine, <= 1 byte dropped, Embree shadow ray) adds a clamped-cosine lobe c_j max(0, n . l_j), its
    normal-incidence value c_j clamped to 255 bytes keeping the hue (no single light brighter than a
    saturated luxel), projected onto L2 (sh.clamped_cosine_factors, Unity axes); every sun whose ray from p
    meets the sky first (emitters.sunlit) adds the lobe of c = colour x intensity along its direction, clamped
    the same way (q3map2's LightContributionToPoint, EMIT_SUN);
  - one bounce: the rig re-lights the level's surfaces (the forward model of model.py: albedo x
    saturated luxel, i.e. the radiance target [lights] fits), and K fixed directions w_k (a
    Fibonacci sphere, gather_directions) gather the radiance L_k of the first surface they hit in
    front: f(n) = (1/pi) integral L(w) max(0, n . w) dw ~ sum_k (4/K) L_k max(0, n . w_k), projected
    the same way. Rays that leave the level, or whose first hit is a surface without baked light
    (sky, emissive, see-through) or the back of a face, gather nothing.
A white Lambertian surface with normal n at p shows the SH evaluated at n: the same scale as the
lightmaps, so a rig that reproduces a level's lightmaps gives probes on the lightmaps' scale.
Everything is vectorised over chunks of points; no random numbers: the same inputs give the same SH.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..core.sh import SH_COEFFICIENTS, SH_FLOATS, clamped_cosine_factors
from ..scenes.coords import quake_to_unity, unity_to_quake
from ..scenes.levels import Level
from ..scenes.lightgrid import LINEAR_PER_BYTE
from ..scenes.raycast import EmbreeRaycaster
from ..scenes.surfaces import ray_geometry
from .emitters import Suns, sunlit
from .model import POINT_SCALE, ForwardModel, Lights, saturate
from .pipeline import load_scene
from .pointlight import visible_light
from .rig import Rig, RigError
from .target import RadianceTarget

GATHER_DIRECTIONS = 128
POINTS_PER_CHUNK = 1024  # direct: points x lights pairs; bounce: points x directions rays at a time
HIT_TOLERANCE = 1.0  # Quake units: an occluder this close before the lit surface's hit is that surface


@dataclass(frozen=True)
class BakeSettings:
    directions: int = GATHER_DIRECTIONS  # gather rays per point for the bounce
    bounce: bool = True
    ambient: bool = True

    def __post_init__(self) -> None:
        if self.directions < 1:
            raise ValueError(f"gather directions {self.directions} must be at least 1")


DEFAULT_BAKE = BakeSettings()


@dataclass(frozen=True)
class BakeScene:
    """The geometry a rig lights, in Quake units: lit surfaces (positions, normals, albedo of the
    radiance target, and its triangles), every occluder of the ray geometry (what a gather ray sees) and the
    shadow casters of q3map2's compile (what the direct light and the surfaces' radiance are shadowed by,
    shadows.py; the occluders when not given)."""

    target: RadianceTarget
    triangles: np.ndarray  # (T, 3) into target.positions
    occluders: EmbreeRaycaster
    surfaces: EmbreeRaycaster
    reach: float  # the longest gather ray (Quake units): the diagonal of the surfaces' box
    shadows: EmbreeRaycaster
    sky: EmbreeRaycaster | None = None  # the level's sky triangles, which a sun's ray must meet first

    @classmethod
    def build(cls, target: RadianceTarget, triangles: np.ndarray, occluders: EmbreeRaycaster,
              shadows: EmbreeRaycaster | None = None, sky: EmbreeRaycaster | None = None) -> "BakeScene":
        triangles = np.asarray(triangles, dtype=np.int64)
        positions = target.positions
        reach = float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0))) if len(positions) else 0.0
        return cls(target=target, triangles=triangles, occluders=occluders,
                   surfaces=EmbreeRaycaster(positions, triangles), reach=max(reach, 1.0),
                   shadows=occluders if shadows is None else shadows, sky=sky)

    def rays_cast(self) -> int:
        """Rays cast so far by the scene's raycasters (the shadow casters counted once when they are the occluders)."""
        raycasters = {id(r): r for r in (self.occluders, self.surfaces, self.shadows)}
        return sum(r.rays_cast for r in raycasters.values())

    @classmethod
    def from_level(cls, level: Level) -> "BakeScene":
        """The level's lit surfaces as `lpnn scene lights` builds them (default subdivision, textures), its shadow
        casters (the scene's forward model's) and its whole ray geometry as the gather's occluders."""
        scene = load_scene(level)
        geometry = ray_geometry(level.bsp)
        return cls.build(scene.target, scene.triangles, EmbreeRaycaster(geometry.vertices, geometry.triangles),
                         shadows=scene.model.raycaster, sky=scene.model.sky)


@dataclass
class BakeResult:
    sh: np.ndarray  # (N, 27) float64, Unity convention, linear units (4/255 per byte)
    rays: int = 0
    seconds: dict[str, float] = field(default_factory=dict)  # surfaces, direct, bounce


def gather_directions(count: int) -> np.ndarray:
    """(count, 3) unit vectors of a Fibonacci sphere (golden-angle spiral, equal-area bands in z):
    a fixed, nearly uniform set whose mean is ~0, so a constant radiance gathers its exact DC."""
    if count < 1:
        raise ValueError(f"gather directions {count} must be at least 1")
    k = np.arange(count, dtype=np.float64)
    z = 1.0 - (2.0 * k + 1.0) / count
    radius = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    angle = k * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([radius * np.cos(angle), radius * np.sin(angle), z], axis=1)


def rig_lights(rig: Rig) -> Lights:
    return Lights(positions=rig.quake_positions(), colours=rig.colours.copy(), intensities=rig.intensities.copy(),
                  ambient=rig.ambient.copy(), sun_directions=np.array([s.quake_direction() for s in rig.suns]).reshape(-1, 3),
                  sun_colours=np.array([s.colour for s in rig.suns], dtype=np.float64).reshape(-1, 3),
                  sun_intensities=np.array([s.intensity for s in rig.suns], dtype=np.float64))


def surface_radiance(scene: BakeScene, rig: Rig) -> np.ndarray:
    """(V, 3) the radiance the rig gives the lit surfaces' vertices (model.py, shadow rays and suns included)."""
    model = ForwardModel(scene.target, scene.shadows)
    model.sky = scene.sky
    lights = rig_lights(rig)
    return model.radiance_of(lights, model.visibility(lights))


def bake_sh(scene: BakeScene, rig: Rig, unity_points: np.ndarray, settings: BakeSettings = DEFAULT_BAKE,
            progress: Callable[[int, int], None] | None = None) -> BakeResult:
    """SH (N, 27) at points (N, 3) in Unity metres lit by `rig` (module docstring)."""
    reason = not_bakeable(rig)
    if reason is not None:
        raise RigError(f"the probe baker bakes a rig's point lights, suns and ambient, not its surface lights; "
                       f"this rig {reason}")
    points = np.asarray(unity_points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3 or not np.isfinite(points).all():
        raise ValueError(f"bake positions must be finite (N, 3) Unity metres, got shape {points.shape}")
    quake = unity_to_quake(points)
    result = BakeResult(sh=np.zeros((len(points), SH_FLOATS)))
    rays_before = scene.rays_cast()
    clock = time.perf_counter()
    radiance = surface_radiance(scene, rig) if settings.bounce else None
    result.seconds["surfaces"] = time.perf_counter() - clock
    directions = gather_directions(settings.directions)
    emitted = rig.colours * rig.intensities[:, None] * POINT_SCALE
    lights = rig.quake_positions()
    result.seconds["direct"] = result.seconds["bounce"] = 0.0
    for start in range(0, len(points), POINTS_PER_CHUNK):
        chunk = slice(start, min(start + POINTS_PER_CHUNK, len(points)))
        clock = time.perf_counter()
        sh = direct_sh(quake[chunk], lights, emitted, scene.shadows) + sun_sh(quake[chunk], rig, scene)
        result.seconds["direct"] += time.perf_counter() - clock
        if radiance is not None:
            clock = time.perf_counter()
            sh += bounce_sh(quake[chunk], scene, radiance, directions)
            result.seconds["bounce"] += time.perf_counter() - clock
        if settings.ambient:
            sh[:, 0::SH_COEFFICIENTS] += LINEAR_PER_BYTE * rig.ambient
        result.sh[chunk] = sh
        if progress is not None:
            progress(chunk.stop, len(points))
    result.rays = scene.rays_cast() - rays_before
    return result


def not_bakeable(rig: Rig) -> str | None:
    """What the baker would leave out of the rig (its surface lights), or None: such a rig is refused."""
    if rig.surfaces:
        return (f"has {len(rig.surfaces)} surface light(s) ({', '.join(s.shader for s in rig.surfaces[:3])}...): "
                f"recover it without --surfaces, or remove its 'surfaces' list (their light is then missing from the "
                f"probes)")
    return None


def sun_sh(points: np.ndarray, rig: Rig, scene: BakeScene) -> np.ndarray:
    """(C, 27): the lobe of every sun whose ray from the point meets the sky before a shadow caster (Quake units in)."""
    out = np.zeros((len(points), SH_FLOATS))
    sky = Suns(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.int64), sky=scene.sky)
    for sun in rig.suns:
        direction = sun.quake_direction()
        lit = sunlit(points, np.broadcast_to(direction, points.shape).copy(), sky, scene.shadows)
        colour = saturate((sun.colour * sun.intensity)[None])[0] * LINEAR_PER_BYTE
        factors = clamped_cosine_factors(quake_to_unity(direction[None], scale=1.0))[0]  # (9,)
        out[lit] += np.outer(colour, factors).reshape(-1)
    return out


def direct_sh(points: np.ndarray, lights: np.ndarray, emitted: np.ndarray,
              occluders: EmbreeRaycaster | None) -> np.ndarray:
    """(C, 27): every visible light's clamped-cosine lobe, at most 255 bytes each (Quake units in)."""
    colour, unit = visible_light(points, lights, emitted, occluders)  # (C, J, 3) bytes, (C, J, 3)
    colour = saturate(colour.reshape(-1, 3)).reshape(colour.shape) * LINEAR_PER_BYTE
    factors = clamped_cosine_factors(quake_to_unity(unit, scale=1.0))  # (C, J, 9)
    return np.einsum("cjk,cji->cki", colour, factors).reshape(len(points), SH_FLOATS)


def bounce_sh(points: np.ndarray, scene: BakeScene, radiance: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """(C, 27): the radiance of the first lit surface in front along every gather direction."""
    count, k = len(points), len(directions)
    origins = np.repeat(points, k, axis=0)
    rays = np.tile(directions, (count, 1))
    distance, triangle = scene.surfaces.first_hits(origins, rays, scene.reach)
    hit = triangle >= 0
    gathered = np.zeros((count * k, 3))
    if hit.any():
        blocked, _ = scene.occluders.cast(origins[hit], rays[hit], float(distance[hit].max()))
        seen = blocked >= distance[hit] - HIT_TOLERANCE
        index = np.flatnonzero(hit)[seen]
        corners = scene.triangles[triangle[index]]  # (H, 3)
        weights = barycentric(scene.target.positions[corners], origins[index] + distance[index, None] * rays[index])
        normal = np.einsum("hc,hck->hk", weights, scene.target.normals[corners])
        front = np.einsum("hk,hk->h", normal, rays[index]) < 0
        gathered[index[front]] = np.einsum("hc,hck->hk", weights[front], radiance[corners[front]])
    factors = clamped_cosine_factors(quake_to_unity(directions, scale=1.0))  # (K, 9)
    per_point = gathered.reshape(count, k, 3)
    return ((4.0 / k) * np.einsum("pkc,ki->pci", per_point, factors)).reshape(count, SH_FLOATS)


def barycentric(corners: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(H, 3) barycentric weights of points (H, 3) on triangles (H, 3, 3), clipped to the triangle."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    v0, v1, v2 = b - a, c - a, points - a
    d00, d01, d11 = (np.einsum("hk,hk->h", x, y) for x, y in ((v0, v0), (v0, v1), (v1, v1)))
    d20, d21 = np.einsum("hk,hk->h", v2, v0), np.einsum("hk,hk->h", v2, v1)
    denominator = d00 * d11 - d01 * d01
    safe = np.where(np.abs(denominator) > 0, denominator, 1.0)
    v = np.where(np.abs(denominator) > 0, (d11 * d20 - d01 * d21) / safe, 1.0 / 3.0)
    w = np.where(np.abs(denominator) > 0, (d00 * d21 - d01 * d20) / safe, 1.0 / 3.0)
    weights = np.clip(np.stack([1.0 - v - w, v, w], axis=1), 0.0, 1.0)
    return weights / weights.sum(axis=1, keepdims=True)

