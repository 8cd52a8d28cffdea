"""How good a rig is (Documentation~/lights.md §6): against the level's real lights, and against the
light grid the compiler stored.

Rig vs rig (positions in metres, "power" = intensity x largest colour component):
  - intensity-weighted distance real -> recovered: sum_a P_a min_b |x_a - x_b| / sum_a P_a, and the
    same the other way (a rig that adds lights where there are none pays in the second figure);
  - matched share: the share of real power with a significant recovered light (at least
    SIGNIFICANT_SHARE of the recovered power) within `radius` (1 m).
Surface lights (rig.py version 2) take part in the matched share: each emitting piece of a real surface
light (q3map2's subdivided area light, emitters.py) carries the power of the point light of equal flux,
add x area / (4 pi 7500) (an area light sends add x area byte-units^2 into its hemisphere, a point light
7500 I x 4 pi into the sphere), and is matched when a significant recovered surface light of the same
shader lies on it, or a significant recovered point light lies within `radius` of it (distance to the
piece's polygon). A recovered surface light's power is its value's on every piece of its shader.

Light grid re-lit from a rig vs the stored grid, at the stored grid's valid nodes (ambient > 0):
every light visible from the node (an Embree shadow ray) contributes c = colour 7500 I / max(r, 16)^2
bytes (no cosine, contributions of 1 byte or less dropped), combined as q3map2 builds its grid
(quake3-bsp.md §5: l = normalize(sum |c| dir), D = sum max(0, dir.l) c, A = sum 0.25 (1 - dir.l) c
+ 0.125 D, clamped to 255 keeping the hue). The rig's ambient is not in it: q3map2 fills its grid with
the ambient before it reads worldspawn's `_ambient` (light.c LightWorld calls SetupGrid, which copies ambientColor
into every raw grid point, before it sets ambientColor), so its grids hold none (oa_bases3, from its real lights:
error 0.039 without, 0.388 with; Tools~/experiments/lights-grid-gap.py). Both grids are shaded as the engine does,
a + d max(0, n.l), in the 14 directions D14 and compared with quality.md's relative irradiance
error (lpnn.quality.metric.metric.irradiance_error; its scene scale S from the stored grid's SH).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..core.features import D14, scene_scale
from ..core.sh import ambient_plus_directed
from ..quality.metric.metric import irradiance_error
from ..scenes.bsp import Bsp
from ..scenes.errors import BspError
from ..scenes.lightgrid import decode_directions
from ..scenes.coords import unity_to_quake
from ..scenes.raycast import EmbreeRaycaster
from .emitters import Emitters, Spots, emitters_at_points
from .model import POINT_SCALE
from .pointlight import visible_light
from .rig import Rig

MATCH_RADIUS = 1.0  # metres
SIGNIFICANT_SHARE = 0.01
BYTE_MAX = 255.0
GRID_AMBIENT_FUDGE = 0.125  # q3map2's "keep ambient up" share of the directed light (id q3map: 0.25)
NODES_PER_CHUNK = 2048


@dataclass(frozen=True)
class SurfacePieces:
    """The emitting pieces of surface lights (from emitters.AreaLights), in Unity metres."""
    shader: list[str]  # (K,) the piece's shader name
    corners: np.ndarray  # (K, P, 3) Unity metres, padded by repeating the last corner
    normals: np.ndarray  # (K, 3) unit, Unity axes
    power: np.ndarray  # (K,) the equal-flux point light's intensity x largest colour component

    @property
    def count(self) -> int:
        return len(self.shader)


def equal_flux_intensity(add: np.ndarray, area: np.ndarray) -> np.ndarray:
    """The q3map2 `light` intensity of the point light sending the same flux as an area light of `add`
    bytes per unit form factor and `area` square units: add x area / (4 pi POINT_SCALE)."""
    return np.asarray(add) * np.asarray(area) / (4.0 * np.pi * POINT_SCALE)


def polygon_distance(points: np.ndarray, corners: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(B, K) distance from each point (B, 3) to each convex planar polygon (K, P, 3) of unit normal (K, 3):
    the distance to its plane when the point projects inside it, else to its nearest edge."""
    if len(points) == 0 or len(corners) == 0:
        return np.zeros((len(points), len(corners)))
    rel = points[:, None, None, :] - corners[None]  # (B, K, P, 3)
    height = np.einsum("bkd,kd->bk", rel[:, :, 0, :], normals)
    edges = np.roll(corners, -1, axis=1) - corners  # (K, P, 3); padded corners give zero-length edges
    side = np.einsum("bkpd,kpd->bkp", np.cross(edges[None], rel), np.broadcast_to(normals[:, None, :], edges.shape))
    inside = np.all(side >= -1e-9, axis=2) | np.all(side <= 1e-9, axis=2)
    length_sq = np.einsum("kpd,kpd->kp", edges, edges)
    t = np.clip(np.einsum("bkpd,kpd->bkp", rel, edges) / np.where(length_sq > 0, length_sq, 1.0), 0.0, 1.0)
    nearest = np.linalg.norm(rel - t[..., None] * edges[None], axis=3).min(axis=2)
    return np.where(inside, np.abs(height), nearest)


@dataclass(frozen=True)
class RigComparison:
    real_lights: int
    recovered_lights: int
    real_to_recovered: float  # metres, intensity-weighted
    recovered_to_real: float  # metres, intensity-weighted
    matched_share: float  # of real power, with a significant recovered light within MATCH_RADIUS
    real_power: float
    recovered_power: float
    surface_share: float = 0.0  # of real power, in surface lights
    surface_matched_share: float = 0.0  # of real power, in matched surface lights


def compare_rigs(recovered: Rig, real: Rig, radius: float = MATCH_RADIUS, real_surfaces: SurfacePieces | None = None,
                 shader_power: dict[str, float] | None = None) -> RigComparison:
    """`real_surfaces`: the pieces of the real rig's surface lights; `shader_power`: a shader's equal-flux power
    per unit of q3map_surfacelight value over all its pieces (for the recovered rig's surface lights)."""
    real_has_surfaces = real_surfaces is not None and real_surfaces.count > 0
    if (real.count == 0 and not real_has_surfaces) or (recovered.count == 0 and not recovered.surfaces):
        raise ValueError(f"cannot compare rigs of {recovered.count} recovered and {real.count} real lights: "
                         f"both need at least one light (or surface light)")
    real_power = real.intensities * real.colours.max(axis=1) if real.count else np.zeros(0)
    found_power = recovered.intensities * recovered.colours.max(axis=1) if recovered.count else np.zeros(0)
    distance = np.linalg.norm(real.positions[:, None, :] - recovered.positions[None, :, :], axis=2)  # (A, B)
    unknown = [s.shader for s in recovered.surfaces if s.value > 0 and s.shader not in (shader_power or {})]
    if unknown:
        raise ValueError(f"recovered surface light(s) {unknown} have no emitting surface in the level to weigh them by")
    found_surfaces = {s.shader: s.value * max(float(np.max(s.colour)), 0.0) * (shader_power or {})[s.shader]
                      for s in recovered.surfaces if s.value > 0}
    found_total = float(found_power.sum()) + sum(found_surfaces.values())

    def weighted(axis: int, power: np.ndarray) -> float:
        total = float(power.sum())
        if total <= 0 or distance.size == 0:  # no point light on one side: no distance to weigh
            return float("nan")
        return float(np.sum(power * distance.min(axis=axis)) / total)

    floor = SIGNIFICANT_SHARE * max(found_total, np.finfo(float).tiny)
    significant = found_power >= floor
    near = np.any(distance[:, significant] <= radius, axis=1) if significant.any() and real.count \
        else np.zeros(real.count, bool)
    matched = float(real_power[near].sum())
    total_real = float(real_power.sum())
    surface_total = surface_matched = 0.0
    if real_surfaces is not None and real_surfaces.count:
        on_shader = np.array([found_surfaces.get(name, 0.0) >= floor for name in real_surfaces.shader])
        close = polygon_distance(recovered.positions[significant], real_surfaces.corners, real_surfaces.normals)
        piece_matched = on_shader | np.any(close <= radius, axis=0)
        surface_total = float(real_surfaces.power.sum())
        surface_matched = float(real_surfaces.power[piece_matched].sum())
    everything = total_real + surface_total
    return RigComparison(real_lights=real.count, recovered_lights=recovered.count,
                         real_to_recovered=weighted(1, real_power), recovered_to_real=weighted(0, found_power),
                         matched_share=(matched + surface_matched) / everything if everything > 0 else float("nan"),
                         real_power=everything, recovered_power=found_total,
                         surface_share=surface_total / everything if everything > 0 else 0.0,
                         surface_matched_share=surface_matched / everything if everything > 0 else 0.0)


@dataclass(frozen=True)
class GridNodes:
    positions: np.ndarray  # (M, 3) Quake units, valid nodes only
    ambient: np.ndarray  # (M, 3) bytes
    directed: np.ndarray  # (M, 3) bytes
    direction: np.ndarray  # (M, 3) unit, toward the light


def stored_grid(bsp: Bsp) -> GridNodes:
    if bsp.light_grid is None:
        raise BspError(f"{bsp.name}: lump 15 (lightgrid) is empty: nothing to compare a rig with")
    layout = bsp.light_grid_layout
    records = np.asarray(bsp.light_grid, dtype=np.uint8)
    index = np.arange(layout.point_count)
    dims = layout.dims
    cell = np.stack([index % dims[0], (index // dims[0]) % dims[1], index // (dims[0] * dims[1])], axis=1)
    valid = records[:, 0:3].astype(np.int64).sum(axis=1) > 0  # all-zero ambient: "in a wall"
    return GridNodes(positions=(layout.origin + cell * layout.cell_size)[valid],
                     ambient=records[valid, 0:3].astype(np.float64), directed=records[valid, 3:6].astype(np.float64),
                     direction=decode_directions(records[valid, 6], records[valid, 7]))


def grid_sample_points(nodes: np.ndarray, is_open) -> np.ndarray:
    """Where q3map2 samples each grid node (light.c TraceGrid): the node itself when it is in open
    space, else the first of the 8 diagonal offsets of +-9 units, then of +-18 units (x sign from bit
    0, y from bit 1, z from bit 2, minus first), that is; a node with none keeps its position."""
    out = np.asarray(nodes, dtype=np.float64).copy()
    todo = ~is_open(out)
    for step in (9.0, 18.0):
        for i in range(8):
            if not todo.any():
                return out
            offset = step * np.array([1.0 if i & 1 else -1.0, 1.0 if i & 2 else -1.0, 1.0 if i & 4 else -1.0])
            candidate = nodes[todo] + offset
            found = is_open(candidate)
            index = np.flatnonzero(todo)[found]
            out[index] = candidate[found]
            todo[index] = False
    return out


def grid_inhibit(bsp: Bsp) -> float:
    """light.c TraceGrid's inhibitRadius: half the largest side of a grid cell (Quake units)."""
    return 0.5 * float(np.max(bsp.light_grid_layout.cell_size))


def relight_stored_grid(bsp: Bsp, stored: GridNodes, rig: Rig, raycaster: EmbreeRaycaster | None, is_open,
                        emitters: Emitters | None = None) -> GridNodes:
    """The stored grid's valid nodes re-lit as q3map2 lights them: each sampled where TraceGrid
    samples it (grid_sample_points), occluders within grid_inhibit ignored."""
    relit = relight_grid(grid_sample_points(stored.positions, is_open), rig, raycaster, emitters, grid_inhibit(bsp))
    return GridNodes(positions=stored.positions, ambient=relit.ambient, directed=relit.directed,
                     direction=relit.direction)


def relight_grid(nodes: np.ndarray, rig: Rig, raycaster: EmbreeRaycaster | None,
                 emitters: Emitters | None = None, inhibit: float = 0.0) -> GridNodes:
    """The grid q3map2 would store at `nodes` (Quake units) for the rig's point lights (and the
    emitters: spotlights, surface lights, emitters.py), light.c TraceGrid's rule, without the rig's ambient (q3map2's
    grid holds none, module docstring); occluders within
    `inhibit` units of a node are ignored (TraceGrid's inhibitRadius, GRID_INHIBIT_RADIUS). The rig's
    spotlights light the nodes with their cone (as the emitters' spotlights)."""
    ambient = np.zeros((len(nodes), 3))
    directed = np.zeros((len(nodes), 3))
    direction = np.zeros((len(nodes), 3))
    for start in range(0, len(nodes), NODES_PER_CHUNK):
        chunk = slice(start, start + NODES_PER_CHUNK)
        colour, unit, _ = grid_contributions(nodes[chunk], rig, raycaster, emitters, inhibit)
        ambient[chunk], directed[chunk], direction[chunk] = q3map2_grid(colour, unit)
    return GridNodes(positions=nodes, ambient=ambient, directed=directed, direction=direction)


def grid_contributions(nodes: np.ndarray, rig: Rig, raycaster: EmbreeRaycaster | None, emitters: Emitters | None = None,
                       inhibit: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What every light of the rig (and the emitters) gives each node, light.c LightContributionToPoint: bytes
    (C, K, 3), unit directions toward the light (C, K, 3), and the K sources' positions (K, 3, Quake units: the point
    lights, then the emitters' spotlights, backsplash lights and area lights' origins, then NaN for each sun)."""
    if rig.spot.any():
        rig, emitters = _spots_as_emitters(rig, emitters)
    lights = rig.quake_positions()
    emitted = rig.colours * rig.intensities[:, None] * POINT_SCALE  # (J, 3)
    colour, unit = visible_light(nodes, lights, emitted, raycaster, inhibit)  # (C, J, 3) each
    sources = [lights]
    if emitters is not None:
        more, more_unit = emitters_at_points(nodes, emitters, raycaster, inhibit)
        colour, unit = np.concatenate([colour, more], axis=1), np.concatenate([unit, more_unit], axis=1)
        sources += [emitters.spots.positions, emitters.splash_positions, emitters.areas.origins,
                    np.full((emitters.suns.count, 3), np.nan)]
    return colour, unit, np.concatenate(sources).reshape(-1, 3)


def q3map2_grid(colour: np.ndarray, unit: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """combine_grid without the rig's ambient: q3map2's grid holds none (module docstring)."""
    return combine_grid(colour, unit, np.zeros(3))


def combine_grid(colour: np.ndarray, unit: np.ndarray, ambient: np.ndarray,
                 fudge: float = GRID_AMBIENT_FUDGE) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """TraceGrid's sum of the contributions (C, K, 3) from unit directions (C, K, 3): (ambient A, directed D, direction
    l), each (C, 3): l = normalize(sum |c| dir), D = sum max(0, dir.l) c, A = sum 0.25 (1 - dir.l) c + `fudge` D +
    `ambient`, A and D clamped to 255 keeping the hue."""
    main = np.einsum("cj,cjk->ck", np.linalg.norm(colour, axis=2), unit)
    length = np.linalg.norm(main, axis=1, keepdims=True)
    main = np.divide(main, length, out=np.zeros_like(main), where=length > 0)
    cosine = np.einsum("cjk,ck->cj", unit, main)
    d = np.einsum("cj,cjk->ck", np.maximum(0.0, cosine), colour)
    a = np.einsum("cj,cjk->ck", 0.25 * (1.0 - cosine), colour) + fudge * d + ambient
    return _clamped(a), _clamped(d), main


def rig_spots(rig: Rig) -> Spots:
    """The rig's spotlights as emitters.Spots (Quake units and axes)."""
    spot = rig.spot
    return Spots(positions=rig.quake_positions()[spot], colours=rig.colours[spot], intensities=rig.intensities[spot],
                 directions=unity_to_quake(rig.spot_directions[spot], scale=1.0), radius_by_dist=rig.radius_by_dist[spot])


def _spots_as_emitters(rig: Rig, emitters: Emitters | None) -> tuple[Rig, Emitters]:
    """(the rig's point lights, the emitters with the rig's spotlights added)."""
    spots = rig_spots(rig)
    if emitters is None:
        emitters = Emitters(spots=spots)
    else:
        old = emitters.spots
        emitters = replace(emitters, spots=Spots(
            positions=np.concatenate([old.positions, spots.positions]),
            colours=np.concatenate([old.colours, spots.colours]),
            intensities=np.concatenate([old.intensities, spots.intensities]),
            directions=np.concatenate([old.directions, spots.directions]),
            radius_by_dist=np.concatenate([old.radius_by_dist, spots.radius_by_dist])))
    point = ~rig.spot
    points = replace(rig, positions=rig.positions[point], colours=rig.colours[point],
                     intensities=rig.intensities[point], spot_directions=np.zeros((0, 3)), radius_by_dist=np.zeros(0))
    return points, emitters


def _clamped(rgb: np.ndarray) -> np.ndarray:
    peak = rgb.max(axis=1, keepdims=True)
    return np.where(peak > BYTE_MAX, rgb * BYTE_MAX / np.maximum(peak, BYTE_MAX), rgb)


def shade(grid: GridNodes) -> np.ndarray:
    """(M, 42) the engine's a + d max(0, n.l) over D14 x RGB (D14 is closed under the axis mapping)."""
    cosine = np.maximum(0.0, grid.direction @ D14.T)  # (M, 14)
    return (grid.ambient[:, None, :] + grid.directed[:, None, :] * cosine[..., None]).reshape(len(cosine), -1)


@dataclass(frozen=True)
class GridComparison:
    nodes: int
    mean_error: float  # quality.md relative irradiance error, mean over nodes
    p95_error: float
    plain_relative: float  # sum |relit - stored| / sum |stored| over all nodes and values


def compare_grid(stored: GridNodes, relit: GridNodes) -> GridComparison:
    if len(stored.positions) == 0:
        raise ValueError("the stored light grid has no valid node (every record is 'in a wall')")
    reference, modelled = shade(stored), shade(relit)
    scale = scene_scale(ambient_plus_directed(stored.ambient, stored.directed, stored.direction).reshape(-1, 27))
    errors = irradiance_error(modelled, reference, scale)
    total = float(np.abs(reference).sum())
    return GridComparison(nodes=len(errors), mean_error=float(errors.mean()), p95_error=float(np.percentile(errors, 95)),
                          plain_relative=float(np.abs(modelled - reference).sum() / total) if total > 0 else float("nan"))
