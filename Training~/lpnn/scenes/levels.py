"""Where a level's bytes come from: a loose `.bsp`, a member of a `.pk3` (zip), or a map name.

LEVEL syntax (CLI and API alike):
  path/to/level.bsp           a file on disk
  path/to/pak.pk3:maps/x.bsp  a member of a pk3, read straight from the zip
  x                           maps/x.bsp in the default pak (env LPNN_OPENARENA_PAK, else the Debian path)
"""

from __future__ import annotations

import hashlib
import os
import zipfile
from dataclasses import dataclass
from pathlib import Path

from .bsp import Bsp, read_bsp
from .errors import BspError

PAK_ENV = "LPNN_OPENARENA_PAK"
DEBIAN_PAK = Path("/usr/share/games/openarena/baseoa/pak1-maps.pk3")
INSTALL_HINT = "run Tools~/install-openarena.sh (Debian package openarena-081-maps) or set LPNN_OPENARENA_PAK"
PAK_SEPARATOR = ".pk3:"
# The largest level we accept, loose or packed. Map packs are shared by strangers and a small .pk3 can
# inflate to gigabytes (a zip bomb), so a member is refused before it is read whole. The largest BSP in
# OpenArena's pak1-maps.pk3 is 7.6 MB (ctf_inyard); 256 MiB leaves a wide margin for real maps.
MAX_LEVEL_BYTES = 256 << 20
_READ_CHUNK = 1 << 20


@dataclass(frozen=True)
class Level:
    """A level read into memory: its bytes, where they came from, and the parsed BSP."""

    name: str  # map name, e.g. "oa_dm1"
    location: str  # for messages: "pak1-maps.pk3:maps/oa_dm1.bsp" or the .bsp path
    pak: Path | None
    data: bytes
    bsp: Bsp

    @property
    def sha256(self) -> str:
        return hashlib.sha256(self.data).hexdigest()


def default_pak() -> Path:
    """The pak named by LPNN_OPENARENA_PAK, else the Debian package's; not checked for existence."""
    configured = os.environ.get(PAK_ENV)
    return Path(configured) if configured else DEBIAN_PAK


def pak_members(pak: Path) -> list[str]:
    """The `maps/*.bsp` members of a pak, sorted."""
    with _open_pak(pak) as archive:
        return sorted(n for n in archive.namelist() if n.lower().startswith("maps/") and n.lower().endswith(".bsp"))


def load_level(spec: str) -> Level:
    """Read and parse the level that `spec` names (see the module docstring)."""
    if PAK_SEPARATOR in spec.lower():
        cut = spec.lower().rindex(PAK_SEPARATOR) + len(PAK_SEPARATOR) - 1
        return load_pak_member(Path(spec[:cut]), spec[cut + 1:])
    if spec.lower().endswith(".bsp") or os.sep in spec or "/" in spec:
        path = Path(spec)
        try:
            _check_level_size(str(path), path.stat().st_size, "is")
            data = path.read_bytes()
        except OSError as exc:
            raise BspError(f"{path}: cannot read the level: {exc.strerror or exc}") from exc
        return Level(name=path.stem, location=str(path), pak=None, data=data, bsp=read_bsp(data, str(path)))
    return load_pak_member(default_pak(), f"maps/{spec}.bsp")


def load_pak_member(pak: Path, member: str) -> Level:
    with _open_pak(pak) as archive:
        by_lower = {n.lower(): n for n in archive.namelist()}
        stored = by_lower.get(member.lower())
        if stored is None:
            available = sorted(Path(n).stem for n in archive.namelist()
                               if n.lower().startswith("maps/") and n.lower().endswith(".bsp"))
            raise BspError(f"{pak}: has no member {member!r}; its levels are: {', '.join(available) or 'none'}")
        location = f"{pak.name}:{stored}"
        _check_level_size(location, archive.getinfo(stored).file_size, "declares")
        try:
            data = _read_member_capped(archive, stored, location)
        except (zipfile.BadZipFile, OSError, EOFError) as exc:
            raise BspError(f"{location}: cannot be extracted: {exc}") from exc
    return Level(name=Path(stored).stem, location=location, pak=pak, data=data, bsp=read_bsp(data, location))


def _check_level_size(location: str, size: int, verb: str) -> None:
    if size > MAX_LEVEL_BYTES:
        raise BspError(f"{location}: {verb} {size:,} bytes, more than the {MAX_LEVEL_BYTES:,} bytes a level may have; "
                       "refused unread (a damaged or hostile file: use a level from a trusted source)")


def _read_member_capped(archive: zipfile.ZipFile, member: str, location: str) -> bytes:
    """The member's bytes, inflating no more than the cap whatever its header declares."""
    chunks: list[bytes] = []
    total = 0
    with archive.open(member) as stream:
        while chunk := stream.read(_READ_CHUNK):
            total += len(chunk)
            if total > MAX_LEVEL_BYTES:
                raise BspError(f"{location}: inflates to more than the {MAX_LEVEL_BYTES:,} bytes a level may have "
                               f"although its header declares {archive.getinfo(member).file_size:,}; refused "
                               "(a damaged or hostile file: use a level from a trusted source)")
            chunks.append(chunk)
    return b"".join(chunks)


def _open_pak(pak: Path) -> zipfile.ZipFile:
    if not pak.is_file():
        raise BspError(f"{pak}: no such pak; {INSTALL_HINT}")
    try:
        return zipfile.ZipFile(pak)
    except (zipfile.BadZipFile, OSError) as exc:
        raise BspError(f"{pak}: not a readable pk3 (zip) archive: {exc}") from exc
