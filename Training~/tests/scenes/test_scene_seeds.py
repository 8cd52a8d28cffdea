"""Seeds of the in-use walk in a Quake III level (scenes/seeds.py, in-use.md "Seeds")."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.scenes.coords import quake_to_unity
from lpnn.scenes.errors import BspError
from lpnn.scenes.seeds import is_seed, seed_positions


def test_spawns_teleporter_destinations_flags_and_items_are_seeds_and_nothing_else():
    for name in ("info_player_deathmatch", "info_player_start", "team_CTF_redspawn", "team_CTF_blueplayer",
                 "misc_teleporter_dest", "team_CTF_redflag", "weapon_railgun", "ammo_cells", "item_botroam",
                 "holdable_teleporter"):
        assert is_seed(name), name
    for name in ("light", "worldspawn", "target_position", "trigger_push", "func_door", "info_null", ""):
        assert not is_seed(name), name


def test_seed_origins_in_unity_metres_in_file_order():
    entities = [{"classname": "worldspawn"}, {"classname": "weapon_shotgun", "origin": "64 0 24"},
                {"classname": "light", "origin": "1 2 3"}, {"classname": "info_player_start", "origin": "0 128 40"}]
    seeds = seed_positions(entities, "test.bsp")
    assert np.allclose(seeds, quake_to_unity(np.array([[64.0, 0, 24], [0, 128, 40]])))
    assert seed_positions([{"classname": "light"}], "test.bsp").shape == (0, 3)
    with pytest.raises(BspError, match="entity 0 .*origin"):
        seed_positions([{"classname": "item_health", "origin": "1 2"}], "test.bsp")
