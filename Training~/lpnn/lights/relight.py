"""A rig as the importer's lighting (`lpnn scene import LEVEL --lighting rig:RIG.json`, lights.md §8):
the probe baker's SH at the capture's points instead of the light grid's, and what the capture's
`source` section records about it (file-formats.md, openarena.md)."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from ..scenes.errors import BspError
from ..scenes.levels import Level
from .bake import DEFAULT_BAKE, BakeScene, BakeSettings, bake_sh, not_bakeable
from .rig import Rig, RigError, read_rig

GRID_SOURCE = {"lighting": "grid"}
_SCENES: dict[str, BakeScene] = {}  # the last level's scene, by BSP hash: variants of one crop share it


@dataclass(frozen=True)
class RigLighting:
    rig: Rig
    name: str  # what the capture records: the rig file's name, or the variant's label
    sha256: str  # of the rig's file bytes, or of its canonical JSON for a variant made in memory
    settings: BakeSettings = DEFAULT_BAKE

    @classmethod
    def read(cls, path: Path, settings: BakeSettings = DEFAULT_BAKE) -> "RigLighting":
        rig = read_rig(path)
        reason = not_bakeable(rig)
        if reason is not None:
            raise RigError(f"{path}: the probe baker bakes a rig's point lights, suns and ambient, not its surface "
                           f"lights; this rig {reason}")
        return cls(rig=rig, name=Path(path).name, sha256=hashlib.sha256(Path(path).read_bytes()).hexdigest(),
                   settings=settings)

    @classmethod
    def of_rig(cls, rig: Rig, name: str, settings: BakeSettings = DEFAULT_BAKE) -> "RigLighting":
        """A rig made in memory (a relit variant): its hash is that of its canonical JSON."""
        canonical = json.dumps({"ambient": rig.ambient.tolist(), "positions": rig.positions.tolist(),
                                "colours": rig.colours.tolist(), "intensities": rig.intensities.tolist(),
                                **({"suns": [[*s.direction.tolist(), *s.colour.tolist(), s.intensity] for s in rig.suns]}
                                   if rig.suns else {})})
        return cls(rig=rig, name=name, sha256=hashlib.sha256(canonical.encode()).hexdigest(), settings=settings)

    def check_level(self, level: Level) -> None:
        if self.rig.bsp_sha256 and self.rig.bsp_sha256 != level.sha256:
            raise RigError(f"rig {self.name} was recovered from a level whose BSP hash is {self.rig.bsp_sha256[:12]}…, "
                           f"not {level.location} ({level.sha256[:12]}…): recover a rig for this level with "
                           f"lpnn scene lights {level.name} --out RIG.json")

    def sh_at(self, level: Level, unity_positions: np.ndarray,
              progress: Callable[[int, int], None] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """SH (N, 27) float64 baked from the rig at the positions, and (N,) bool "lit": some light
        (ambient, a visible light or a bounce) reaches the point."""
        self.check_level(level)
        scene = _SCENES.get(level.sha256)
        if scene is None:
            _SCENES.clear()
            scene = _SCENES[level.sha256] = BakeScene.from_level(level)
        sh = bake_sh(scene, self.rig, unity_positions, self.settings, progress).sh
        return sh, np.any(sh[:, 0::9] > 0, axis=1)

    def source_fields(self) -> dict[str, str | int | bool]:
        return {"lighting": "rig", "rig": self.name, "rig_sha256": self.sha256, "rig_lights": self.rig.count,
                "bake_bounce": self.settings.bounce, "bake_directions": self.settings.directions}


def parse_lighting(text: str) -> RigLighting | None:
    """`grid` -> None (the light grid); `rig:PATH` -> the rig read from PATH; anything else is refused."""
    if text == "grid":
        return None
    if text.startswith("rig:") and len(text) > 4:
        return RigLighting.read(Path(text[4:]))
    raise BspError(f"--lighting {text!r} must be 'grid' or 'rig:RIG.json' (a rig written by lpnn scene lights)")


def lighting_of(source: dict) -> str:
    """'grid' or 'rig': how a capture was lit; captures written before the `lighting` key are the grid's."""
    return str(source.get("lighting", "grid"))
