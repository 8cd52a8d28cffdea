"""How good a rig is (Documentation~/lights.md §6): against the level's real lights, and against the
light grid the compiler stored.

Rig vs rig (positions in metres, "power" = intensity x largest colour component):
  - intensity-weighted distance real -> recovered: sum_a P_a min_b |x_a - x_b| / sum_a P_a, and the
    same the other way (a rig that adds lights where there are none pays in the second figure);
  - matched share: the share of real power with a significant recovered light (at least
    SIGNIFICANT_SHARE of the recovered power) within `radius` (1 m).

Light grid re-lit from a rig vs the stored grid, at the stored grid's valid nodes (ambient > 0):
every light visible from the node (an Embree shadow ray) contributes c = colour 7500 I / max(r, 16)^2
bytes (no cosine, contributions of 1 byte or less dropped), combined as q3map2 builds its grid
(quake3-bsp.md §5: l = normalize(sum |c| dir), D = sum max(0, dir.l) c, A = sum 0.25 (1 - dir.l) c
+ 0.125 D + the rig's ambient, clamped to 255 keeping the hue). The ambient is in the grid as id's
q3map puts it there (q3map2 sets its grid up before reading the ambient): the levels' stored grids
hold it (oa_bases3, from its real lights: error 0.90 without, 0.37 with). Both grids are shaded as the engine does,
a + d max(0, n.l), in the 14 directions D14 and compared with quality.md's relative irradiance
error (lpnn.quality.metric.irradiance_error; its scene scale S from the stored grid's SH).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.features import D14, scene_scale
from ..core.sh import ambient_plus_directed
from ..quality.metric import irradiance_error
from ..scenes.bsp import Bsp
from ..scenes.errors import BspError
from ..scenes.lightgrid import decode_directions
from ..scenes.raycast import EmbreeRaycaster
from .emitters import Emitters, emitters_at_points
from .model import POINT_SCALE
from .pointlight import visible_light
from .rig import Rig

MATCH_RADIUS = 1.0  # metres
SIGNIFICANT_SHARE = 0.01
BYTE_MAX = 255.0
GRID_AMBIENT_FUDGE = 0.125  # q3map2's "keep ambient up" share of the directed light (id q3map: 0.25)
NODES_PER_CHUNK = 2048


@dataclass(frozen=True)
class RigComparison:
    real_lights: int
    recovered_lights: int
    real_to_recovered: float  # metres, intensity-weighted
    recovered_to_real: float  # metres, intensity-weighted
    matched_share: float  # of real power, with a significant recovered light within MATCH_RADIUS
    real_power: float
    recovered_power: float


def compare_rigs(recovered: Rig, real: Rig, radius: float = MATCH_RADIUS) -> RigComparison:
    if real.count == 0 or recovered.count == 0:
        raise ValueError(f"cannot compare rigs of {recovered.count} recovered and {real.count} real lights: "
                         f"both need at least one light")
    real_power = real.intensities * real.colours.max(axis=1)
    found_power = recovered.intensities * recovered.colours.max(axis=1)
    distance = np.linalg.norm(real.positions[:, None, :] - recovered.positions[None, :, :], axis=2)  # (A, B)

    def weighted(nearest: np.ndarray, power: np.ndarray) -> float:
        total = float(power.sum())
        return float(np.sum(power * nearest) / total) if total > 0 else float("nan")

    significant = found_power >= SIGNIFICANT_SHARE * max(float(found_power.sum()), np.finfo(float).tiny)
    near = np.any(distance[:, significant] <= radius, axis=1) if significant.any() else np.zeros(real.count, bool)
    total_real = float(real_power.sum())
    return RigComparison(real_lights=real.count, recovered_lights=recovered.count,
                         real_to_recovered=weighted(distance.min(axis=1), real_power),
                         recovered_to_real=weighted(distance.min(axis=0), found_power),
                         matched_share=float(real_power[near].sum() / total_real) if total_real > 0 else float("nan"),
                         real_power=total_real, recovered_power=float(found_power.sum()))


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
    emitters: spotlights, surface lights, emitters.py), light.c TraceGrid's rule; occluders within
    `inhibit` units of a node are ignored (TraceGrid's inhibitRadius, GRID_INHIBIT_RADIUS)."""
    lights = rig.quake_positions()
    emitted = rig.colours * rig.intensities[:, None] * POINT_SCALE  # (J, 3)
    ambient = np.zeros((len(nodes), 3))
    directed = np.zeros((len(nodes), 3))
    direction = np.zeros((len(nodes), 3))
    for start in range(0, len(nodes), NODES_PER_CHUNK):
        chunk = slice(start, start + NODES_PER_CHUNK)
        colour, unit = visible_light(nodes[chunk], lights, emitted, raycaster, inhibit)  # (C, J, 3) each
        if emitters is not None:
            more, more_unit = emitters_at_points(nodes[chunk], emitters, raycaster, inhibit)
            colour, unit = np.concatenate([colour, more], axis=1), np.concatenate([unit, more_unit], axis=1)
        main = np.einsum("cj,cjk->ck", np.linalg.norm(colour, axis=2), unit)
        length = np.linalg.norm(main, axis=1, keepdims=True)
        main = np.divide(main, length, out=np.zeros_like(main), where=length > 0)
        cosine = np.einsum("cjk,ck->cj", unit, main)
        d = np.einsum("cj,cjk->ck", np.maximum(0.0, cosine), colour)
        a = np.einsum("cj,cjk->ck", 0.25 * (1.0 - cosine), colour) + GRID_AMBIENT_FUDGE * d + rig.ambient
        ambient[chunk], directed[chunk], direction[chunk] = _clamped(a), _clamped(d), main
    return GridNodes(positions=nodes, ambient=ambient, directed=directed, direction=direction)


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
