"""One level from its BSP to a fitted rig: the scene (target, shadow-ray geometry, open-space test)
and the fit (initial grid, scheme), wired together once for the CLI, the evaluation and the tests."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..scenes.errors import BspError
from ..scenes.levels import Level, default_pak
from ..scenes.raycast import EmbreeRaycaster
from ..scenes.solid import SolidTester
from ..scenes.surfaces import ray_geometry
from .emitters import Emitters, Spots, read_shader_scripts, shader_light, surface_emitters
from .model import ForwardModel, Lights
from .optimise import FitResult, Fitter, initial_grid, initial_intensity
from .rig import EntityLights, Rig
from .settings import DEFAULT_GRID, DEFAULT_MAX_EDGE, DEFAULT_REFRESH, DEFAULT_SCHEME, SCHEMES
from .surfaces import lit_mesh, subdivide
from .target import DEFAULT_SAMPLES_PER_SIDE, RadianceTarget, build_target
from .textures import Albedo, load_albedo, texture_paks, uniform_albedo

# MAX_TARGET_POINTS bounds the cost of DEFAULT_MAX_EDGE's subdivision (settings.py) on big levels.
MAX_TARGET_POINTS = 100_000
BOX_MARGIN = 1.0  # Quake units inside the world box: positions on its faces are outside the map


@dataclass
class LevelScene:
    level: Level
    target: RadianceTarget
    triangles: np.ndarray  # (T, 3) the target mesh's triangles (indices into target.positions)
    albedo: Albedo
    model: ForwardModel
    is_open: Callable[[np.ndarray], np.ndarray]
    bounds: tuple[np.ndarray, np.ndarray]  # Quake units: the lights' box
    max_edge: float | None  # the subdivision actually used (None: BSP vertices only)
    seconds: dict[str, float] = field(default_factory=dict)


def load_scene(level: Level, max_edge: float | None = DEFAULT_MAX_EDGE, textures: bool = True,
               samples_per_side: int = DEFAULT_SAMPLES_PER_SIDE, max_points: int = MAX_TARGET_POINTS) -> LevelScene:
    """The level's radiance target and forward model. With `max_edge`, target triangles are subdivided
    to it, doubled until the target has at most `max_points` points."""
    seconds: dict[str, float] = {}
    clock = time.perf_counter()
    bsp = level.bsp
    mesh = lit_mesh(bsp)
    used_edge = max_edge
    if max_edge is not None:
        fine = subdivide(mesh, max_edge)
        while fine.vertex_count > max_points and used_edge is not None:
            used_edge *= 2.0
            fine = subdivide(mesh, used_edge)
            if used_edge > 4096.0:  # coarser than any face: the BSP's own vertices
                fine, used_edge = mesh, None
        mesh = fine
    seconds["mesh"] = time.perf_counter() - clock
    clock = time.perf_counter()
    names = [bsp.shader_name(index) for index in range(len(bsp.shaders))]
    albedo = load_albedo(names, texture_paks(level.pak, default_pak().parent)) if textures \
        else uniform_albedo(len(names))
    seconds["textures"] = time.perf_counter() - clock
    clock = time.perf_counter()
    target = build_target(mesh, bsp.lightmaps, albedo, samples_per_side)
    seconds["target"] = time.perf_counter() - clock
    if not np.any(target.radiance > 0):
        raise BspError(f"{level.location}: no surface carries baked light (every lightmap texel and vertex colour "
                       f"of its {target.point_count:,} target points is black): compile the level with q3map2 -light")
    clock = time.perf_counter()
    geometry = ray_geometry(bsp)
    raycaster = EmbreeRaycaster(geometry.vertices, geometry.triangles)
    solid = SolidTester(bsp)
    seconds["geometry"] = time.perf_counter() - clock

    def is_open(points: np.ndarray) -> np.ndarray:
        return ~solid.solid_or_outside(points)

    bounds = (bsp.world_mins + BOX_MARGIN, bsp.world_maxs - BOX_MARGIN)
    return LevelScene(level=level, target=target, triangles=mesh.triangles, albedo=albedo, model=ForwardModel(target, raycaster),
                      is_open=is_open, bounds=bounds, max_edge=used_edge, seconds=seconds)


def fit_scene(scene: LevelScene, grid: tuple[int, int, int] = DEFAULT_GRID, scheme: str = DEFAULT_SCHEME,
              refresh: int = DEFAULT_REFRESH, progress: Callable[[int, int], None] | None = None) -> FitResult:
    if scheme not in SCHEMES:
        raise ValueError(f"scheme {scheme!r} is not one of {', '.join(SCHEMES)}")
    start = initial_grid(scene.bounds[0], scene.bounds[1], grid, scene.is_open)
    if len(start) == 0:
        raise ValueError(f"{scene.level.name}: no cell centre of the {'x'.join(map(str, grid))} grid is in open "
                         f"space; use a finer --grid")
    lights = initial_intensity(scene.model, start)
    fitter = Fitter(scene.model, scene.bounds, scene.is_open, scene.target.positions, refresh=refresh,
                    progress=progress)
    return fitter.fit(lights, SCHEMES[scheme])


def rig_of(scene: LevelScene, result: FitResult, grid: tuple[int, int, int], scheme: str) -> Rig:
    """The fitted lights as a rig; lights that went dark (intensity 0) are dropped."""
    lights = result.lights
    lit = lights.intensities * lights.colours.max(axis=1) > 0
    info = {"grid": list(grid), "initial_lights": int(lights.count), "iterations": result.iterations,
            "rays": result.rays, "seconds": round(result.seconds, 3), "target_points": scene.target.point_count,
            "projection_loss": round(scene.target.projection_loss, 6),
            "max_edge": scene.max_edge, "textures_found": scene.albedo.found}
    return Rig.from_quake(lights.positions[lit], lights.colours[lit], lights.intensities[lit], ambient=lights.ambient,
                          level=scene.level.name, bsp_sha256=scene.level.sha256, scheme=scheme,
                          objective=float(result.objective), extra=info)


def level_emitters(level: Level, real: EntityLights, surfaces: bool = True) -> Emitters:
    """The light elements of the level's compile that are not plain point lights: its spotlights
    (from the light entities) and, with `surfaces`, the surface lights of its shaders (the
    `scripts/*.shader` of the pk3s beside it, emitters.py)."""
    spot = real.spot
    quake = real.rig.quake_positions()
    spots = Spots(positions=quake[spot], colours=real.rig.colours[spot], intensities=real.rig.intensities[spot],
                  directions=real.spot_direction[spot], radius_by_dist=real.radius_by_dist[spot])
    emitters = Emitters(spots=spots)
    if not surfaces:
        return emitters
    bsp = level.bsp
    paks = texture_paks(level.pak, default_pak().parent)
    scripts = read_shader_scripts(paks)
    images: dict[str, np.ndarray | None] = {}

    def image_colour(path: str) -> np.ndarray | None:
        if path not in images:
            albedo = load_albedo([path], paks)
            images[path] = None if albedo.images[0] is None else albedo.images[0].reshape(-1, 3).mean(axis=0)
        return images[path]

    shaders = {}
    for index in range(len(bsp.shaders)):
        light = shader_light(scripts, bsp.shader_name(index), image_colour)
        if light is not None:
            shaders[index] = light
    areas, positions, colours, intensities, splash_shader = surface_emitters(bsp, shaders)
    emitters.areas, emitters.shaders = areas, shaders
    emitters.splash_positions, emitters.splash_colours, emitters.splash_intensities = positions, colours, intensities
    emitters.splash_shader = splash_shader
    return emitters


def point_lights_of(real: EntityLights) -> Lights:
    """The level's light entities that are plain point lights (spotlights are emitters), with its ambient."""
    keep = ~real.spot if len(real.spot) == real.rig.count else np.ones(real.rig.count, bool)
    return Lights(real.rig.quake_positions()[keep], real.rig.colours[keep], real.rig.intensities[keep],
                  ambient=real.rig.ambient.copy())
