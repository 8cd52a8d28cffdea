"""The LEVEL and --pak arguments of the commands that read OpenArena levels (`lpnn scene`, `scene lights`, `demo`,
`recipe`): the LEVEL help, the pak that must exist, and a level's problems as one-line user errors."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from ..errors import UserError

LEVEL_HELP = "a .bsp file, PAK.pk3:maps/NAME.bsp, or a map name in the default pak (LPNN_OPENARENA_PAK or the Debian path)"


def existing_pak(value: str | None) -> Path:
    """--pak, or the default pak ($LPNN_OPENARENA_PAK, else the Debian path); UserError if it is missing."""
    from ..scenes.levels import INSTALL_HINT, default_pak

    pak = Path(value) if value else default_pak()
    if not pak.is_file():
        raise UserError(f"{pak}: openarena maps pak not found; {INSTALL_HINT}")
    return pak


@contextmanager
def level_user_errors() -> Iterator[None]:
    """Level, grid and feature problems are the user's to fix: one line, no traceback."""
    from ..core.features import FeatureError
    from ..core.grid import GridError
    from ..scenes.errors import BspError

    try:
        yield
    except (BspError, GridError, FeatureError) as exc:
        raise UserError(str(exc)) from exc
