"""Whole-pack check: import every level of a pak at one cell size and report those that fail."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ..core.capture import CaptureError
from ..core.capture_encoder import encode_capture
from ..core.capture_file import append_capture
from ..core.features import FeatureError
from ..core.grid import GridError
from .errors import BspError
from .defaults import DEFAULT_CELL, DEFAULT_POINT_LIMIT
from .importer import import_level
from .levels import load_pak_member, pak_members

# Problems with the data or the settings; anything else is reported as an importer bug.
EXPECTED_ERRORS = (BspError, GridError, FeatureError, CaptureError)


@dataclass
class LevelCheck:
    member: str
    ok: bool
    reason: str = ""
    points: int = 0
    removed_solid: int = 0
    unlit_points: int = 0
    removed_unlit: int = 0
    rays: int = 0
    seconds: float = 0.0
    output: Path | None = None


def check_pack(pak: Path, cell_size: float = DEFAULT_CELL, point_limit: int = DEFAULT_POINT_LIMIT,
               drop_unlit: bool = False, out_folder: Path | None = None, members: list[str] | None = None,
               on_level: Callable[[LevelCheck], None] | None = None) -> list[LevelCheck]:
    """Full import of each level (all members of `pak` unless `members` names some); never stops early.

    With `out_folder` each capture is appended there; otherwise it is encoded (and so validated)
    and dropped.
    """
    results: list[LevelCheck] = []
    for member in members if members is not None else pak_members(pak):
        clock = time.perf_counter()
        try:
            imported = import_level(load_pak_member(pak, member), cell_size, point_limit=point_limit,
                                    drop_unlit=drop_unlit)
            output = None
            if out_folder is not None:
                output = append_capture(out_folder, imported.capture, imported.level.name)
            else:
                encode_capture(imported.capture)
            check = LevelCheck(member=member, ok=True, points=imported.capture.point_count,
                               removed_solid=imported.removed_solid, unlit_points=imported.unlit_points,
                               removed_unlit=imported.removed_unlit,
                               rays=imported.rays, output=output)
        except EXPECTED_ERRORS as exc:
            check = LevelCheck(member=member, ok=False, reason=str(exc))
        except Exception as exc:  # noqa: BLE001 - the check reports every level, a crash included
            check = LevelCheck(member=member, ok=False, reason=f"importer bug: {type(exc).__name__}: {exc}")
        check.seconds = time.perf_counter() - clock
        results.append(check)
        if on_level is not None:
            on_level(check)
    return results
