"""The light rig file (JSON, Documentation~/lights.md §5) and a level's own light entities.

A rig is a list of lights in Unity metres and axes (the importer's mapping, scenes/coords.py),
with a colour normalised to a largest component of 1 and an intensity in q3map2 `light` units
(the falloff is q3map2's default point light, model.py) — point lights and spotlights (a unit
direction and q3map2's radiusByDist cone) — plus surface lights (a shader's emitting surfaces of
the level with their q3map_surfacelight value, emitters.py) and the level's ambient in lightmap
bytes, so a recovered rig and a level's light entities, shader lights and worldspawn ambient are
directly comparable. Version 2 added spotlights and surface lights, version 3 suns (q3map2's directional
light from the sky: a unit direction toward the sun in Unity axes, a colour and an intensity in photons), version 4
each surface light's q3map2 settings besides its value (q3map_lightSubdivide, two-sidedness, q3map_backsplash: what the
fit's or the scripts' emitters were built with, so the rig re-lights as it was fitted); version 1-3 files are still
read, their surface lights with q3map2's defaults for those.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidInputError
from ..core.atomic import write_text_atomic
from ..scenes.coords import quake_to_unity, unity_to_quake
from ..scenes.entities import light_entities, parse_vector
from ..scenes.errors import BspError
from .emitters import BACKSPLASH_DISTANCE, BACKSPLASH_FRACTION, DEFAULT_LIGHT_SUBDIVIDE
from .model import BYTE_MAX

FORMAT = "lpnn-light-rig"
VERSION = 4
READABLE_VERSIONS = (1, 2, 3, 4)
POINT, SPOT = "point", "spot"
FALLOFF = "q3map2-point"  # 7500 * I * cos / max(r, 16 units)^2 bytes (model.py)
DEFAULT_ENTITY_INTENSITY = 300.0  # q3map2: a light without (or with 0) `_light` / `light`
SPAWNFLAG_LINEAR = 1
SPOT_DEFAULT_RADIUS = 64.0  # light.c CreateEntityLights


class RigError(InvalidInputError):
    """A rig file cannot be used; the message names the file, the light and the value."""


@dataclass(frozen=True)
class SurfaceLight:
    """The emitting surfaces of one shader of the level (every face drawn with it), q3map2's area lights."""
    shader: str  # the BSP's shader name, e.g. textures/base_light/ceil1_22a
    value: float  # q3map_surfacelight, >= 0
    colour: np.ndarray  # (3,) largest component 1
    # q3map2's other settings of the shader's light (emitters.ShaderLight; rig version 4, q3map2's defaults before)
    subdivide: float = DEFAULT_LIGHT_SUBDIVIDE  # q3map_lightSubdivide, Quake units
    two_sided: bool = False  # cull none / twoSided, or fog: emits from both sides
    backsplash_fraction: float = BACKSPLASH_FRACTION  # q3map_backsplash percent / 100
    backsplash_distance: float = BACKSPLASH_DISTANCE  # q3map_backsplash distance, Quake units


@dataclass(frozen=True)
class Sun:
    """q3map2's sun (EMIT_SUN, emitters.py): a lit luxel of normal n gets colour x intensity x max(0, n . direction)
    bytes. A q3map_sun's unit-length colour c and photons P are colour c / max(c) and intensity P max(c) here, so
    the colour's largest component is 1 as everywhere in a rig (Sun.from_quake)."""
    direction: np.ndarray  # (3,) unit, Unity axes, toward the sun
    colour: np.ndarray  # (3,) largest component 1
    intensity: float  # photons per unit colour, >= 0

    @classmethod
    def from_quake(cls, direction: np.ndarray, colour: np.ndarray, photons: float) -> "Sun":
        """From Quake axes and a colour of any scale (its largest component moves into the intensity)."""
        colour = np.asarray(colour, dtype=np.float64)
        peak = float(colour.max())
        return cls(direction=quake_to_unity(np.asarray(direction, dtype=np.float64)[None], scale=1.0)[0],
                   colour=colour / peak if peak > 0 else np.ones(3), intensity=float(photons) * max(peak, 0.0))

    def quake_direction(self) -> np.ndarray:
        return unity_to_quake(np.asarray(self.direction, dtype=np.float64)[None], scale=1.0)[0]


@dataclass
class Rig:
    positions: np.ndarray  # (J, 3) Unity metres
    colours: np.ndarray  # (J, 3) largest component 1 (or all 0 for a black light)
    intensities: np.ndarray  # (J,) q3map2 light units, >= 0
    ambient: np.ndarray = field(default_factory=lambda: np.zeros(3))  # (3,) lightmap bytes added everywhere
    level: str = ""
    bsp_sha256: str = ""
    scheme: str = ""
    objective: float | None = None
    extra: dict[str, Any] = field(default_factory=dict)  # grid, iterations, timings: informative only
    # spotlights: (J, 3) unit direction in Unity axes and (J,) radiusByDist, 0 for a point light; empty: all points
    spot_directions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    radius_by_dist: np.ndarray = field(default_factory=lambda: np.zeros(0))
    surfaces: list[SurfaceLight] = field(default_factory=list)
    suns: list[Sun] = field(default_factory=list)

    @property
    def count(self) -> int:
        return len(self.positions)

    @property
    def spot(self) -> np.ndarray:
        """(J,) bool: the light is a spotlight."""
        if len(self.radius_by_dist) != self.count:
            return np.zeros(self.count, bool)
        return self.radius_by_dist > 0

    @property
    def point_lights_only(self) -> bool:
        return not self.spot.any() and not self.surfaces and not self.suns

    def quake_positions(self) -> np.ndarray:
        return unity_to_quake(self.positions)

    @classmethod
    def from_quake(cls, positions: np.ndarray, colours: np.ndarray, intensities: np.ndarray, **info: Any) -> "Rig":
        """Normalise colours to a largest component of 1, moving their scale into the intensity."""
        colours = np.asarray(colours, dtype=np.float64)
        peak = colours.max(axis=1) if len(colours) else np.zeros(0)
        safe = np.where(peak > 0, peak, 1.0)
        return cls(positions=quake_to_unity(positions), colours=np.where(peak[:, None] > 0, colours / safe[:, None], 1.0),
                   intensities=np.asarray(intensities, dtype=np.float64) * np.where(peak > 0, peak, 0.0), **info)


def write_rig(path: Path, rig: Rig) -> Path:
    validate_rig(rig, str(path))
    spot = rig.spot
    lights = []
    for index, (p, c, i) in enumerate(zip(rig.positions, rig.colours, rig.intensities)):
        light: dict[str, Any] = {"type": SPOT if spot[index] else POINT, "position": [round(float(v), 6) for v in p],
                                 "color": [round(float(v), 6) for v in c], "intensity": round(float(i), 4)}
        if spot[index]:
            light["direction"] = [round(float(v), 6) for v in rig.spot_directions[index]]
            light["radius_by_dist"] = round(float(rig.radius_by_dist[index]), 6)
        lights.append(light)
    document = {
        "format": FORMAT,
        "version": VERSION,
        "level": rig.level,
        "bsp_sha256": rig.bsp_sha256,
        "units": {"position": "m, Unity axes", "intensity": "q3map2 light", "direction": "unit, Unity axes",
                  "surface value": "q3map2 q3map_surfacelight",
                  "sun intensity": "q3map2 photons (bytes at normal incidence per unit colour)"},
        "falloff": FALLOFF,
        "scheme": rig.scheme,
        "objective": rig.objective,
        "ambient": [round(float(v), 4) for v in rig.ambient],
        "lights": lights,
        "surfaces": [{"shader": surface.shader, "value": round(float(surface.value), 4),
                      "color": [round(float(v), 6) for v in surface.colour], "subdivide": float(surface.subdivide),
                      "two_sided": bool(surface.two_sided),
                      "backsplash": [float(surface.backsplash_fraction), float(surface.backsplash_distance)]}
                     for surface in rig.surfaces],
        "suns": [{"direction": [round(float(v), 6) for v in sun.direction], "color": [round(float(v), 6) for v in sun.colour],
                  "intensity": round(float(sun.intensity), 4)} for sun in rig.suns],
        "info": rig.extra,
    }
    return write_text_atomic(path, json.dumps(document, indent=1, allow_nan=False) + "\n")


def read_rig(path: Path) -> Rig:
    where = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise RigError(f"{where}: cannot read the rig: {exc}") from exc
    try:
        document = json.loads(text)
    except json.JSONDecodeError as exc:
        raise RigError(f"{where}: not JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from exc
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise RigError(f"{where}: not a light rig (its 'format' must be {FORMAT!r}); write one with lpnn scene lights")
    version = document.get("version")
    if version not in READABLE_VERSIONS or isinstance(version, bool):
        raise RigError(f"{where}: rig version {version!r} is not supported (this lpnn reads "
                       f"{', '.join(map(str, READABLE_VERSIONS))})")
    lights = document.get("lights")
    surfaces_in = document.get("surfaces", []) if version >= 2 else []
    if not isinstance(surfaces_in, list):
        raise RigError(f"{where}: 'surfaces' = {surfaces_in!r} must be a list of surface lights")
    suns_in = document.get("suns", []) if version >= 3 else []
    if not isinstance(suns_in, list):
        raise RigError(f"{where}: 'suns' = {suns_in!r} must be a list of suns")
    if not isinstance(lights, list) or (not lights and not surfaces_in and not suns_in):
        raise RigError(f"{where}: 'lights' must be a list of lights, non-empty unless 'surfaces' has surface lights "
                       f"or 'suns' has suns")
    positions, colours, intensities, directions, cones = [], [], [], [], []
    for index, light in enumerate(lights):
        if not isinstance(light, dict):
            raise RigError(f"{where}: light {index} is not an object with position, color and intensity")
        kind = light.get("type", POINT) if version >= 2 else POINT
        if kind not in (POINT, SPOT):
            raise RigError(f"{where}: light {index}: 'type' = {kind!r} is not {POINT!r} or {SPOT!r}")
        positions.append(_numbers(light.get("position"), 3, f"{where}: light {index}: 'position'"))
        colours.append(_numbers(light.get("color"), 3, f"{where}: light {index}: 'color'"))
        intensities.append(_numbers([light.get("intensity")], 1, f"{where}: light {index}: 'intensity'")[0])
        if kind == SPOT:
            directions.append(_numbers(light.get("direction"), 3, f"{where}: light {index}: 'direction'"))
            cones.append(_numbers([light.get("radius_by_dist")], 1, f"{where}: light {index}: 'radius_by_dist'")[0])
            if not cones[-1] > 0:
                raise RigError(f"{where}: light {index}: 'radius_by_dist' = {cones[-1]!r} must be > 0 for a spotlight")
        else:
            directions.append([0.0, 0.0, 0.0])
            cones.append(0.0)
    surfaces = []
    for index, surface in enumerate(surfaces_in):
        what = f"{where}: surface light {index}"
        if not isinstance(surface, dict) or not isinstance(surface.get("shader"), str) or not surface["shader"]:
            raise RigError(f"{what} = {surface!r} is not an object with a shader name, value and color")
        settings = {}  # version 4: q3map2's settings besides the value; absent (and before version 4) its defaults
        if version >= 4 and "subdivide" in surface:
            settings["subdivide"] = _numbers([surface["subdivide"]], 1, f"{what}: 'subdivide'")[0]
        if version >= 4 and "two_sided" in surface:
            if not isinstance(surface["two_sided"], bool):
                raise RigError(f"{what}: 'two_sided' = {surface['two_sided']!r} must be true or false")
            settings["two_sided"] = surface["two_sided"]
        if version >= 4 and "backsplash" in surface:
            settings["backsplash_fraction"], settings["backsplash_distance"] = _numbers(
                surface["backsplash"], 2, f"{what}: 'backsplash'")
        surfaces.append(SurfaceLight(shader=surface["shader"],
                                     value=_numbers([surface.get("value")], 1, f"{what}: 'value'")[0],
                                     colour=np.array(_numbers(surface.get("color"), 3, f"{what}: 'color'")), **settings))
    suns = []
    for index, sun in enumerate(suns_in):
        what = f"{where}: sun {index}"
        if not isinstance(sun, dict):
            raise RigError(f"{what} = {sun!r} is not an object with direction, color and intensity")
        suns.append(Sun(direction=np.array(_numbers(sun.get("direction"), 3, f"{what}: 'direction'")),
                        colour=np.array(_numbers(sun.get("color"), 3, f"{what}: 'color'")),
                        intensity=_numbers([sun.get("intensity")], 1, f"{what}: 'intensity'")[0]))
    objective = document.get("objective")
    ambient = _numbers(document.get("ambient"), 3, f"{where}: 'ambient'")
    rig = Rig(positions=np.array(positions).reshape(-1, 3), colours=np.array(colours).reshape(-1, 3),
              intensities=np.array(intensities), ambient=np.array(ambient),
              spot_directions=np.array(directions).reshape(-1, 3), radius_by_dist=np.array(cones), surfaces=surfaces, suns=suns,
              level=str(document.get("level", "")), bsp_sha256=str(document.get("bsp_sha256", "")),
              scheme=str(document.get("scheme", "")),
              objective=float(objective) if isinstance(objective, (int, float)) else None,
              extra=document.get("info") if isinstance(document.get("info"), dict) else {})
    validate_rig(rig, where)
    return rig


def validate_rig(rig: Rig, where: str) -> None:
    if rig.ambient.shape != (3,) or not np.isfinite(rig.ambient).all() or (rig.ambient < 0).any() \
            or (rig.ambient > BYTE_MAX).any():
        raise RigError(f"{where}: ambient {rig.ambient.tolist()} must be 3 numbers in [0, 255] (lightmap bytes)")
    for index in range(rig.count):
        intensity = float(rig.intensities[index])
        if not math.isfinite(intensity) or intensity < 0:
            raise RigError(f"{where}: light {index}: intensity {intensity!r} must be a finite number >= 0 "
                           f"(q3map2 light units; a negative, NaN or infinite light is not a point light)")
        colour = rig.colours[index]
        if not np.isfinite(colour).all() or (colour < 0).any() or (colour > 1 + 1e-9).any():
            raise RigError(f"{where}: light {index}: color {colour.tolist()} must be 3 numbers in [0, 1]")
        if not np.isfinite(rig.positions[index]).all():
            raise RigError(f"{where}: light {index}: position {rig.positions[index].tolist()} is not finite")
    if len(rig.radius_by_dist) not in (0, rig.count) or len(rig.spot_directions) != len(rig.radius_by_dist):
        raise RigError(f"{where}: {len(rig.radius_by_dist)} spotlight cones and {len(rig.spot_directions)} directions "
                       f"for {rig.count} lights (give one of each per light, or none)")
    for index in np.flatnonzero(rig.spot):
        cone, direction = float(rig.radius_by_dist[index]), rig.spot_directions[index]
        if not math.isfinite(cone):
            raise RigError(f"{where}: light {index}: radius_by_dist {cone!r} is not finite")
        if not np.isfinite(direction).all() or abs(float(np.linalg.norm(direction)) - 1.0) > 1e-4:
            raise RigError(f"{where}: light {index}: direction {direction.tolist()} must be a unit vector")
    for index, surface in enumerate(rig.surfaces):
        if not math.isfinite(surface.value) or surface.value < 0:
            raise RigError(f"{where}: surface light {index} ({surface.shader}): value {surface.value!r} must be a "
                           f"finite number >= 0 (q3map_surfacelight)")
        colour = np.asarray(surface.colour)
        if colour.shape != (3,) or not np.isfinite(colour).all() or (colour < 0).any() or (colour > 1 + 1e-9).any():
            raise RigError(f"{where}: surface light {index} ({surface.shader}): color {colour.tolist()} must be 3 "
                           f"numbers in [0, 1]")
        if not math.isfinite(surface.subdivide) or surface.subdivide <= 0:
            raise RigError(f"{where}: surface light {index} ({surface.shader}): subdivide {surface.subdivide!r} must be "
                           f"a finite number > 0 (q3map_lightSubdivide, Quake units)")
        if not all(math.isfinite(v) and v >= 0 for v in (surface.backsplash_fraction, surface.backsplash_distance)):
            raise RigError(f"{where}: surface light {index} ({surface.shader}): backsplash "
                           f"{[surface.backsplash_fraction, surface.backsplash_distance]!r} must be 2 finite numbers >= 0 "
                           f"(q3map_backsplash's fraction and distance)")
    for index, sun in enumerate(rig.suns):
        intensity, colour, direction = float(sun.intensity), np.asarray(sun.colour), np.asarray(sun.direction)
        if not math.isfinite(intensity) or intensity < 0:
            raise RigError(f"{where}: sun {index}: intensity {intensity!r} must be a finite number >= 0 (q3map2 photons)")
        if colour.shape != (3,) or not np.isfinite(colour).all() or (colour < 0).any() or (colour > 1 + 1e-9).any():
            raise RigError(f"{where}: sun {index}: color {colour.tolist()} must be 3 numbers in [0, 1]")
        if direction.shape != (3,) or not np.isfinite(direction).all() or \
                abs(float(np.linalg.norm(direction)) - 1.0) > 1e-4:
            raise RigError(f"{where}: sun {index}: direction {direction.tolist()} must be a unit vector (Unity axes, "
                           f"toward the sun)")
    if rig.count == 0 and not rig.surfaces and not rig.suns:
        raise RigError(f"{where}: the rig has no light, no surface light and no sun")


def _numbers(value: Any, count: int, what: str) -> list[float]:
    if not isinstance(value, list) or len(value) != count or \
            not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        raise RigError(f"{what} = {value!r} is not {count} number(s)")
    return [float(v) for v in value]


@dataclass(frozen=True)
class EntityLights:
    rig: Rig  # point lights and spotlights (the positions a rig can match)
    linear: np.ndarray  # (J,) bool: spawnflags 1 (linear falloff)
    skipped: dict[str, int]  # reason -> light entities left out
    spot: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))  # (J,) bool: a spotlight
    spot_direction: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # (J, 3) Quake axes, unit
    radius_by_dist: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (J,) the cone, 0 for a point light


def entity_lights(entities: list[dict[str, str]], level_name: str) -> EntityLights:
    """The level's light entities as q3map2 reads them (quake3-bsp.md §5): origin, `_light` then
    `light` (300 when missing or 0) x `scale`, `_color` normalised to max 1. Suns and negative
    (subtractive) lights are left out and counted. A light whose `target` names an entity with an
    origin is a spotlight (light.c CreateEntityLights: unit direction to the target's origin,
    radiusByDist = (`radius`, default 64, + 16) / distance, distance 0 -> 64)."""
    positions, colours, intensities, linear = [], [], [], []
    spots, directions, cones = [], [], []
    targets = {e["targetname"]: e for e in entities if "targetname" in e and "origin" in e}
    skipped = {"sun": 0, "negative or zero": 0, "no origin": 0, "grid only (lightJunior)": 0}
    for number, entity in enumerate(light_entities(entities)):
        what = f"{level_name}: light entity {number}"
        reason = _not_a_lightmap_point_light(entity)
        if reason is not None:
            skipped[reason] += 1
            continue
        if "origin" not in entity:
            skipped["no origin"] += 1
            continue
        origin = parse_vector(entity["origin"], 3, f"{what}: key 'origin'")
        intensity = _float(entity.get("_light", entity.get("light", "0")), f"{what}: key '_light'")
        if intensity == 0:
            intensity = DEFAULT_ENTITY_INTENSITY
        intensity *= _float(entity.get("scale", "1"), f"{what}: key 'scale'")
        if intensity <= 0:
            skipped["negative or zero"] += 1
            continue
        colour = np.array(parse_vector(entity["_color"], 3, f"{what}: key '_color'")) if "_color" in entity else np.ones(3)
        if colour.max() <= 0:
            colour = np.ones(3)
        positions.append(origin)
        colours.append(colour / colour.max())
        intensities.append(intensity)
        linear.append(int(_float(entity.get("spawnflags", "0"), f"{what}: key 'spawnflags'")) & SPAWNFLAG_LINEAR != 0)
        target = targets.get(entity.get("target", ""))
        direction, cone = np.zeros(3), 0.0
        if target is not None:
            offset = np.array(parse_vector(target["origin"], 3, f"{what}: its target's 'origin'")) - np.array(origin)
            distance = float(np.linalg.norm(offset))
            direction = offset / distance if distance > 0 else np.array([0.0, 0.0, -1.0])
            radius = _float(entity.get("radius", "0"), f"{what}: key 'radius'") or SPOT_DEFAULT_RADIUS
            cone = (radius + 16.0) / (distance if distance > 0 else SPOT_DEFAULT_RADIUS)
        spots.append(target is not None)
        directions.append(direction)
        cones.append(cone)
    rig = Rig.from_quake(np.array(positions).reshape(-1, 3), np.array(colours).reshape(-1, 3),
                         np.array(intensities), ambient=worldspawn_ambient(entities, level_name),
                         level=level_name, scheme="light entities",
                         spot_directions=quake_to_unity(np.array(directions).reshape(-1, 3), scale=1.0),
                         radius_by_dist=np.array(cones, dtype=np.float64))
    return EntityLights(rig=rig, linear=np.array(linear, dtype=bool), skipped=skipped, spot=np.array(spots, dtype=bool),
                        spot_direction=np.array(directions).reshape(-1, 3), radius_by_dist=np.array(cones))


def worldspawn_ambient(entities: list[dict[str, str]], level_name: str) -> np.ndarray:
    """q3map2's ambient (bytes every luxel starts at, light.c LightWorld): worldspawn `_ambient`, or
    `ambient` when that is 0, times `_color` as given (white when absent or zero), clamped to [0, 255]."""
    world = entities[0] if entities else {}
    value = _float(world.get("_ambient", "0"), f"{level_name}: worldspawn key '_ambient'")
    if value == 0:
        value = _float(world.get("ambient", "0"), f"{level_name}: worldspawn key 'ambient'")
    colour = np.array(parse_vector(world["_color"], 3, f"{level_name}: worldspawn key '_color'")) \
        if "_color" in world else np.ones(3)
    if not np.any(colour):
        colour = np.ones(3)
    return np.clip(value * colour, 0.0, BYTE_MAX)


def _not_a_lightmap_point_light(entity: dict[str, str]) -> str | None:
    if entity.get("classname", "").lower() == "lightjunior":  # lights the grid only, not the lightmaps
        return "grid only (lightJunior)"
    if entity.get("_sun", "0") not in ("", "0"):
        return "sun"
    return None


def _float(text: str, what: str) -> float:
    try:
        value = float(text.split()[0]) if text.split() else 0.0
    except ValueError as exc:
        raise BspError(f"{what}: {text!r} is not a number") from exc
    if not math.isfinite(value):
        raise BspError(f"{what}: {text!r} is not finite")
    return value
