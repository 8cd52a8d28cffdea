#!/usr/bin/env bash
# OpenArena textures (albedo) and shader scripts (q3map_surfacelight, q3map_sun: lights.md §1, §3) for the light rig's
# forward model: ~250 MB of GPL game data from Debian (openarena-data: pak0.pk3, the base release's scripts the
# 0.8.1 maps were compiled with), installed only where the light rig needs them (never by make test or
# make demo), never committed (idempotent). Prints the folder of the paks.
source "$(dirname "$0")/lib.sh"
apt_install openarena-081-textures openarena-data openarena-085-data openarena-088-data
echo /usr/share/games/openarena
