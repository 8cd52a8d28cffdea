"""Light elements of a q3map2 compile beyond plain point lights: spotlights and shader surface lights
(Documentation~/lights.md §3). Facts from q3map2 (TTimo/GtkRadiant tools/quake3/q3map2), cited by file
and function:

- **Spotlights** (light.c `CreateEntityLights`): a light entity whose `target` names an entity becomes
  a spotlight along the unit normal N from the light to the target's origin, with
  radiusByDist = (radius + 16) / dist (`radius` key, default 64; dist 0 -> 64). It is a point light
  with angle attenuation (never linear) times the cone factor of light.c `LightContributionToSample`
  (and `LightContributionToPoint` for the grid): with t = (p - x).N (0 behind the light),
  r = |p - (x + t N)|, R = radiusByDist t: 0 when r >= R, (R - r) / 32 when r > R - 32, else 1.
- **Surface lights** (light.c `CreateSurfaceLights`, light_bounce.c `RadLightForTriangles`,
  `RadSubdivideDiffuseLight`): every triangle of a surface whose shader has `q3map_surfacelight V`
  is split by axial planes at its bounds' middle until no side is longer than `q3map_lightSubdivide`
  (default 999 units); each piece of area >= 1 is an area light: winding w, normal N (the average
  vertex normal), origin = bounds centre + 1 N, add = V x formFactorValueScale (3) x areaScale
  (0.25), colour = the shader's colour (`q3map_lightRGB`, else the average of `q3map_lightImage` or
  the shader's image, shaders.c `LoadShaderImages`, ColorNormalize: largest channel 1). Two-sided
  when the shader is fog or two-sided. A piece that was not split also makes a backsplash point light
  (`q3map_backsplash`, default 5 % at 23 units): photons V x area x 0.25 x 5 %, at origin + 23 N.
- **An area light's contribution** (light.c `LightContributionToSample`, exact form factor, no
  `-fast`): with d = p.N - origin.N: nothing when d < -1 (one-sided) or when -3 < d < 3 and
  n.N > 0.9 (coplanar); the point is pushed to p + (8 - d) N when |d| < 8; then
  add x PointToPolygonFormFactor(pushed, n, w) (light.c: (1 / 2 pi) sum over edges of
  acos(u_i.u_j) (n . normalize(u_i x u_j)), u the unit directions to the winding's corners: the
  projected solid angle over pi, A / (pi r^2) for a small facing patch, 1 for a whole hemisphere), negated
  for a two-sided light, then a shadow ray to the origin. On the grid (`LightContributionToPoint`) the
  normal is the direction to the light's origin.
- **Suns** (shaders.c `ParseShaderFile`: `q3map_sun` / `q3map_sunExt R G B intensity degrees elevation`: the
  colour normalised to unit length (VectorNormalize, not largest channel 1), the direction toward the sun
  (cos a cos e, sin a cos e, sin e) with a = degrees and e = elevation in radians, the sky surfaceparm applied;
  light.c `CreateSurfaceLights` makes one sun per shader drawn in the level unless worldspawn
  `_noshadersun` is 1, `CreateSunLight`: photons = intensity x skyScale (1), flags LIGHT_SUN_DEFAULT, which
  include angle attenuation). Its light at a luxel (light.c `LightContributionToSample`, EMIT_SUN):
  colour x photons x (n . direction) bytes, when the trace toward the sun ends on a sky surface (C_SKY) and
  nothing opaque is in between; on the grid (`LightContributionToPoint`) the same without the cosine. The
  sky is not in the shadow-ray geometry (scenes/surfaces.py), so a sun ray is lit when the level's sky
  triangles (`Suns.sky`) are hit before any other. `q3map_sunExt`'s deviance and samples (random jitter of
  the direction) are read but not modelled: the one sun along the main direction carries all the photons.
"""

from __future__ import annotations

import math
import re
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..scenes.bsp import FACE_MESH, FACE_PATCH, FACE_POLYGON, Bsp
from ..scenes.patches import PATCH_LEVEL
from ..scenes.raycast import EmbreeRaycaster
from .surfaces import NORMAL, POSITION, face_triangles

SPOT_DEFAULT_RADIUS = 64.0  # light.c CreateEntityLights
SPOT_EDGE = 32.0  # units of soft cone edge, LightContributionToSample
FORM_FACTOR_VALUE_SCALE = 3.0  # q3map2.h formFactorValueScale
AREA_SCALE = 0.25  # q3map2.h areaScale
DEFAULT_LIGHT_SUBDIVIDE = 999.0  # q3map2.h defaultLightSubdivide
BACKSPLASH_FRACTION = 0.05  # q3map2.h DEF_BACKSPLASH_FRACTION
BACKSPLASH_DISTANCE = 23.0  # q3map2.h DEF_BACKSPLASH_DISTANCE
POINT_SCALE = 7500.0  # q3map2 pointScale: a point light of `light` I sends 7500 I photons
MIN_DISTANCE = 16.0  # units: q3map2 clamps a point light's distance to at least this (the inverse square's peak)
DROPPED_CONTRIBUTION = 1.0  # bytes: q3map2 ignores a light adding this much or less
ORIGIN_NUDGE = 1.0  # the area light's origin is 1 unit in front of its winding
RAY_OFFSET = 0.5  # units off the surface where a target point's shadow rays start
# A lightmap sample's trace ignores occluders within this many units of its origin: q3map2.h DEFAULT_INHIBIT_RADIUS,
# the trace.inhibitRadius of light_ydnar.c IlluminateRawLightmap (and IlluminateVertexes), applied by light_trace.c
# TraceTriangle (`depth <= trace->inhibitRadius` is no hit). A target point on the edge where a wall meets its face
# starts its rays on that wall's plane; without it every such point was in shadow (lights.md §3).
SURFACE_INHIBIT_RADIUS = 1.5
# Pairs whose form-factor bound add x area / (pi dist^2) is below this many bytes are not evaluated
# (q3map2 evaluates every pair without -fast; 0.05 byte a pair bounds what is left out).
AREA_BOUND_BYTES = 0.05
POINTS_PER_CHUNK = 2048


# ----------------------------------------------------------------------------------- shader scripts

@dataclass(frozen=True)
class ShaderLight:
    value: float  # q3map_surfacelight
    colour: np.ndarray  # (3,) largest channel 1
    subdivide: float
    backsplash_fraction: float
    backsplash_distance: float
    two_sided: bool
    colour_source: str


@dataclass(frozen=True)
class ShaderScripts:
    blocks: dict[str, str]  # lower-case shader name -> its body (comments stripped)
    sources: dict[str, str]  # lower-case shader name -> "pak:member"

    def keywords(self, name: str) -> list[list[str]]:
        """The body's lines as token lists (lower-case keywords, values as written)."""
        body = self.blocks.get(name.lower())
        if body is None:
            return []
        return [line.split() for line in body.splitlines() if line.split()]


_BLOCK = re.compile(r"([^\s{}]+)\s*\{")


def read_shader_scripts(paks: list[Path]) -> ShaderScripts:
    """Every shader block of `scripts/*.shader` in the paks: later paks override earlier ones (as for images,
    textures.py), and within one pak the **first** definition of a name wins, as in q3map2 (shaders.c: ParseShaderFile
    appends a shaderInfo for every block it reads and ShaderInfoForShader returns the first one of that name). kaos's
    `base_light/wsupprt1_12` is defined twice in pak0.pk3's oalite.shader, `q3map_surfacelight 3000` with `surfaceparm
    nomarks` first, 600 without it second; its BSP records SURF_NOMARKS for it, the first one's flag (lights.md §1)."""
    blocks: dict[str, str] = {}
    sources: dict[str, str] = {}
    for pak in paks:
        in_pak: dict[str, tuple[str, str]] = {}
        try:
            with zipfile.ZipFile(pak) as archive:
                members = sorted(m for m in archive.namelist() if m.lower().startswith("scripts/")
                                 and m.lower().endswith(".shader"))
                for member in members:
                    text = archive.read(member).decode("latin-1")
                    for name, body in _parse_blocks(text):
                        in_pak.setdefault(name.lower(), (body, f"{pak.name}:{member}"))
        except (zipfile.BadZipFile, OSError):
            continue
        for name, (body, source) in in_pak.items():
            blocks[name] = body
            sources[name] = source
    return ShaderScripts(blocks=blocks, sources=sources)


UPDATE_PAK_MARK = "patch"  # OpenArena's later releases ship as updates: pak6-patch085.pk3, pak6-patch088.pk3


def script_order(paks: list[Path], level_pak: Path | None) -> list[Path]:
    """The paks in the order their shader scripts are read (a later definition of a shader overrides an earlier
    one): the updates of later releases (a name with UPDATE_PAK_MARK) first, then the others in the engine's
    order, unless the level ships in an update itself (then the engine's order). A level is compiled with its
    release's scripts, so those win and an update only adds the shaders they lack: OpenArena 0.8.8's
    `base_light/ceil1_22a` has q3map_surfacelight 10000, 0.8.1's pak0.pk3 300 (lights.md §1, §7)."""
    if level_pak is not None and UPDATE_PAK_MARK in level_pak.name.lower():
        return list(paks)
    updates = [pak for pak in paks if UPDATE_PAK_MARK in pak.name.lower()]
    return updates + [pak for pak in paks if UPDATE_PAK_MARK not in pak.name.lower()]


def _parse_blocks(text: str):
    text = re.sub(r"//[^\n]*", "", text)
    position = 0
    while True:
        match = _BLOCK.search(text, position)
        if match is None:
            return
        depth, index = 1, match.end()
        while index < len(text) and depth > 0:
            depth += {"{": 1, "}": -1}.get(text[index], 0)
            index += 1
        yield match.group(1), text[match.end():index - 1]
        position = index


def shader_light(scripts: ShaderScripts, name: str, image_colour) -> ShaderLight | None:
    """The surface light a shader emits, or None. `image_colour(path)` -> mean RGB of an image
    (path without extension) or None."""
    value, subdivide = 0.0, DEFAULT_LIGHT_SUBDIVIDE
    fraction, distance = BACKSPLASH_FRACTION, BACKSPLASH_DISTANCE
    rgb, light_image, editor_image, first_map = None, None, None, None
    two_sided = False
    for tokens in scripts.keywords(name):
        key = tokens[0].lower()
        args = tokens[1:]
        try:
            if key == "q3map_surfacelight" and args:
                value = float(args[0])
            elif key == "q3map_lightsubdivide" and args:
                subdivide = float(args[0])
            elif key == "q3map_backsplash" and len(args) >= 2:
                fraction, distance = float(args[0]) * 0.01, float(args[1])
            elif key == "q3map_lightrgb" and len(args) >= 3:
                rgb = np.array([float(a) for a in args[:3]])
            elif key == "q3map_lightimage" and args:
                light_image = args[0]
            elif key == "qer_editorimage" and args:
                editor_image = args[0]
            elif key in ("map", "clampmap") and args and first_map is None and not args[0].startswith("$"):
                first_map = args[0]
            elif key == "surfaceparm" and args and args[0].lower() == "fog":
                two_sided = True
            elif key == "cull" and args and args[0].lower() in ("none", "twosided", "disable"):
                two_sided = True
        except ValueError:
            continue
    if value <= 0:
        return None
    source = "q3map_lightRGB"
    if rgb is None:
        for label, path in (("q3map_lightImage", light_image), ("qer_editorImage", editor_image),
                            ("shader image", name), ("first stage", first_map)):
            if path is None:
                continue
            colour = image_colour(re.sub(r"\.(tga|jpg|png)$", "", path, flags=re.I))
            if colour is not None:
                rgb, source = colour, f"{label} {path}"
                break
    if rgb is None or not np.any(rgb > 0):
        rgb, source = np.ones(3), "white (no image)"
    return ShaderLight(value=value, colour=rgb / rgb.max(), subdivide=subdivide if subdivide > 0 else
                       DEFAULT_LIGHT_SUBDIVIDE, backsplash_fraction=fraction, backsplash_distance=distance,
                       two_sided=two_sided, colour_source=source)


SKY_KEYWORDS = ("q3map_sun", "q3map_sunext", "sun")  # shaders.c: these apply the sky surfaceparm


def script_declares_sky(scripts: ShaderScripts, name: str) -> bool:
    """The shader's script makes it sky (`surfaceparm sky`, or a sun line, which applies it: shaders.c). The BSP
    stores the surface flags its compile gave each shader, so a sky script on a shader the BSP does not flag SURF_SKY
    is not the script the level was compiled with (q3dm6ish's xtoxicsky_q3ctf3, lights.md §1)."""
    for tokens in scripts.keywords(name):
        key = tokens[0].lower()
        if key in SKY_KEYWORDS or (key == "surfaceparm" and len(tokens) > 1 and tokens[1].lower() == "sky"):
            return True
    return False


def shader_suns(scripts: ShaderScripts, name: str) -> list[tuple[np.ndarray, float, np.ndarray]]:
    """The q3map_sun / q3map_sunExt lines of a shader (module docstring): (unit colour, photons, unit direction
    toward the sun) each."""
    suns = []
    for tokens in scripts.keywords(name):
        if tokens[0].lower() not in SKY_KEYWORDS or len(tokens) < 7:
            continue
        try:
            red, green, blue, photons, degrees, elevation = (float(t) for t in tokens[1:7])
        except ValueError:
            continue
        colour = np.array([red, green, blue])
        length = float(np.linalg.norm(colour))
        if length <= 0 or photons <= 0:
            continue
        a, e = math.radians(degrees), math.radians(elevation)
        suns.append((colour / length, photons, np.array([math.cos(a) * math.cos(e), math.sin(a) * math.cos(e),
                                                         math.sin(e)])))
    return suns


# ------------------------------------------------------------------------------------- emitters

@dataclass
class AreaLights:
    """Area lights (q3map2 EMIT_AREA), Quake units: windings padded to `corners.shape[1]` by repeating
    the last corner (a zero-length edge adds nothing to the form factor)."""
    corners: np.ndarray  # (K, P, 3)
    normals: np.ndarray  # (K, 3)
    origins: np.ndarray  # (K, 3)
    areas: np.ndarray  # (K,)
    add: np.ndarray  # (K,) value x 3 x 0.25 (bytes per unit form factor, before colour)
    colours: np.ndarray  # (K, 3) largest channel 1
    two_sided: np.ndarray  # (K,) bool
    shader: np.ndarray  # (K,) BSP shader index

    @property
    def count(self) -> int:
        return len(self.origins)

    @staticmethod
    def empty() -> "AreaLights":
        return AreaLights(np.zeros((0, 3, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0),
                          np.zeros((0, 3)), np.zeros(0, bool), np.zeros(0, np.int64))


@dataclass
class Spots:
    """Spotlights: q3map2 point lights (photons = 7500 I) with a cone."""
    positions: np.ndarray  # (S, 3)
    colours: np.ndarray  # (S, 3)
    intensities: np.ndarray  # (S,)
    directions: np.ndarray  # (S, 3) unit, toward the target
    radius_by_dist: np.ndarray  # (S,)

    @property
    def count(self) -> int:
        return len(self.positions)

    @staticmethod
    def empty() -> "Spots":
        return Spots(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3)), np.zeros(0))


@dataclass
class Suns:
    """q3map2 suns (EMIT_SUN, module docstring): directional light from the sky."""
    directions: np.ndarray  # (K, 3) unit, toward the sun
    colours: np.ndarray  # (K, 3) unit length (q3map2's VectorNormalize)
    photons: np.ndarray  # (K,) bytes at normal incidence
    shader: np.ndarray  # (K,) BSP shader index of the sky shader that made it
    sky: EmbreeRaycaster | None = None  # the level's sky triangles: a sun ray is lit when it hits them first

    @property
    def count(self) -> int:
        return len(self.photons)

    @staticmethod
    def empty() -> "Suns":
        return Suns(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.int64))


@dataclass
class Emitters:
    """Everything of a compile that is held fixed in a fit: spotlights, area lights and their
    backsplash point lights (positions, colours, intensities in q3map2 `light` units)."""
    spots: Spots = field(default_factory=Spots.empty)
    areas: AreaLights = field(default_factory=AreaLights.empty)
    splash_positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    splash_colours: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    splash_intensities: np.ndarray = field(default_factory=lambda: np.zeros(0))
    shaders: dict[int, ShaderLight] = field(default_factory=dict)  # BSP shader -> its surface light
    splash_shader: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))  # (B,) BSP shader
    suns: Suns = field(default_factory=Suns.empty)

    def of_shader(self, shader: int, scale: float = 1.0) -> "Emitters":
        """The area lights and backsplash lights of one shader (no spotlights), their values x `scale`."""
        pick = self.areas.shader == shader
        a = self.areas
        areas = AreaLights(corners=a.corners[pick], normals=a.normals[pick], origins=a.origins[pick],
                           areas=a.areas[pick], add=a.add[pick] * scale, colours=a.colours[pick],
                           two_sided=a.two_sided[pick], shader=a.shader[pick])
        splash = self.splash_shader == shader
        return Emitters(areas=areas, splash_positions=self.splash_positions[splash],
                        splash_colours=self.splash_colours[splash],
                        splash_intensities=self.splash_intensities[splash] * scale,
                        shaders={shader: self.shaders[shader]} if shader in self.shaders else {},
                        splash_shader=self.splash_shader[splash])


def cone_factor(along: np.ndarray | float, radial: np.ndarray, radius_by_dist: np.ndarray | float) -> np.ndarray:
    """q3map2's spotlight cone (module docstring) of a point `along` units down the axis from the light and `radial`
    units off it (broadcast): 0 behind the light or outside the cone of radius R = radiusByDist x along, (R - r) /
    SPOT_EDGE on its soft edge, else 1. The one statement of the rule: the rig's emitters (spot_factor), the fit's
    pairs (model.spot_factors) and the floor discs of the fit's starts (starts.spot_disc_profile) all call it; only
    the compiled objective (objective_kernel.spot_factor) restates it, tested against model.spot_factors."""
    cone = radius_by_dist * along
    return np.where((along > 0) & (radial < cone), np.clip((cone - radial) / SPOT_EDGE, 0.0, 1.0), 0.0)


def spot_factor(points: np.ndarray, positions: np.ndarray, directions: np.ndarray,
                radius_by_dist: np.ndarray) -> np.ndarray:
    """(C, S) q3map2's cone factor (cone_factor) of spotlights at points (C, 3)."""
    offset = points[:, None, :] - positions[None, :, :]  # p - x
    along = np.einsum("csk,sk->cs", offset, directions)
    radial = np.linalg.norm(offset - along[..., None] * directions[None], axis=2)
    return cone_factor(along, radial, radius_by_dist[None, :])


def clamped_distance_squared(distance: np.ndarray) -> np.ndarray:
    """max(distance, MIN_DISTANCE)^2: the denominator of q3map2's inverse-square falloff of a point light (light_ydnar.c
    LightContributionToSample / LightContributionToPoint), shared by every point-light sum of the rig code."""
    return np.maximum(distance, MIN_DISTANCE) ** 2


def form_factor(points: np.ndarray, normals: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(P,) light.c PointToPolygonFormFactor for pairs: points (P, 3), normals (P, 3), windings (P, C, 3)."""
    u = corners - points[:, None, :]
    u /= np.maximum(np.linalg.norm(u, axis=2, keepdims=True), 1e-12)
    v = np.roll(u, -1, axis=1)
    angle = np.arccos(np.clip(np.einsum("pck,pck->pc", u, v), -1.0, 1.0))
    cross = np.cross(u, v)
    length = np.linalg.norm(cross, axis=2)
    facing = np.einsum("pck,pk->pc", cross, normals) / np.maximum(length, 1e-30)
    total = np.sum(np.where(length >= 1e-4, facing * angle, 0.0), axis=1)
    return total / (2.0 * math.pi)


def emitter_bytes(points: np.ndarray, normals: np.ndarray, emitters: Emitters,
                  raycaster: EmbreeRaycaster | None) -> np.ndarray:
    """(N, 3) lightmap bytes the emitters add at surface points (before the 255 clamp)."""
    out = np.zeros((len(points), 3))
    for start in range(0, len(points), POINTS_PER_CHUNK):
        chunk = slice(start, start + POINTS_PER_CHUNK)
        p, n = points[chunk], normals[chunk]
        out[chunk] += _point_lights_at_surface(p, n, emitters.splash_positions, emitters.splash_colours,
                                               emitters.splash_intensities, None, raycaster)
        out[chunk] += _point_lights_at_surface(p, n, emitters.spots.positions, emitters.spots.colours,
                                               emitters.spots.intensities, emitters.spots, raycaster)
        out[chunk] += _areas_at_surface(p, n, emitters.areas, raycaster)
        out[chunk] += _suns_at_surface(p, n, emitters.suns, raycaster)
    return out


SUN_RAY_LENGTH = 131072.0  # Quake units: past the far side of any level (the world is at most 2 x 65536 across)


def sunlit(origins: np.ndarray, directions: np.ndarray, suns: Suns, raycaster: EmbreeRaycaster | None) -> np.ndarray:
    """(R,) bool: the ray from each origin along its direction ends on the sky (hits the level's sky triangles
    before any other geometry; light.c LightContributionToSample, EMIT_SUN: C_SKY and not opaque). Without a
    raycaster (no geometry) every ray is lit; without sky triangles none is."""
    if len(origins) == 0:
        return np.zeros(0, bool)
    if suns.sky is None:
        return np.zeros(len(origins), bool) if raycaster is not None else np.ones(len(origins), bool)
    sky, _ = suns.sky.cast(origins, directions, SUN_RAY_LENGTH)
    if raycaster is None:
        return np.isfinite(sky)
    other, _ = raycaster.cast(origins, directions, SUN_RAY_LENGTH)
    return np.isfinite(sky) & (sky < other)


def _suns_at_surface(p, n, suns: Suns, raycaster) -> np.ndarray:
    out = np.zeros((len(p), 3))
    for k in range(suns.count):
        cosine = n @ suns.directions[k]
        facing = np.flatnonzero(cosine > 0)
        origins = sun_ray_origins(p[facing], n[facing], suns.directions[k])
        lit = facing[sunlit(origins, np.broadcast_to(suns.directions[k], origins.shape).copy(), suns, raycaster)]
        out[lit] += (suns.photons[k] * cosine[lit])[:, None] * suns.colours[k]
    return out


def surface_bases(points: np.ndarray, normals: np.ndarray, emitters: Emitters,
                  raycaster: EmbreeRaycaster | None) -> tuple[list[int], np.ndarray]:
    """(shaders, (S, N, 3)): the bytes each emitting shader's surfaces (area lights and backsplash) add at the
    points per unit of its q3map_surfacelight value: emitter_bytes of that shader at the value it was built with
    (the skip of pairs under AREA_BOUND_BYTES is that value's), divided by the value. An element of the model is
    linear in its value (add and backsplash both are), so value x basis is its light at any value."""
    shaders = sorted(emitters.shaders)
    basis = np.zeros((len(shaders), len(points), 3))
    for index, shader in enumerate(shaders):
        value = emitters.shaders[shader].value
        if value <= 0:
            raise ValueError(f"shader {shader}: surface light value {value!r} must be > 0 to build its basis")
        basis[index] = emitter_bytes(points, normals, emitters.of_shader(shader), raycaster) / value
    return shaders, basis


def _point_lights_at_surface(p, n, positions, colours, intensities, spots: Spots | None, raycaster) -> np.ndarray:
    if len(positions) == 0:
        return np.zeros((len(p), 3))
    d = positions[None] - p[:, None]
    q = np.linalg.norm(d, axis=2)
    cos = np.einsum("cjk,ck->cj", d, n) / np.maximum(q, 1e-9)
    g = np.where(cos > 0, cos / clamped_distance_squared(q), 0.0) * POINT_SCALE * intensities[None]
    if spots is not None:
        g = g * spot_factor(p, spots.positions, spots.directions, spots.radius_by_dist)
    g = _shadowed(p + RAY_OFFSET * n, positions, g, raycaster, min_value=0.0, inhibit=SURFACE_INHIBIT_RADIUS)
    return g @ colours


def _plane_offsets(points: np.ndarray, areas: AreaLights) -> np.ndarray:
    """(C, K) d = p.N - origin.N of every point in front of (> 0) or behind every area light's plane."""
    return np.einsum("ck,jk->cj", points, areas.normals) - np.einsum("jk,jk->j", areas.origins, areas.normals)[None]


def _area_light_bytes(points: np.ndarray, normals: np.ndarray, areas: AreaLights, point: np.ndarray, light: np.ndarray,
                      offsets: np.ndarray) -> np.ndarray:
    """(P,) bytes (before colour and shadow) of area light `light` at point `point` per pair, receiving along
    `normals` (P, 3), `offsets` the points' _plane_offsets: the point pushed to 8 units off the light's plane when
    closer (light.c LightContributionToSample), add x PointToPolygonFormFactor, its magnitude for a two-sided light."""
    d = offsets[point, light]
    pushed = points[point] + np.where((d > -8.0) & (d < 8.0), 8.0 - d, 0.0)[:, None] * areas.normals[light]
    factor = form_factor(pushed, normals, areas.corners[light])
    factor = np.where(areas.two_sided[light], np.abs(factor), np.maximum(factor, 0.0))
    return factor * areas.add[light]


def _areas_at_surface(p, n, areas: AreaLights, raycaster) -> np.ndarray:
    if areas.count == 0:
        return np.zeros((len(p), 3))
    d = _plane_offsets(p, areas)
    aligned = np.einsum("ck,jk->cj", n, areas.normals)
    keep = ~((d < -1.0) & ~areas.two_sided[None]) & ~((d > -3.0) & (d < 3.0) & (aligned > 0.9))
    keep &= np.einsum("cjk,ck->cj", areas.origins[None] - p[:, None], n) >= 0  # light behind the surface
    distance = np.linalg.norm(areas.origins[None] - p[:, None], axis=2)
    radius = np.sqrt(areas.areas / math.pi) * 2.0
    near = np.maximum(distance - radius[None], 1.0)
    bound = areas.add[None] * np.minimum(1.0, areas.areas[None] / (math.pi * near ** 2))
    point, light = np.nonzero(keep & (bound > AREA_BOUND_BYTES))
    value = np.zeros(d.shape)
    if point.size:
        value[point, light] = _area_light_bytes(p, n[point], areas, point, light, d)
    value = _shadowed(p + RAY_OFFSET * n, areas.origins, value, raycaster, min_value=0.0,
                      inhibit=SURFACE_INHIBIT_RADIUS)
    return value @ areas.colours


def occluder_distances(raycaster: EmbreeRaycaster, origins: np.ndarray, directions: np.ndarray, max_distance: float,
                       inhibit: float) -> np.ndarray:
    """(R,) distance from each origin along its unit direction to the first occluder farther than `inhibit` units
    (np.inf: none): the trace of light_trace.c TraceTriangle with its inhibitRadius."""
    distances, _ = raycaster.cast(origins + inhibit * directions, directions, max_distance)
    return distances + inhibit


def occluded(raycaster: EmbreeRaycaster, origins: np.ndarray, directions: np.ndarray, lengths: np.ndarray,
             inhibit: float) -> np.ndarray:
    """(R,) bool: the ray from each origin along its unit direction meets an occluder (occluder_distances, `inhibit`)
    more than RAY_OFFSET short of its light at `lengths` units: the shadow test of the forward model's visibility and
    of the emitters' light (a hit within RAY_OFFSET of the light is taken for the light's own surface)."""
    if len(lengths) == 0:
        return np.zeros(0, bool)
    distances = occluder_distances(raycaster, origins, directions, float(lengths.max()), inhibit)
    return distances < lengths - RAY_OFFSET


def sun_ray_origins(points: np.ndarray, normals: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Where surface points' rays toward a sun of unit `direction` start: RAY_OFFSET off the surface, then past the
    lightmap trace's SURFACE_INHIBIT_RADIUS along the ray (sunlit has no inhibit radius of its own)."""
    return points + RAY_OFFSET * normals + SURFACE_INHIBIT_RADIUS * direction


def _shadowed(origins: np.ndarray, lights: np.ndarray, value: np.ndarray, raycaster, min_value: float,
              inhibit: float = 0.0) -> np.ndarray:
    """value (C, J) with the pairs whose light is hidden from the origin (C, 3) set to 0 (occluded: occluders
    closer than `inhibit` to the origin ignored)."""
    if raycaster is None:
        return value
    point, light = np.nonzero(value > min_value)
    if point.size == 0:
        return value
    offset = lights[light] - origins[point]
    length = np.linalg.norm(offset, axis=1)
    ok = length > max(RAY_OFFSET, inhibit)
    unit = offset[ok] / length[ok, None]
    blocked = np.zeros(point.size, bool)
    blocked[np.flatnonzero(ok)] = occluded(raycaster, origins[point][ok], unit, length[ok], inhibit)
    out = value.copy()
    out[point[blocked], light[blocked]] = 0.0
    return out


def emitters_at_points(points: np.ndarray, emitters: Emitters, raycaster,
                       inhibit: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """What the emitters give free points (the light grid, light.c LightContributionToPoint): bytes
    (C, K, 3) and unit directions (C, K, 3) over K = spots + splashes + area lights, no cosine, a
    contribution of 1 byte or less dropped, shadow rays."""
    positions = np.concatenate([emitters.spots.positions, emitters.splash_positions, emitters.areas.origins])
    offset = positions[None] - points[:, None]
    distance = np.linalg.norm(offset, axis=2)
    unit = offset / np.maximum(distance, 1e-9)[..., None]
    s, b = emitters.spots.count, len(emitters.splash_positions)
    value = np.zeros(distance.shape)
    clamp = clamped_distance_squared(distance)
    value[:, :s] = POINT_SCALE * emitters.spots.intensities[None] / clamp[:, :s] * spot_factor(
        points, emitters.spots.positions, emitters.spots.directions, emitters.spots.radius_by_dist)
    value[:, s:s + b] = POINT_SCALE * emitters.splash_intensities[None] / clamp[:, s:s + b]
    areas = emitters.areas
    if areas.count:  # LightContributionToPoint: the area light seen along the direction to its origin
        d = _plane_offsets(points, areas)
        point, light = np.nonzero(~((d < -1.0) & ~areas.two_sided[None]))
        value[point, s + b + light] = _area_light_bytes(points, unit[point, s + b + light], areas, point, light, d)
    colours = np.concatenate([emitters.spots.colours, emitters.splash_colours, areas.colours])
    colour = value[..., None] * colours[None]
    value = np.where(colour.max(axis=2) > DROPPED_CONTRIBUTION, value, 0.0)
    value = _shadowed(points, positions, value, raycaster, min_value=0.0, inhibit=inhibit)
    colour = value[..., None] * colours[None]
    suns = emitters.suns
    if suns.count == 0:
        return colour, unit
    sun_colour = np.zeros((len(points), suns.count, 3))
    for k in range(suns.count):  # LightContributionToPoint, EMIT_SUN: photons without a cosine
        direction = np.broadcast_to(suns.directions[k], points.shape).copy()
        lit = sunlit(points + inhibit * direction, direction, suns, raycaster)
        sun_colour[lit, k] = suns.photons[k] * suns.colours[k]
    sun_unit = np.broadcast_to(suns.directions[None], sun_colour.shape)
    return np.concatenate([colour, sun_colour], axis=1), np.concatenate([unit, sun_unit], axis=1)


# -------------------------------------------------------------------------- building from a level

def surface_triangles(bsp: Bsp, faces: np.ndarray, patch_level: int = PATCH_LEVEL) -> tuple[np.ndarray, np.ndarray,
                                                                                             np.ndarray]:
    """Corners (T, 3, 3), vertex normals (T, 3, 3) and face (T,) of the given faces' triangles
    (surfaces.face_triangles: polygons and meshes by their indices, patches tessellated)."""
    attributes, triangles, face = face_triangles(bsp, faces, patch_level)
    corners = attributes[triangles]
    return corners[:, :, POSITION], corners[:, :, NORMAL], face


def _clip(polygon: list[np.ndarray], axis: int, value: float, keep_above: bool) -> list[np.ndarray]:
    out: list[np.ndarray] = []
    count = len(polygon)
    for i in range(count):
        a, b = polygon[i], polygon[(i + 1) % count]
        side_a = (a[axis] - value) if keep_above else (value - a[axis])
        side_b = (b[axis] - value) if keep_above else (value - b[axis])
        if side_a >= 0:
            out.append(a)
        if (side_a >= 0) != (side_b >= 0):
            t = side_a / (side_a - side_b)
            out.append(a + t * (b - a))
    return out


def subdivide_winding(polygon: list[np.ndarray], size: float) -> list[list[np.ndarray]]:
    """light_bounce.c RadSubdivideDiffuseLight: split at the bounds' middle along the first axis whose
    extent exceeds `size`, recursively."""
    corners = np.array(polygon)
    extent = corners.max(axis=0) - corners.min(axis=0)
    for axis in range(3):
        if extent[axis] > size:
            middle = 0.5 * (corners[:, axis].max() + corners[:, axis].min())
            front = _clip(polygon, axis, middle, True)
            back = _clip(polygon, axis, middle, False)
            return (subdivide_winding(front, size) if len(front) >= 3 else []) + \
                (subdivide_winding(back, size) if len(back) >= 3 else [])
    return [polygon]


def _area(polygon: np.ndarray) -> float:
    return float(0.5 * sum(np.linalg.norm(np.cross(polygon[i - 1] - polygon[0], polygon[i] - polygon[0]))
                           for i in range(2, len(polygon))))


def surface_emitters(bsp: Bsp, shaders: dict[int, ShaderLight]) -> tuple[AreaLights, np.ndarray, np.ndarray, np.ndarray,
                                                                         np.ndarray]:
    """Area lights and backsplash point lights (positions, colours, intensities, shaders) of every face whose
    shader emits (billboards excluded, as CreateSurfaceLights only handles planar, soup and patch)."""
    faces = np.flatnonzero(np.isin(bsp.faces["shader"], list(shaders)) &
                           np.isin(bsp.faces["type"], (FACE_POLYGON, FACE_PATCH, FACE_MESH)))
    if faces.size == 0:
        return AreaLights.empty(), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.int64)
    corners, vertex_normals, face = surface_triangles(bsp, faces)
    windings, normals, origins, areas, add, colours, sided, shader_of = [], [], [], [], [], [], [], []
    splash_pos, splash_col, splash_int, splash_shader = [], [], [], []
    for triangle, triangle_normals, f in zip(corners, vertex_normals, face):
        shader = int(bsp.faces["shader"][f])
        light = shaders[shader]
        pieces = subdivide_winding(list(triangle), light.subdivide)
        for piece in pieces:
            polygon = np.array(piece)
            area = _area(polygon)
            if area < 1.0 or area > 2e7:
                continue
            normal = triangle_normals.mean(axis=0)
            length = np.linalg.norm(normal)
            if length == 0:
                continue
            normal = normal / length
            origin = 0.5 * (polygon.min(axis=0) + polygon.max(axis=0)) + ORIGIN_NUDGE * normal
            windings.append(polygon)
            normals.append(normal)
            origins.append(origin)
            areas.append(area)
            add.append(light.value * FORM_FACTOR_VALUE_SCALE * AREA_SCALE)
            colours.append(light.colour)
            sided.append(light.two_sided)
            shader_of.append(shader)
            if len(pieces) == 1 and light.backsplash_fraction > 0:
                splash_pos.append(origin + light.backsplash_distance * normal)
                splash_col.append(light.colour)
                splash_int.append(light.value * area * AREA_SCALE * light.backsplash_fraction / POINT_SCALE)
                splash_shader.append(shader)
    if not windings:
        return AreaLights.empty(), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.int64)
    size = max(len(w) for w in windings)
    padded = np.stack([np.concatenate([w, np.repeat(w[-1:], size - len(w), axis=0)]) for w in windings])
    return (AreaLights(corners=padded, normals=np.array(normals), origins=np.array(origins), areas=np.array(areas),
                       add=np.array(add), colours=np.array(colours), two_sided=np.array(sided, bool),
                       shader=np.array(shader_of, np.int64)),
            np.array(splash_pos).reshape(-1, 3), np.array(splash_col).reshape(-1, 3), np.array(splash_int),
            np.array(splash_shader, np.int64))
