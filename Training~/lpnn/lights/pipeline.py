"""One level from its BSP to a fitted rig: the scene (target, shadow-ray geometry, open-space test)
and the fit (initial grid, scheme), wired together once for the CLI, the evaluation and the tests."""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from ..scenes.errors import BspError
from ..scenes.levels import Level, default_pak
from ..scenes.raycast import EmbreeRaycaster
from ..scenes.solid import SolidTester
from ..scenes.coords import quake_to_unity
from ..scenes.surfaces import SURF_SKY
from .compare import SurfacePieces, equal_flux_intensity
from .emitters import (AREA_SCALE, BACKSPLASH_DISTANCE, BACKSPLASH_FRACTION, DEFAULT_LIGHT_SUBDIVIDE,
                       FORM_FACTOR_VALUE_SCALE, Emitters, ShaderLight, ShaderScripts, Spots, Suns,
                       read_shader_scripts, script_declares_sky, script_order,
                       shader_light, shader_suns, surface_bases, surface_emitters, surface_triangles)
from .merge import merge_spotlights, settle_on_fixtures
from .model import ForwardModel, Lights
from .optimise import FitResult, Fitter, initial_grid, initial_intensity
from .rig import EntityLights, Rig, RigError, Sun, SurfaceLight, worldspawn_ambient
from .shadows import shadow_raycaster
from .settings import (AMBIENTS, DEFAULT_AMBIENT, DEFAULT_GRID, DEFAULT_MAX_EDGE, DEFAULT_REFRESH, DEFAULT_SCHEME,
                       DEFAULT_SCRIPT_LIGHTS, DEFAULT_START, DEFAULT_SUNS, FITTED_AMBIENT, GRID_START, HELD_SCRIPTS,
                       FIXTURE_REACH, MERGE_PASS, PEAK_START, SCHEMES, SCRIPT_LIGHTS, STARTS)
from .starts import (DEFAULT_PEAKS, SPOT_REACH, UP, PeakSettings, Starts, ceiling_starts, disc_gains, fixture_starts,
                     lit_by_spotlights, peak_starts, under_a_ceiling, with_grid_fallback)
from .surfaces import lit_mesh, subdivide
from .target import DEFAULT_SAMPLES_PER_SIDE, RadianceTarget, build_target
from .textures import Albedo, load_albedo, texture_paks, uniform_albedo

# MAX_TARGET_POINTS bounds the cost of DEFAULT_MAX_EDGE's subdivision (settings.py) on big levels.
MAX_TARGET_POINTS = 100_000
BOX_MARGIN = 1.0  # Quake units inside the world box: positions on its faces are outside the map
CANDIDATE_VALUE = 1000.0  # q3map_surfacelight a candidate surface light's basis is built at (script_lights)
CANDIDATE_SOURCE = "candidate: "  # a candidate's ShaderLight.colour_source starts so: no script gave its value
LIGHT_WORD = "light"  # a shader whose name has it draws a light (names_a_light)


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
    # with add_surface_lights: the BSP shaders of model.surface_basis, and their emitters (values as built)
    surface_shaders: list[int] = field(default_factory=list)
    surface_emitters: Emitters = field(default_factory=Emitters)


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
    raycaster = shadow_raycaster(bsp)  # q3map2's shadow casters: no patches, no entity surfaces by default
    solid = SolidTester(bsp)
    seconds["geometry"] = time.perf_counter() - clock

    def is_open(points: np.ndarray) -> np.ndarray:
        return ~solid.solid_or_outside(points)

    bounds = (bsp.world_mins + BOX_MARGIN, bsp.world_maxs - BOX_MARGIN)
    model = ForwardModel(target, raycaster)
    model.sky = sky_raycaster(bsp)  # for fitted suns (fit_scene(suns=...))
    return LevelScene(level=level, target=target, triangles=mesh.triangles, albedo=albedo, model=model,
                      is_open=is_open, bounds=bounds, max_edge=used_edge, seconds=seconds)


def start_positions(scene: LevelScene, grid: tuple[int, int, int], start: str = DEFAULT_START,
                    peaks: PeakSettings = DEFAULT_PEAKS) -> Starts:
    """Where the fit's lights start (starts.py, lights.md §4): the open cells of `grid`, or with `start` "peaks"
    the peaks of the baked light with those cells as fallback."""
    if start not in STARTS:
        raise ValueError(f"start {start!r} is not one of {', '.join(STARTS)}")
    cells = initial_grid(scene.bounds[0], scene.bounds[1], grid, scene.is_open)
    if start == GRID_START:
        return Starts(cells, np.zeros(len(cells)), 0)
    target = scene.target
    found = peak_starts(target.positions, target.normals, target.radiance, target.albedo, scene.is_open, peaks)
    inside = _in_bounds(scene, found.positions)
    found = Starts(found.positions[inside], found.intensities[inside], int(inside.sum()))
    return with_grid_fallback(found, cells, peaks.fallback_distance)


def fit_scene(scene: LevelScene, grid: tuple[int, int, int] = DEFAULT_GRID, scheme: str = DEFAULT_SCHEME,
              refresh: int = DEFAULT_REFRESH, progress: Callable[[int, int], None] | None = None,
              spots: bool | None = None, start: str = DEFAULT_START, peaks: PeakSettings = DEFAULT_PEAKS,
              suns: bool | None = None, ambient: str = DEFAULT_AMBIENT,
              scripts: str = DEFAULT_SCRIPT_LIGHTS) -> FitResult:
    """With `spots` (None: fits_spots's default), every start position starts both a point light and a q3map2
    spotlight (pointing down), the spotlights' axes and cones fitted too; with `suns` (None: fits_sun's default), one
    sun whose direction, colour and intensity are fitted, lighting what sees the level's sky surfaces; `ambient`: held
    at the worldspawn's or fitted (held_ambient, lights.md §4). With spotlights and the peak start, the fitted
    spotlights within the starts' merge distance of a stronger one are folded into it, the spotlights settle on the
    light fixtures' starts within FIXTURE_REACH merge distances (a fixture left free taking a share of its nearest
    spotlight: merge.settle_on_fixtures) and a second pass (MERGE_PASS) starts from there (merge.py, lights.md §4).
    `scripts` HELD_SCRIPTS: the surface lights with a script value and the scripts' suns are held at what the scripts
    say (held_script_values, held_suns); FITTED_SCRIPTS: fitted."""
    suns = fits_sun(scene, suns)
    held = held_ambient(scene.level, ambient)
    if scripts not in SCRIPT_LIGHTS:
        raise ValueError(f"scripts {scripts!r} is not one of {', '.join(SCRIPT_LIGHTS)}")
    values = held_script_values(scene) if scripts == HELD_SCRIPTS else None
    script_suns = held_suns(scene, suns) if scripts == HELD_SCRIPTS else None
    spots = fits_spots(scene, spots, start, peaks)
    if scheme not in SCHEMES:
        raise ValueError(f"scheme {scheme!r} is not one of {', '.join(SCHEMES)}")
    starts = start_positions(scene, grid, start, peaks)
    if len(starts.positions) == 0:
        raise ValueError(f"{scene.level.name}: no cell centre of the {'x'.join(map(str, grid))} grid is in open "
                         f"space and no peak of the baked light gave a start; use a finer --grid")
    positions = starts.positions
    relative = None
    if starts.from_peaks:  # the peaks' estimated intensities; grid cells (no estimate) the peaks' median
        relative = np.where(starts.intensities > 0, starts.intensities,
                            np.median(starts.intensities[:starts.from_peaks]))
    flags = None
    if spots:
        spot_positions, spot_relative = spotlight_starts(scene, starts, relative, start, peaks)
        flags = np.repeat([False, True], [len(positions), len(spot_positions)])
        positions = np.concatenate([positions, spot_positions])
        relative = None if relative is None else np.concatenate([relative, spot_relative])
    lights = initial_intensity(scene.model, positions, spots=flags, relative=relative, sun=suns, ambient=held,
                               held_values=values, held_suns=script_suns)
    fitter = Fitter(scene.model, scene.bounds, scene.is_open, scene.target.positions, refresh=refresh,
                    progress=progress, fit_ambient=held is None,
                    held_values=None if values is None else ~np.isnan(values), hold_suns=script_suns is not None)
    first = fitter.fit(lights, SCHEMES[scheme])
    if not (spots and start == PEAK_START):
        return first
    merged = merge_spotlights(first.lights, peaks.merge_distance)
    merged = settle_on_fixtures(merged, _fixture_starts(scene, peaks).positions, FIXTURE_REACH * peaks.merge_distance)
    if merged is first.lights:
        return first
    return replace(second_pass(fitter, merged, len(SCHEMES[scheme])), initial_lights=first.initial_lights)


def second_pass(fitter: Fitter, lights: Lights, phases_before: int) -> FitResult:
    """MERGE_PASS from the merged `lights` on the first pass's `fitter` (Fitter.fit: its clock, iteration count and
    curve go on), the new pass's phases numbered after the first's `phases_before`: the result is the second pass's
    best point, so a first-pass point with the split spotlights does not come back."""
    before = len(fitter.curve)
    second = fitter.fit(lights, MERGE_PASS)
    curve = second.curve[:before] + [replace(point, phase=point.phase + phases_before) for point in second.curve[before:]]
    return replace(second, curve=curve)


def held_script_values(scene: LevelScene) -> np.ndarray:
    """(S,) the q3map_surfacelight value a fit holds for each of the scene's surface lights (add_surface_lights): its
    script's where a script the level was compiled with gives it one (script_lights), NaN for a candidate without
    one (fitted). q3map2 makes every surface of such a shader an area light of exactly that value (light.c
    CreateSurfaceLights, `si->value`), so where the script is the level's the value is known; the lightmaps alone
    let point lights near the surface stand in for it, which the light grid (light in the air) shows (lights.md §4)."""
    lights = scene.surface_emitters.shaders
    return np.array([np.nan if lights[shader].colour_source.startswith(CANDIDATE_SOURCE) else lights[shader].value
                     for shader in scene.surface_shaders], dtype=np.float64)


def held_suns(scene: LevelScene, suns: bool) -> Suns | None:
    """The suns a fit holds where it would fit one (`suns`): the level's shader suns (level_suns: the q3map_sun lines
    of the scripts it was compiled with, as q3map2's light.c CreateSunLight makes them), or None where the scripts
    give none (a sun is fitted, fits_sun)."""
    if not suns:
        return None
    found = level_suns(scene.level)
    return found if found.count else None


def held_ambient(level: Level, ambient: str = DEFAULT_AMBIENT) -> np.ndarray | None:
    """The ambient a fit holds (3,) bytes, or None where it fits it: with `ambient` WORLDSPAWN_AMBIENT, what the
    worldspawn records (rig.worldspawn_ambient: `_ambient`, else `ambient`, x `_color`, as q3map2's light.c
    LightWorld reads it) where it records one (not 0) and no `_minlight` (LightWorld's floor on every luxel, which the
    model lacks and a fitted ambient stands in for). These keys stay in a compiled level's entity lump where its
    light entities were stripped. The lightmaps cannot tell a byte of ambient from a byte of light that falls on
    every surface alike (a sky's), but the light grid holds none of the ambient (compare.py). Where no ambient is
    recorded q3map2's is 0, but holding 0 there was chosen against on the training levels (lights.md §4: kaos's
    objective 8 % worse), so it is fitted."""
    if ambient not in AMBIENTS:
        raise ValueError(f"ambient {ambient!r} is not one of {', '.join(AMBIENTS)}")
    world = level.bsp.entities[0] if level.bsp.entities else {}
    recorded = worldspawn_ambient(level.bsp.entities, level.name)
    if ambient == FITTED_AMBIENT or "_minlight" in world or not np.any(recorded > 0):
        return None
    return recorded


def spotlight_starts(scene: LevelScene, starts: Starts, relative: np.ndarray | None, start: str = DEFAULT_START,
                     peaks: PeakSettings = DEFAULT_PEAKS) -> tuple[np.ndarray, np.ndarray | None]:
    """Where fit_scene(spots=True)'s spotlights start, and their relative intensities: at the point lights' starts
    (`starts`, `relative`); with the peak start also under the fixtures of light-named shaders (starts.fixture_starts)
    and under the ceiling above the floor's peaks (starts.ceiling_starts, lights.md §4) — a ceiling start within merge
    distance of a fixture start dropped, and both replacing the point lights' starts within merge distance of them —,
    and then all of them only where something other than sky is above in reach (starts.under_a_ceiling). A fixture
    start over a floor too dark to read gets the median of the others' estimates. Without the peak start, or without
    peaks (relative None), the point lights' starts as they are, no ceiling test (and without the peak start no merge
    either: fit_scene)."""
    if start != PEAK_START or relative is None:
        return starts.positions, relative
    target = scene.target
    fixtures = _fixture_starts(scene, peaks)
    ceiling = ceiling_starts(target.positions, target.normals, target.radiance, target.albedo, scene.is_open,
                             _distance_up(scene), peaks)
    hung, estimates = fixtures.positions, fixtures.intensities
    inside = _in_bounds(scene, ceiling.positions)
    far = _farther(ceiling.positions[inside], hung, peaks.merge_distance)
    hung = np.concatenate([hung, ceiling.positions[inside][far]])
    estimates = np.concatenate([estimates, ceiling.intensities[inside][far]])
    read = estimates > 0
    estimates = np.where(read, estimates, np.median(estimates[read]) if read.any() else np.median(relative))
    far = _farther(starts.positions, hung, peaks.merge_distance)
    positions, relative = np.concatenate([hung, starts.positions[far]]), np.concatenate([estimates, relative[far]])
    hangs = under_a_ceiling(positions, _distance_up(scene), _sky_up(scene))
    return positions[hangs], relative[hangs]


def _fixture_starts(scene: LevelScene, peaks: PeakSettings) -> Starts:
    """The spotlight starts under the level's light fixtures (starts.fixture_starts over light_fixtures) inside the
    lights' box: where spotlight_starts starts spotlights and where fit_scene's spotlights settle after the fit."""
    target = scene.target
    corners, normals, face = light_fixtures(scene.level.bsp)
    found = fixture_starts(corners, normals, face, target.positions, target.radiance, target.albedo, scene.is_open,
                           _distance_down(scene), peaks)
    inside = _in_bounds(scene, found.positions)
    return Starts(found.positions[inside], found.intensities[inside], int(inside.sum()))


def _farther(positions: np.ndarray, others: np.ndarray, distance: float) -> np.ndarray:
    """(N,) bool: each of `positions` (N, 3) at least `distance` from every one of `others` (M, 3) (True without any)."""
    gap = np.linalg.norm(positions[:, None] - others[None], axis=2).min(axis=1, initial=np.inf)
    return gap >= distance


def _in_bounds(scene: LevelScene, positions: np.ndarray) -> np.ndarray:
    """(N,) bool: the start positions (N, 3) inside the lights' box (scene.bounds), where the fit keeps its lights."""
    return np.all((positions >= scene.bounds[0]) & (positions <= scene.bounds[1]), axis=1)


def _distance_up(scene: LevelScene) -> Callable[[np.ndarray], np.ndarray]:
    """(N, 3) Quake points -> (N,) units to the first surface straight above (inf beyond SPOT_REACH)."""
    return _through(scene.model.raycaster, UP)


def _distance_down(scene: LevelScene) -> Callable[[np.ndarray], np.ndarray]:
    """(N, 3) Quake points -> (N,) units to the first surface straight below (inf beyond SPOT_REACH)."""
    return _through(scene.model.raycaster, -UP)


def _sky_up(scene: LevelScene) -> Callable[[np.ndarray], np.ndarray] | None:
    """(N, 3) Quake points -> (N,) units to the level's sky triangles straight above (inf beyond SPOT_REACH); None on
    a level without sky."""
    return None if scene.model.sky is None else _through(scene.model.sky, UP)


def _through(raycaster: EmbreeRaycaster, direction: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """(N, 3) Quake points -> (N,) units to `raycaster`'s first triangle along the unit `direction` (inf beyond
    SPOT_REACH)."""
    return lambda points: raycaster.cast(points, np.broadcast_to(direction, points.shape).copy(), SPOT_REACH + 1.0)[0]


def fits_spots(scene: LevelScene, spots: bool | None, start: str = DEFAULT_START,
               peaks: PeakSettings = DEFAULT_PEAKS) -> bool:
    """Whether a fit starts spotlights: as asked, or by default (None) with the peak start where a spotlight's disc
    explains the floor's peaks of baked light better than a point light's bump (starts.lit_by_spotlights, lights.md
    §4); the grid start has no floor peaks to judge by, so no spotlights by default."""
    if spots is not None:
        return spots
    if start != PEAK_START:
        return False
    target = scene.target
    return lit_by_spotlights(disc_gains(target.positions, target.normals, target.radiance, target.albedo,
                                        _distance_up(scene), peaks))


def fits_sun(scene: LevelScene, suns: bool | None) -> bool:
    """Whether a fit recovers a sun: as asked, or by default (None) DEFAULT_SUNS where the level has sky surfaces. Asked
    on a level without sky, refused."""
    if suns is None:
        return DEFAULT_SUNS and scene.model.sky is not None
    if suns and scene.model.sky is None:
        raise ValueError(f"{scene.level.name}: no sky surface (SURF_SKY) for a sun to shine through; fit with --no-suns")
    return suns


def rig_of(scene: LevelScene, result: FitResult, grid: tuple[int, int, int], scheme: str,
           start: str = DEFAULT_START) -> Rig:
    """The fitted lights as a rig; lights that went dark (intensity 0) are dropped."""
    lights = result.lights
    lit = lights.intensities * lights.colours.max(axis=1) > 0
    info = {"grid": list(grid), "start": start, "initial_lights": int(result.initial_lights),
            "iterations": result.iterations,
            "rays": result.rays, "seconds": round(result.seconds, 3), "target_points": scene.target.point_count,
            "projection_loss": round(scene.target.projection_loss, 6),
            "max_edge": scene.max_edge, "textures_found": scene.albedo.found}
    surfaces = [surface_light(scene.level.bsp.shader_name(shader), scene.surface_emitters.shaders[shader], float(value))
                for shader, value in zip(scene.surface_shaders, lights.surface_values) if value > 0]
    fitted_suns = [Sun.from_quake(direction, colour, intensity) for direction, colour, intensity in
                   zip(lights.sun_directions, lights.sun_colours, lights.sun_intensities)]
    fitted_suns = [sun for sun in fitted_suns if sun.intensity > 0]
    if lights.sun_count:
        info["suns"] = len(fitted_suns)
    axes, cones = lights.cones()
    spot = {}
    if np.any(cones > 0):  # spotlights (fit_scene(spots=True)): unit axes in Unity axes, radiusByDist (0: a point)
        spot = dict(spot_directions=quake_to_unity(axes[lit], scale=1.0), radius_by_dist=cones[lit].copy())
        info["spots"] = True
    return Rig.from_quake(lights.positions[lit], lights.colours[lit], lights.intensities[lit], ambient=lights.ambient,
                          level=scene.level.name, bsp_sha256=scene.level.sha256, scheme=scheme,
                          objective=float(result.objective), extra=info, surfaces=surfaces, suns=fitted_suns, **spot)


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
    surfaces_of = shader_emitters(level.bsp, script_lights(level))
    surfaces_of.spots = spots
    surfaces_of.suns = level_suns(level)
    return surfaces_of


def level_suns(level: Level) -> Suns:
    """The suns of the shaders drawn in the level (their q3map_sun lines in the `scripts/*.shader` beside it), unless
    worldspawn `_noshadersun` is 1 (light.c CreateSurfaceLights), with the level's sky triangles for their rays
    (emitters.py)."""
    bsp = level.bsp
    world = bsp.entities[0] if bsp.entities else {}
    if str(world.get("_noshadersun", "")).startswith("1"):
        return Suns.empty()
    scripts = level_scripts(level)
    drawn = np.unique(bsp.faces["shader"])
    directions, colours, photons, shader_of = [], [], [], []
    for shader in drawn:
        if not compiled_with_script(bsp, scripts, int(shader)):
            continue
        for colour, value, direction in shader_suns(scripts, bsp.shader_name(int(shader))):
            directions.append(direction)
            colours.append(colour)
            photons.append(value)
            shader_of.append(int(shader))
    if not photons:
        return Suns.empty()
    return Suns(directions=np.array(directions), colours=np.array(colours), photons=np.array(photons),
                shader=np.array(shader_of, np.int64), sky=sky_raycaster(bsp))


def sky_raycaster(bsp) -> EmbreeRaycaster | None:
    """The level's sky triangles (faces whose shader is SURF_SKY), which a sun's ray must meet first; None without."""
    sky_faces = np.flatnonzero(bsp.shaders["surface_flags"][bsp.faces["shader"]].astype(np.int64) & SURF_SKY)
    if sky_faces.size == 0:
        return None
    corners, _, _ = surface_triangles(bsp, sky_faces)
    return EmbreeRaycaster(corners.reshape(-1, 3), np.arange(3 * len(corners)).reshape(-1, 3))


def rig_suns(bsp, rig: Rig) -> Suns:
    """A rig's suns as emitters.Suns (Quake axes) with the level's sky triangles."""
    if not rig.suns:
        return Suns.empty()
    return Suns(directions=np.array([sun.quake_direction() for sun in rig.suns]),
                colours=np.array([sun.colour for sun in rig.suns]), photons=np.array([sun.intensity for sun in rig.suns]),
                shader=np.full(len(rig.suns), -1, np.int64), sky=sky_raycaster(bsp))


def compiled_with_script(bsp, scripts: ShaderScripts, shader: int) -> bool:
    """False when the shader's script makes it sky but the BSP does not flag it SURF_SKY: the level was compiled
    without that script (emitters.script_declares_sky), so its surface light and sun are not the level's."""
    return not script_declares_sky(scripts, bsp.shader_name(shader)) or \
        bool(int(bsp.shaders["surface_flags"][shader]) & SURF_SKY)


def level_scripts(level: Level) -> ShaderScripts:
    """The shader scripts of the pk3s beside the level, its release's winning (emitters.script_order)."""
    return read_shader_scripts(script_order(texture_paks(level.pak, default_pak().parent), level.pak))


def script_lights(level: Level, candidates: bool = False) -> dict[int, ShaderLight]:
    """BSP shader -> its surface light by the `scripts/*.shader` of the pk3s beside the level. With
    `candidates`, also the shaders that may emit although no installed script says so (the fit recovers
    their value, lights.md §4): those without any script whose faces are sky (SURF_SKY: q3map2's
    CreateSurfaceLights makes area lights of any surface with a q3map_surfacelight, sky included) or whose
    name has "light" in it; they get CANDIDATE_VALUE (the value their basis is built at), the colour of their
    image (white without one) and q3map2's defaults."""
    bsp = level.bsp
    paks = texture_paks(level.pak, default_pak().parent)
    scripts = level_scripts(level)
    images: dict[str, np.ndarray | None] = {}

    def image_colour(path: str) -> np.ndarray | None:
        if path not in images:
            albedo = load_albedo([path], paks)
            images[path] = None if albedo.images[0] is None else albedo.images[0].reshape(-1, 3).mean(axis=0)
        return images[path]

    shaders = {}
    for index in range(len(bsp.shaders)):
        name = bsp.shader_name(index)
        if not compiled_with_script(bsp, scripts, index):
            continue
        light = shader_light(scripts, name, image_colour)
        if light is not None:
            shaders[index] = light
        elif candidates and name.lower() not in scripts.blocks and \
                (int(bsp.shaders["surface_flags"][index]) & SURF_SKY or names_a_light(name)):
            colour = image_colour(name)
            colour = np.ones(3) if colour is None or not np.any(colour > 0) else colour / colour.max()
            shaders[index] = ShaderLight(value=CANDIDATE_VALUE, colour=colour, subdivide=DEFAULT_LIGHT_SUBDIVIDE,
                                         backsplash_fraction=BACKSPLASH_FRACTION,
                                         backsplash_distance=BACKSPLASH_DISTANCE, two_sided=False,
                                         colour_source=CANDIDATE_SOURCE + ("image" if colour is not None else "white"))
    return shaders


def names_a_light(shader: str) -> bool:
    """Whether a shader's name says it draws a light ("light" in it, any case): the surface-light candidates without a
    script (script_lights) and the fixtures spotlights hang from (light_fixtures)."""
    return LIGHT_WORD in shader.lower()


def light_fixtures(bsp) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The triangles of the faces drawn with a shader whose name says it draws a light (names_a_light): corners (T, 3,
    3) Quake units, vertex normals (T, 3, 3), face (T,) (emitters.surface_triangles), where spotlights may hang
    (starts.fixture_starts)."""
    named = np.array([names_a_light(bsp.shader_name(index)) for index in range(len(bsp.shaders))], dtype=bool)
    faces = np.flatnonzero(named[bsp.faces["shader"]]) if len(named) else np.zeros(0, np.int64)
    if len(faces) == 0:
        return np.zeros((0, 3, 3)), np.zeros((0, 3, 3)), np.zeros(0, np.int64)
    return surface_triangles(bsp, faces)


def shader_emitters(bsp, shaders: dict[int, ShaderLight]) -> Emitters:
    """The area lights and backsplash lights of the shaders' faces (emitters.surface_emitters)."""
    areas, positions, colours, intensities, splash_shader = surface_emitters(bsp, shaders)
    return Emitters(areas=areas, splash_positions=positions, splash_colours=colours, splash_intensities=intensities,
                    shaders=shaders, splash_shader=splash_shader)


def add_surface_lights(scene: LevelScene) -> None:
    """The level's candidate surface lights (script_lights with candidates) as elements of the fit: their bases
    in the scene's model (model.surface_basis), so fit_scene recovers one q3map_surfacelight value each."""
    clock = time.perf_counter()
    emitters = shader_emitters(scene.level.bsp, script_lights(scene.level, candidates=True))
    shaders, basis = surface_bases(scene.model.points, scene.model.normals, emitters, scene.model.raycaster)
    scene.model.surface_basis = basis
    scene.surface_shaders = shaders
    scene.surface_emitters = emitters
    scene.seconds["surface lights"] = time.perf_counter() - clock


def surface_pieces(bsp, emitters: Emitters) -> SurfacePieces:
    """The emitters' area lights as compare.SurfacePieces (Unity metres, equal-flux power)."""
    a = emitters.areas
    corners = quake_to_unity(a.corners.reshape(-1, 3)).reshape(a.corners.shape)
    return SurfacePieces(shader=[bsp.shader_name(int(i)) for i in a.shader], corners=corners,
                         normals=quake_to_unity(a.normals, scale=1.0),
                         power=equal_flux_intensity(a.add, a.areas) * a.colours.max(axis=1, initial=0.0))


def shader_power(bsp, emitters: Emitters) -> dict[str, float]:
    """Shader name -> equal-flux power of all its pieces per unit of q3map_surfacelight value."""
    out: dict[str, float] = {}
    add_per_value = FORM_FACTOR_VALUE_SCALE * AREA_SCALE  # an area light's add per unit of q3map_surfacelight
    for shader in emitters.shaders:
        pick = emitters.areas.shader == shader
        out[bsp.shader_name(shader)] = float(equal_flux_intensity(add_per_value, emitters.areas.areas[pick]).sum())
    return out


def surface_light(shader: str, light: ShaderLight, value: float | None = None) -> SurfaceLight:
    """The rig's record of a shader's surface light built as `light` (emitters.ShaderLight), at `value` (None: the
    light's own): its colour and q3map2's settings besides the value, so the rig re-lights as it was built."""
    return SurfaceLight(shader=shader, value=light.value if value is None else value, colour=light.colour.copy(),
                        subdivide=light.subdivide, two_sided=light.two_sided,
                        backsplash_fraction=light.backsplash_fraction, backsplash_distance=light.backsplash_distance)


def rig_emitters(level: Level, rig: Rig) -> Emitters:
    """A rig's surface lights as emitters of the level (its faces drawn with each shader), at the rig's values and
    settings (surface_light), and its suns."""
    names = {level.bsp.shader_name(index).lower(): index for index in range(len(level.bsp.shaders))}
    missing = [s.shader for s in rig.surfaces if s.shader.lower() not in names]
    if missing:
        raise RigError(f"rig surface light(s) {missing} name shaders {level.name} does not have")
    shaders = {names[s.shader.lower()]: ShaderLight(value=s.value, colour=np.asarray(s.colour, dtype=np.float64),
                                                    subdivide=s.subdivide, backsplash_fraction=s.backsplash_fraction,
                                                    backsplash_distance=s.backsplash_distance, two_sided=s.two_sided,
                                                    colour_source="rig")
               for s in rig.surfaces if s.value > 0}
    emitters = shader_emitters(level.bsp, shaders)
    emitters.suns = rig_suns(level.bsp, rig)
    return emitters


def real_rig(level: Level, real: EntityLights, emitters: Emitters) -> Rig:
    """The level's real rig as a rig file holds it (the export of lights.md §5): its light entities (point lights and
    spotlights) and ambient, the surface lights of its shader scripts at their script values and colours, and its
    suns (`emitters` = level_emitters), with the scripts' settings besides the value (surface_light)."""
    bsp = level.bsp
    surfaces = [surface_light(bsp.shader_name(shader), light) for shader, light in sorted(emitters.shaders.items())]
    suns = [Sun.from_quake(direction, colour, photons) for direction, colour, photons in
            zip(emitters.suns.directions, emitters.suns.colours, emitters.suns.photons)]
    return replace(real.rig, bsp_sha256=level.sha256, scheme="real rig", surfaces=surfaces, suns=suns,
                   extra={"source": "the level's light entities, worldspawn ambient, shader scripts and suns"})


def point_lights_of(real: EntityLights) -> Lights:
    """The level's light entities that are plain point lights (spotlights are emitters), with its ambient."""
    keep = ~real.spot if len(real.spot) == real.rig.count else np.ones(real.rig.count, bool)
    return Lights(real.rig.quake_positions()[keep], real.rig.colours[keep], real.rig.intensities[keep],
                  ambient=real.rig.ambient.copy())
