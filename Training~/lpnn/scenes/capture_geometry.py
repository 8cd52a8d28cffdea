"""The geometry a capture was imported from, for checks that cast rays after the import (leaks.md): an OpenArena
capture records its level, pak and the level's SHA-256 (openarena.md "source"); the level is read again from the
pak and its ray geometry (surfaces.py) built as the importer built it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.capture import Capture
from .coords import quake_to_unity
from .importer import BACKEND
from .levels import default_pak, load_pak_member
from .raycast import EmbreeRaycaster
from .surfaces import ray_geometry


def capture_triangles(capture: Capture, pak: Path | None = None) -> tuple[tuple[np.ndarray, np.ndarray] | None, str]:
    """((vertices (V, 3) float64 in Unity metres, triangles (T, 3) int64), "") — the triangles rays hit, in the capture's
    frame — for a capture of an OpenArena level found in `pak` (default: the default pak's folder holds the recorded
    pak) with the recorded SHA-256; otherwise (None, why not): a Unity export carries no geometry."""
    source = capture.source
    if source.get("backend") != BACKEND or "level" not in source:
        return None, "the capture records no level geometry (not an OpenArena import)"
    recorded = source.get("pak")
    where = pak if pak is not None else (default_pak().parent / recorded if recorded else default_pak())
    if not where.is_file():
        return None, f"its pak {where} is not on this machine"
    level = load_pak_member(where, f"maps/{source['level']}.bsp")
    if source.get("bsp_sha256") not in (None, level.sha256):
        return None, f"{level.location} is not the level the capture was imported from (its SHA-256 differs)"
    soup = ray_geometry(level.bsp)
    return (quake_to_unity(soup.vertices), soup.triangles), ""


def capture_raycaster(capture: Capture, pak: Path | None = None) -> tuple[EmbreeRaycaster | None, str]:
    """(raycaster, "") over capture_triangles(capture, pak), or (None, why not)."""
    triangles, why = capture_triangles(capture, pak)
    return (None, why) if triangles is None else (EmbreeRaycaster(*triangles), "")
