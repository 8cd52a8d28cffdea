#!/usr/bin/env bash
# OpenArena levels (GPL game data) from Debian: installed, never committed (idempotent).
# Prints the path of the map pack.
source "$(dirname "$0")/lib.sh"
apt_install openarena-081-maps
# textures (albedo) and the shader scripts (q3map_surfacelight, lights.md §1, §3) of the same paks
apt_install openarena-081-textures openarena-085-data openarena-088-data
pak=/usr/share/games/openarena/baseoa/pak1-maps.pk3
[ -f "$pak" ] || die "openarena-081-maps is installed but $pak is missing"
echo "$pak"
