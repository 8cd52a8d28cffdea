"""Where players go in a Quake III level: the seeds of the in-use rule's walk (Documentation~/in-use.md "Seeds").

Player spawns, teleporter destinations and items (weapons, ammo, health, armour, powerups, flags, and the invisible
`item_botroam` markers mappers place where bots should roam). Items also mark the ledges that jump pads and jumps
reach, which walking from the spawns cannot.
"""

from __future__ import annotations

import numpy as np

from .coords import quake_to_unity
from .entities import parse_vector

SPAWN_CLASSNAMES = frozenset({
    "info_player_deathmatch", "info_player_start", "team_ctf_redspawn", "team_ctf_bluespawn", "team_ctf_redplayer",
    "team_ctf_blueplayer", "misc_teleporter_dest",
    "team_ctf_redflag", "team_ctf_blueflag", "team_ctf_neutralflag",
})
ITEM_PREFIXES = ("weapon_", "ammo_", "item_", "holdable_")


def is_seed(classname: str) -> bool:
    name = classname.lower()
    return name in SPAWN_CLASSNAMES or name.startswith(ITEM_PREFIXES)


def seed_positions(entities: list[dict[str, str]], where: str) -> np.ndarray:
    """(S, 3) Unity metres: the origins of the seed entities, in file order; an entity without an origin is skipped
    (an item always has one; a malformed origin raises BspError naming `where` and the entity)."""
    origins = []
    for index, entity in enumerate(entities):
        if not is_seed(entity.get("classname", "")) or "origin" not in entity:
            continue
        origins.append(parse_vector(entity["origin"], 3, f"{where}: entity {index} ({entity['classname']}) origin"))
    if not origins:
        return np.zeros((0, 3))
    return quake_to_unity(np.asarray(origins, dtype=np.float64))


