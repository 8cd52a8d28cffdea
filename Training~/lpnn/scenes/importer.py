"""Level -> capture: evaluation grid, removal of points in solid, SH from the light grid, features.

Which points cannot hold a probe (`validity`, openarena.md "Probe validity in the importer"): "bsp" (default) removes
the points in solid or outside the map by the exact BSP test; "rays" by the probe-validity rule of the Unity pipeline
alone (lpnn.core.validity: more than a quarter of the 26 rays meet back faces); "both" removes what either finds.

Everything is in Unity axes and metres (coords.py); the capture is the one Unity would export for
the same volume (file-formats.md), so training and evaluation run on real baked lighting.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np

from .. import __version__
from ..core.capture import Capture
from ..core.features import extract_features
from ..core.grid import EvaluationGrid, GridError
from ..core.grid_box import Box
from ..core.grid_builder import build_grid
from ..core.in_use import RULES as IN_USE_RULES
from ..core.in_use import InUseError, InUseParameters, in_use_mask
from ..core.in_use_section import IN_USE_SECTION
from ..core.schema import LPNN_V1
from ..core.validity import back_face_fractions, invalid
from .coords import quake_to_unity, unity_to_quake
from .defaults import DEFAULT_CELL, DEFAULT_POINT_LIMIT
from .errors import BspError
from .levels import Level, load_level
from .lightgrid import LightGrid
from .patches import PATCH_LEVEL
from .raycast import EmbreeRaycaster
from .seeds import seed_positions
from .solid import SolidTester
from .surfaces import ray_geometry

BACKEND = "openarena"
# The lattice before solid removal may hold this many times the point limit: only ids and
# positions exist at that stage (~24 bytes a point), and big open levels lose most of it.
LATTICE_FACTOR = 4
VALIDITY_MODES = ("bsp", "rays", "both")
DEFAULT_VALIDITY = "bsp"  # exact where a BSP exists; the measured reasons not to add the rays are in openarena.md

Progress = Callable[[str, int, int], None]  # (step, done, total)


class ProbeLighting(Protocol):
    """Lighting other than the light grid (lights/relight.py: a rig); scenes/ does not import lights/."""

    def sh_at(self, level: Level, unity_positions: np.ndarray,
              progress: Callable[[int, int], None] | None = None) -> tuple[np.ndarray, np.ndarray]: ...

    def source_fields(self) -> dict[str, str | int | bool]: ...


@dataclass
class ImportResult:
    capture: Capture
    level: Level
    removed_solid: int  # by the BSP test (validity "bsp" or "both")
    removed_invalid: int  # by the ray rule, beyond those (validity "rays" or "both")
    unlit_points: int  # points in the capture where every light grid corner is zero: black SH
    removed_unlit: int  # unlit points dropped (drop_unlit)
    points_before_in_use: int  # valid points before the in-use rule kept its own (all of them for `all`)
    lattice_points: int
    rays: int
    triangles: int
    # read, geometry, grid, solid, validity, sh, features (rays: time inside the raycaster, features and validity
    # rays together); the CLI adds write
    seconds: dict[str, float] = field(default_factory=dict)


def auto_box(level: Level) -> Box:
    """The light grid's extent as one axis-aligned box in Unity metres."""
    layout = level.bsp.light_grid_layout
    corners = quake_to_unity(np.stack([layout.origin, layout.maxs]))
    return Box.axis_aligned(corners.min(axis=0), corners.max(axis=0))


def import_level(source: str | Level, cell_size: float = DEFAULT_CELL, boxes: list[Box] | None = None,
                 point_limit: int = DEFAULT_POINT_LIMIT, bounds_label: str = "auto",
                 drop_unlit: bool = False, timings_in_source: bool = True,
                 progress: Progress | None = None, validity: str = DEFAULT_VALIDITY,
                 lighting: ProbeLighting | None = None, in_use: str = "all",
                 in_use_parameters: InUseParameters | None = None) -> ImportResult:
    """Import one level. boxes=None: the light grid's extent. Points in solid or outside the map
    are removed in every case (they cannot hold a probe). `point_limit` bounds the points kept.

    Unlit points (all 8 grid corners zero: q3map2 found no light, or no open space, there) keep
    black SH, unless drop_unlit removes them too: some levels enclose large dark voids that are
    not in solid (hydronex, oa_koth1, czest3ctf: about two thirds of their open points).

    timings_in_source=False leaves `feature_seconds` out of the capture, so the same level and cell
    give byte-identical files. `lighting`: None = the light grid; a rig = the probe baker's SH
    (lights/relight.py; "unlit" then means no light, ambient or bounce reaches the point).

    `in_use` (Documentation~/in-use.md): "band" or "reachable" (seeded by the level's spawns and items, seeds.py) keep
    only the points where dynamic objects go, before the light grid and the features are sampled (most of the time on
    large levels); "all" keeps every point and adds the section `in_use`, the mask of "reachable" (or "band" on a
    level without seeds), so reports can show the error where objects go.
    """
    if point_limit < 1:
        raise ValueError(f"point_limit {point_limit} must be at least 1")
    if validity not in VALIDITY_MODES:
        raise ValueError(f"validity {validity!r} must be one of {', '.join(VALIDITY_MODES)}")
    if in_use not in IN_USE_RULES:
        raise ValueError(f"in_use {in_use!r} must be one of {', '.join(IN_USE_RULES)}")
    seconds: dict[str, float] = {}
    clock = time.perf_counter()
    level = load_level(source) if isinstance(source, str) else source
    light_grid = LightGrid.from_bsp(level.bsp) if lighting is None else None
    seconds["read"] = time.perf_counter() - clock

    clock = time.perf_counter()
    soup = ray_geometry(level.bsp)
    raycaster = EmbreeRaycaster(quake_to_unity(soup.vertices), soup.triangles)
    seconds["geometry"] = time.perf_counter() - clock

    grid, lattice_points, removed, removed_invalid = _open_grid(level, boxes, cell_size, point_limit, validity, raycaster,
                                                                seconds, progress)

    clock = time.perf_counter()
    parameters = in_use_parameters if in_use_parameters is not None else InUseParameters()
    seeds = seed_positions(level.bsp.entities, level.location)
    points_before_in_use = grid.point_count
    if in_use != "all":
        try:
            grid = grid.subset(in_use_mask(in_use, grid, raycaster, parameters, seeds, progress))
        except InUseError as exc:
            raise InUseError(f"{level.location}: {exc}") from exc
    report_rule, report_mask = _report_mask(grid, raycaster, parameters, seeds) if in_use == "all" else ("", None)
    seconds["in_use"] = time.perf_counter() - clock

    clock = time.perf_counter()
    grid, sh, unlit, removed_unlit, kept = _sampled_sh(level, light_grid, lighting, grid, drop_unlit, progress)
    positions = grid.positions
    seconds["sh"] = time.perf_counter() - clock

    clock = time.perf_counter()
    feature_progress = None if progress is None else (lambda done, total: progress("features", done, total))
    features, scale = extract_features(grid, sh, raycaster, progress=feature_progress)
    seconds["features"] = time.perf_counter() - clock
    seconds["rays"] = raycaster.cast_seconds  # part of "features" (and of "validity" when the rays judge validity)
    rays = raycaster.rays_cast

    source_info = _source_info(level, bounds_label, rays, validity, removed, removed_invalid, unlit, removed_unlit)
    source_info.update({"lighting": "grid"} if lighting is None else lighting.source_fields())
    source_info.update(_in_use_fields(in_use, parameters, seeds.shape[0], points_before_in_use))
    extra_sections: dict[str, np.ndarray] = {}
    if report_mask is not None:  # computed on every valid point, as band and reachable are; unlit ones dropped after
        source_info["in_use_report_rule"] = report_rule
        extra_sections[IN_USE_SECTION] = report_mask[kept].astype(np.uint8)
    if timings_in_source:
        source_info["feature_seconds"] = round(seconds["features"], 3)
    capture = Capture(
        ids=grid.ids, positions=positions, sh=sh, features=features, schema=LPNN_V1.id,
        feature_names=list(LPNN_V1.names), cell_size=float(cell_size), lighting_scale=float(scale), units="m",
        source=source_info, extra_sections=extra_sections,
    )
    return ImportResult(capture=capture, level=level, removed_solid=removed, removed_invalid=removed_invalid, unlit_points=unlit,
                        removed_unlit=removed_unlit, points_before_in_use=points_before_in_use,
                        lattice_points=lattice_points, rays=rays, triangles=soup.triangle_count, seconds=seconds)


def _in_use_fields(rule: str, parameters: InUseParameters, seeds: int, points_before: int) -> dict[str, str | int | float]:
    """The capture's record of the in-use rule (in-use.md "What placement does with the mask")."""
    return {"in_use": rule, "in_use_band_height": parameters.band_height,
            "in_use_slope_limit": parameters.slope_limit_degrees, "in_use_step_height": parameters.step_height,
            "in_use_seeds": seeds, "points_before_in_use": points_before}


def _report_mask(grid: EvaluationGrid, raycaster: EmbreeRaycaster, parameters: InUseParameters,
                 seeds: np.ndarray) -> tuple[str, np.ndarray | None]:
    """An `all` capture's report mask: "reachable", else (no seeds, or none attaching) "band", else none at all
    (no walkable floor under any point: the report says "n/a")."""
    for rule in ("reachable", "band"):
        if rule == "reachable" and seeds.shape[0] == 0:
            continue
        try:
            return rule, in_use_mask(rule, grid, raycaster, parameters, seeds)
        except InUseError:
            continue
    return "none", None


def _open_grid(level: Level, boxes: list[Box] | None, cell_size: float, point_limit: int, validity: str,
               raycaster: EmbreeRaycaster, seconds: dict[str, float],
               progress: Progress | None) -> tuple[EvaluationGrid, int, int, int]:
    """The lattice of the bounds without the points that cannot hold a probe (`validity`: in solid or outside the map
    by the BSP, inside geometry by the rays, or either): (grid, lattice points, removed by the BSP, removed by the
    rays beyond those); BspError when none or too many remain."""
    clock = time.perf_counter()
    try:
        lattice = build_grid(boxes if boxes is not None else [auto_box(level)], cell_size,
                             point_limit=LATTICE_FACTOR * point_limit)
    except GridError as exc:
        raise GridError(f"{level.location}: before removing points in solid (the lattice may hold {LATTICE_FACTOR} x "
                        f"the point limit {point_limit:,}): {exc}") from exc
    seconds["grid"] = time.perf_counter() - clock

    clock = time.perf_counter()
    blocked = solid_mask(level, lattice, progress) if validity != "rays" else np.zeros(lattice.point_count, dtype=bool)
    removed = int(np.count_nonzero(blocked))
    seconds["solid"] = time.perf_counter() - clock
    clock = time.perf_counter()
    removed_invalid = 0
    if validity != "bsp":
        candidates = np.flatnonzero(~blocked)
        inside = invalid(back_face_fractions(lattice.positions[candidates], raycaster))
        blocked[candidates[inside]] = True
        removed_invalid = int(np.count_nonzero(inside))
    seconds["validity"] = time.perf_counter() - clock
    remaining = lattice.point_count - removed - removed_invalid
    if remaining == 0:
        raise BspError(f"{level.location}: all {lattice.point_count:,} evaluation points of the bounds are in solid, "
                       f"outside the map or inside geometry (validity {validity}): choose bounds inside the level "
                       f"(or --bounds auto)")
    if remaining > point_limit:
        suggestion = cell_size * (remaining / point_limit) ** (1.0 / 3.0)
        raise BspError(f"{level.location}: {remaining:,} evaluation points remain at cell size {cell_size:g} m "
                       f"(after removing {removed + removed_invalid:,} in solid or inside geometry), more than the point "
                       f"limit {point_limit:,}: "
                       f"use a cell of about {suggestion:.3g} m or a higher point limit")
    grid = lattice.subset(~blocked)
    return grid, lattice.point_count, removed, removed_invalid


def _sampled_sh(level: Level, light_grid: LightGrid | None, lighting: ProbeLighting | None, grid: EvaluationGrid,
                drop_unlit: bool, progress: Progress | None) -> tuple[EvaluationGrid, np.ndarray, int, int, np.ndarray]:
    """SH of the light grid (or baked from the rig) at every point, as the capture stores it (float32):
    (grid, sh, unlit points kept, unlit points removed, which points of `grid` were kept); drop_unlit removes the
    unlit ones."""
    step = "light grid" if lighting is None else "rig bake"
    step_progress = None if progress is None else (lambda done, total: progress(step, done, total))
    if lighting is None:
        sh, lit = light_grid.sh_at(grid.positions, step_progress)
    else:
        sh, lit = lighting.sh_at(level, grid.positions, step_progress)
    unlit = int(np.count_nonzero(~lit))
    removed_unlit = 0
    kept = np.ones(grid.point_count, dtype=bool)
    if drop_unlit and unlit:
        if unlit == grid.point_count:
            raise BspError(f"{level.location}: all {unlit:,} evaluation points left are unlit (every light grid "
                           f"corner is zero); import without dropping unlit points to keep them with black SH")
        grid, sh, removed_unlit, unlit, kept = grid.subset(lit), sh[lit], unlit, 0, lit
    return grid, sh.astype(np.float32), unlit, removed_unlit, kept  # features are computed from exactly these values


def _source_info(level: Level, bounds_label: str, rays: int, validity: str, removed: int, removed_invalid: int,
                 unlit: int, removed_unlit: int) -> dict[str, str | int | float | bool]:
    """The capture's `source` section (file-formats.md): where the points came from and what was removed. A capture
    without `validity` was imported before the option existed, i.e. with "bsp"."""
    source_info: dict[str, str | int | float | bool] = {"backend": BACKEND, "level": level.name}
    if level.pak is not None:
        source_info["pak"] = level.pak.name
    source_info.update({
        "bsp_sha256": level.sha256,
        "importer": f"lpnn {__version__}",
        "bounds": bounds_label,
        "patch_level": PATCH_LEVEL,
        "rays": rays,
        "validity": validity,
        "removed_solid": removed,
        "removed_invalid": removed_invalid,
        "unlit_points": unlit,
        "removed_unlit": removed_unlit,
    })
    return source_info


def solid_mask(level: Level, grid: EvaluationGrid, progress: Progress | None = None) -> np.ndarray:
    """(N,) bool: grid points in solid or outside the map."""
    step_progress = None if progress is None else (lambda done, total: progress("solid test", done, total))
    return SolidTester(level.bsp).solid_or_outside(unity_to_quake(grid.positions), step_progress)
