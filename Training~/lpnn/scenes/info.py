"""What `lpnn scene info` reports about a level: counts, bounds, light grid, ray geometry."""

from __future__ import annotations

from typing import Any

import numpy as np

from .bsp import FACE_TYPE_NAMES
from .coords import quake_to_unity
from .defaults import METRES_PER_UNIT
from .entities import light_entities, parse_vector
from .errors import BspError
from .levels import Level
from .surfaces import ray_geometry, select_ray_faces


def level_summary(level: Level) -> dict[str, Any]:
    """A JSON-ready description of the level (Quake units where named so, else Unity metres)."""
    bsp = level.bsp
    layout = bsp.light_grid_layout
    unity_corners = quake_to_unity(np.stack([bsp.world_mins, bsp.world_maxs]))
    selection = select_ray_faces(bsp)
    soup = ray_geometry(bsp)
    face_types = np.bincount(bsp.faces["type"], minlength=5)
    grid_corners = quake_to_unity(np.stack([layout.origin, layout.maxs]))
    lights = light_entities(bsp.entities)
    return {
        "level": level.name,
        "location": level.location,
        "bsp_sha256": level.sha256,
        "bytes": len(level.data),
        "world_bounds_quake": [bsp.world_mins.tolist(), bsp.world_maxs.tolist()],
        "world_bounds_unity_m": [unity_corners.min(axis=0).tolist(), unity_corners.max(axis=0).tolist()],
        "light_grid": {
            "present": bsp.light_grid is not None,
            "dims": [int(d) for d in layout.dims],
            "points": layout.point_count,
            "cell_quake": layout.cell_size.tolist(),
            "cell_m": (layout.cell_size * METRES_PER_UNIT).tolist(),
            "bounds_unity_m": [grid_corners.min(axis=0).tolist(), grid_corners.max(axis=0).tolist()],
        },
        "entities": len(bsp.entities),
        "light_entities": len(lights),
        "lights": [_light_description(entity) for entity in lights],
        "faces": {FACE_TYPE_NAMES[t]: int(face_types[t]) for t in sorted(FACE_TYPE_NAMES)},
        "ray_faces": int(np.count_nonzero(selection.is_geometry)),
        "ray_faces_excluded": selection.excluded,
        "ray_triangles": soup.triangle_count,
        "counts": {
            "shaders": len(bsp.shaders), "planes": len(bsp.planes), "nodes": len(bsp.nodes),
            "leafs": len(bsp.leafs), "brushes": len(bsp.brushes), "brush_sides": len(bsp.brush_sides),
            "models": len(bsp.models), "vertices": len(bsp.vertices), "mesh_verts": len(bsp.mesh_verts),
            "lightmaps": bsp.lightmap_count, "clusters": bsp.cluster_count,
        },
    }


def _light_description(entity: dict[str, str]) -> dict[str, Any]:
    """The entity's keys as stored, plus its origin in Unity metres when it parses."""
    described: dict[str, Any] = dict(entity)
    try:
        described["origin_unity_m"] = quake_to_unity(np.array(parse_vector(entity.get("origin", ""), 3, "origin"))).tolist()
    except BspError:
        pass  # no or malformed origin: the stored keys say what there is
    return described


def format_summary(summary: dict[str, Any]) -> str:
    grid = summary["light_grid"]

    def corners(pair: list[list[float]]) -> str:
        return " .. ".join("(" + ", ".join(f"{v:.4g}" for v in corner) + ")" for corner in pair)

    dims = "x".join(str(d) for d in grid["dims"])
    lines = [
        f"level          {summary['level']}  ({summary['location']}, {summary['bytes']:,} bytes)",
        f"sha256         {summary['bsp_sha256']}",
        f"world bounds   {corners(summary['world_bounds_unity_m'])} m (Unity)",
        f"               {corners(summary['world_bounds_quake'])} units (Quake)",
        f"light grid     {dims} = {grid['points']:,} points, cell "
        + " x ".join(f"{c:g}" for c in grid["cell_quake"]) + " units ("
        + " x ".join(f"{c:.4g}" for c in grid["cell_m"]) + " m)" + ("" if grid["present"] else "  [MISSING: no baked grid]"),
        f"               extent {corners(grid['bounds_unity_m'])} m (Unity)",
        f"entities       {summary['entities']:,} ({summary['light_entities']:,} lights)",
        "faces          " + ", ".join(f"{n:,} {k}" for k, n in summary["faces"].items()),
        f"ray geometry   {summary['ray_faces']:,} faces, {summary['ray_triangles']:,} triangles; excluded: "
        + ", ".join(f"{n:,} {k}" for k, n in summary["ray_faces_excluded"].items()),
        "counts         " + ", ".join(f"{n:,} {k}" for k, n in summary["counts"].items()),
    ]
    return "\n".join(lines)
