#!/usr/bin/env python3
"""Measures the probe-validity rule (lpnn/core/validity.py) against the BSP solid test on real OpenArena levels.

Every point of a level's lattice (before the importer removes anything) is put in one of three classes by the exact
BSP test (lpnn/scenes/solid.py): *open* (the air a player can reach; the importer keeps these), *in a solid brush*,
and *void* (outside the map: a leaf with cluster < 0 that is not inside a solid brush). The 26 feature rays are cast
with the level's oriented triangle normals, as far as RAY_LENGTH ("long") and as far as the features' 4 cells
("feature"), and the back-face rule is applied to each. Printed per level and ray length:

  open flagged    open points the rule calls invalid (would be lost as probe candidates: should be ~0)
  solid caught    in-solid points the rule calls invalid (the job the rule does in Unity)
  void caught     void points the rule calls invalid (outside the level; a Unity volume rarely reaches there)
  agreement       share of all points where the rule equals "solid or void" (the figure of the first measurement)

and, for the open points the long rule flags, the surfaces whose back faces their rays met (face kind and shader),
which is where the disagreement comes from. Measurement only.

    PYTHONPATH=Training~ python Tools~/experiments/validity-vs-solid.py PAK LEVEL [LEVEL ...] [--cell 1.0]
"""
from __future__ import annotations

import argparse
import collections
import time

import numpy as np

from lpnn.core.features import RAY_DIRECTIONS, RAY_LENGTH_CELLS
from lpnn.core.grid_builder import build_grid
from lpnn.core.validity import back_face_fraction, invalid
from lpnn.scenes.bsp import FACE_MESH, FACE_PATCH, FACE_POLYGON
from lpnn.scenes.coords import quake_to_unity, unity_to_quake
from lpnn.scenes.importer import auto_box
from lpnn.scenes.levels import load_level
from lpnn.scenes.solid import SolidTester
from lpnn.scenes.surfaces import ray_geometry

RAY_LENGTH = 1e4  # metres: longer than any level, so a ray that leaves the level misses
CHUNK = 20_000
ENCLOSED_HIT_SHARE = 0.9
KIND_NAMES = {FACE_POLYGON: "polygon", FACE_MESH: "mesh (model)", FACE_PATCH: "patch (curve)"}


def classes(level, lattice) -> tuple[np.ndarray, np.ndarray]:
    """(in solid brush, void) masks over the lattice points; open = neither."""
    tester = SolidTester(level.bsp)
    points = unity_to_quake(lattice.positions).astype(np.float64)
    in_brush = np.zeros(len(points), dtype=bool)
    void = np.zeros(len(points), dtype=bool)
    for start in range(0, len(points), CHUNK):
        chunk = points[start:start + CHUNK]
        pair_point, pair_leaf = tester.leaves_near(chunk)
        outside = np.bincount(pair_point, weights=tester.leaf_clusters[pair_leaf] < 0, minlength=len(chunk)) > 0
        brush = tester.in_solid_brush(chunk, pair_point, pair_leaf)
        in_brush[start:start + len(chunk)] = brush
        void[start:start + len(chunk)] = outside & ~brush
    return in_brush, void


def first_hits(scene, centre, face_normals, origins, directions, length):
    """Embree first hits: (triangle or -1, oriented unit normal)."""
    result = scene.run((origins - centre).astype(np.float32), directions.astype(np.float32),
                       dists=np.full(len(origins), np.float32(length)), output=1)
    triangle = result["primID"].astype(np.int64)
    hit = (triangle >= 0) & (result["tfar"] <= length)
    triangle = np.where(hit, triangle, -1)
    return triangle, np.where(hit[:, None], face_normals[np.maximum(triangle, 0)], 0.0)


def measure(pak: str, name: str, cell: float) -> None:
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    clock = time.perf_counter()
    level = load_level(f"{pak}:maps/{name}.bsp")
    lattice = build_grid([auto_box(level)], cell, point_limit=2_000_000)
    in_brush, void = classes(level, lattice)
    open_points = ~(in_brush | void)
    soup = ray_geometry(level.bsp)
    vertices = quake_to_unity(soup.vertices)
    corners = vertices[soup.triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    face_normals = normals / np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    centre = (vertices.min(axis=0) + vertices.max(axis=0)) / 2
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene=scene, vertices=(vertices - centre).astype(np.float32), indices=soup.triangles.astype(np.int32))

    count, rays = lattice.point_count, len(RAY_DIRECTIONS)
    lengths = {"long": RAY_LENGTH, "feature": RAY_LENGTH_CELLS * cell}
    rule = {key: np.zeros(count, dtype=bool) for key in lengths}
    culprits: collections.Counter[str] = collections.Counter()
    enclosed = 0  # flagged open points whose rays (nearly) all hit: inside a closed curve or model the BSP calls open
    for start in range(0, count, CHUNK):
        stop = min(count, start + CHUNK)
        origins = np.repeat(lattice.positions[start:stop].astype(np.float64), rays, axis=0)
        directions = np.tile(RAY_DIRECTIONS, (stop - start, 1))
        for key, length in lengths.items():
            triangle, hit_normals = first_hits(scene, centre, face_normals, origins, directions, length)
            hits = (triangle >= 0).reshape(-1, rays)
            fraction = back_face_fraction(RAY_DIRECTIONS, hits, hit_normals.reshape(-1, rays, 3))
            rule[key][start:stop] = invalid(fraction)
            if key == "long":
                flagged = np.flatnonzero(rule[key][start:stop] & open_points[start:stop])
                back = (np.einsum("rk,rk->r", hit_normals, directions) > 0).reshape(-1, rays)
                enclosed += int(np.count_nonzero(hits[flagged].mean(axis=1) >= ENCLOSED_HIT_SHARE))
                for point in flagged:
                    for t in triangle.reshape(-1, rays)[point][back[point]]:
                        face = soup.face_of_triangle[t]
                        kind = KIND_NAMES.get(int(level.bsp.faces["type"][face]), "other")
                        culprits[f"{kind}: {level.bsp.shader_name(int(level.bsp.faces['shader'][face]))}"] += 1
    total_open, total_brush, total_void = (int(m.sum()) for m in (open_points, in_brush, void))
    print(f"{name}: {count:,} points: open {total_open:,}, in solid brush {total_brush:,}, void {total_void:,} "
          f"({time.perf_counter() - clock:.0f} s)")
    for key, flags in rule.items():
        def share(mask: np.ndarray) -> str:
            part = int(np.count_nonzero(flags & mask))
            return f"{part:,} ({part / max(int(mask.sum()), 1):.2%})"
        print(f"  {key:8s} rays: open flagged {share(open_points)}, solid caught {share(in_brush)}, "
              f"void caught {share(void)}, agreement {np.mean(flags == ~open_points):.4f}")
    flagged_open = int(np.count_nonzero(rule["long"] & open_points))
    if flagged_open:
        print(f"  flagged open points with >= {ENCLOSED_HIT_SHARE:.0%} of rays hitting (enclosed): {enclosed:,} of {flagged_open:,}")
    back_hits = sum(culprits.values())
    if back_hits:
        print("  back faces met by flagged open points (long rays), by surface:")
        for culprit, hits in culprits.most_common(6):
            print(f"    {hits / back_hits:6.1%}  {culprit}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pak")
    parser.add_argument("levels", nargs="+")
    parser.add_argument("--cell", type=float, default=1.0)
    args = parser.parse_args()
    for name in args.levels:
        measure(args.pak, name, args.cell)


if __name__ == "__main__":
    main()
