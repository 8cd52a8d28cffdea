#!/usr/bin/env python3
"""Measures the probe-validity rule (lpnn/core/validity.py) against the BSP solid test on real OpenArena levels.

For every point of a level's lattice (before the importer removes anything) it casts the 26 feature rays with the
level's oriented triangle normals, applies the back-face rule, and compares with the BSP test "in solid or outside the
map" (lpnn/scenes/solid.py). Prints per level: points, solid/outside, invalid by the rule, agreement, and the two kinds
of disagreement. Measurement only: the importer keeps using the BSP test (it is exact where a BSP exists).

    PYTHONPATH=Training~ python Tools~/validity-vs-solid.py PAK LEVEL [LEVEL ...] [--cell 1.0]
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from lpnn.core.features import RAY_DIRECTIONS
from lpnn.core.grid import build_grid
from lpnn.core.validity import back_face_fraction, invalid
from lpnn.scenes.coords import quake_to_unity
from lpnn.scenes.importer import auto_box, solid_mask
from lpnn.scenes.levels import load_level
from lpnn.scenes.raycast import EmbreeRaycaster
from lpnn.scenes.surfaces import ray_geometry

RAY_LENGTH = 1e4  # metres: longer than any level, so a ray that leaves the level misses


def measure(pak: str, name: str, cell: float) -> str:
    clock = time.perf_counter()
    level = load_level(f"{pak}:maps/{name}.bsp")
    lattice = build_grid([auto_box(level)], cell, point_limit=2_000_000)
    solid = solid_mask(level, lattice)
    soup = ray_geometry(level.bsp)
    raycaster = EmbreeRaycaster(quake_to_unity(soup.vertices), soup.triangles)
    count, rays = lattice.point_count, len(RAY_DIRECTIONS)
    fraction = np.empty(count)
    for start in range(0, count, 20_000):
        stop = min(count, start + 20_000)
        origins = np.repeat(lattice.positions[start:stop].astype(np.float64), rays, axis=0)
        directions = np.tile(RAY_DIRECTIONS, (stop - start, 1))
        t, normals = raycaster.cast(origins, directions, RAY_LENGTH)
        fraction[start:stop] = back_face_fraction(RAY_DIRECTIONS, np.isfinite(t).reshape(-1, rays), normals.reshape(-1, rays, 3))
    rule = invalid(fraction)
    open_points = int(np.count_nonzero(~solid))
    return (f"{name:14s} points {count:8,d}  solid/outside {int(solid.sum()):8,d}  invalid by rule {int(rule.sum()):8,d}  "
            f"agreement {np.mean(rule == solid):.4f}  open but invalid {int(np.sum(~solid & rule)):6,d} "
            f"({np.sum(~solid & rule) / max(open_points, 1):.2%} of {open_points:,} open)  solid/outside but valid "
            f"{int(np.sum(solid & ~rule)):8,d}  ({time.perf_counter() - clock:.1f} s)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pak")
    parser.add_argument("levels", nargs="+")
    parser.add_argument("--cell", type=float, default=1.0)
    args = parser.parse_args()
    for name in args.levels:
        print(measure(args.pak, name, args.cell), flush=True)


if __name__ == "__main__":
    main()
