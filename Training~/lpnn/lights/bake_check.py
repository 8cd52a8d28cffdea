"""The validation of the probe baker (Documentation~/benchmarks.md "The light rig"): rig-baked SH against the stored
light grid at the grid's own valid nodes.

    python -m lpnn.lights.bake_check (--rigs DIR | --entities) --levels oa_bases3 oa_dm2 [--directions K] [--out F.json]

DIR/LEVEL.json is the level's rig (`lpnn scene lights LEVEL --out DIR/LEVEL.json`); --entities uses the
level's own light entities and worldspawn ambient (levels that kept them, lights.md §1). Both lightings are
compared as SH (the stored grid through the importer's conversion, lightgrid.py), evaluated in the 14
directions D14, with quality.md's relative irradiance error (mean and 95th percentile over nodes, scene
scale from the stored grid) and the plain relative error sum |baked - stored| / sum |stored|; also the
ratio of the mean DC luminances (baked / stored: the overall scale). Variants: direct + ambient only,
and direct + ambient + one bounce (the importer's default). For context, the [lights] yardstick: the same
rig through q3map2's grid rule (compare.relight_grid, lights.md §6) against the same stored grid.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..core.atomic import write_text_atomic
from ..core.features import D14, scene_scale
from ..core.sh import ambient_plus_directed, evaluate, luminance
from ..quality.metric.metric import irradiance_error
from ..scenes.coords import quake_to_unity, unity_to_quake
from ..scenes.levels import load_level
from ..scenes.lightgrid import LINEAR_PER_BYTE
from .bake import GATHER_DIRECTIONS, BakeScene, BakeSettings, bake_sh
from .compare import compare_grid, relight_grid, stored_grid
from .rig import entity_lights, read_rig


@dataclass(frozen=True)
class ShComparison:
    points: int
    mean_error: float
    p95_error: float
    plain_relative: float
    dc_ratio: float  # mean DC luminance, compared / reference


def compare_sh(compared: np.ndarray, reference: np.ndarray) -> ShComparison:
    """Relative irradiance error (quality.md) of SH `compared` against `reference`, both (M, 27)."""
    if len(reference) == 0:
        raise ValueError("no points to compare (the stored light grid has no valid node)")
    shaded, expected = (evaluate(s, D14).reshape(len(s), -1) for s in (compared, reference))
    errors = irradiance_error(shaded, expected, scene_scale(reference))
    total = float(np.abs(expected).sum())
    dc = [float(luminance(s.reshape(-1, 3, 9)[:, :, 0]).mean()) for s in (compared, reference)]
    return ShComparison(points=len(errors), mean_error=float(errors.mean()), p95_error=float(np.percentile(errors, 95)),
                        plain_relative=float(np.abs(shaded - expected).sum() / total) if total > 0 else float("nan"),
                        dc_ratio=dc[0] / dc[1] if dc[1] > 0 else float("nan"))


def check_level(name: str, rig_path: Path | None, directions: int) -> dict[str, Any]:
    """rig_path None: the level's own light entities and worldspawn ambient (the yardstick rig)."""
    level = load_level(name)
    rig = read_rig(rig_path) if rig_path is not None else entity_lights(level.bsp.entities, level.name).rig
    if rig.count == 0:
        raise ValueError(f"{level.name} kept no point-light entity: check it with a recovered rig (--rigs)")
    started = time.perf_counter()
    scene = BakeScene.from_level(level)
    scene_seconds = time.perf_counter() - started
    stored = stored_grid(level.bsp)
    reference = LINEAR_PER_BYTE * ambient_plus_directed(stored.ambient, stored.directed,
                                                        quake_to_unity(stored.direction, scale=1.0))
    nodes = quake_to_unity(stored.positions)
    row: dict[str, Any] = {"level": level.name, "rig": str(rig_path or "light entities"), "lights": rig.count, "nodes": len(nodes),
                           "scene_seconds": round(scene_seconds, 1), "directions": directions}
    yardstick = compare_grid(stored, relight_grid(stored.positions, rig, scene.occluders))
    row["grid_rule"] = {"mean": yardstick.mean_error, "p95": yardstick.p95_error, "plain": yardstick.plain_relative}
    for label, settings in (("direct", BakeSettings(bounce=False)), ("bounce", BakeSettings(directions=directions))):
        started = time.perf_counter()
        baked = bake_sh(scene, rig, nodes, settings)
        result = compare_sh(baked.sh, reference)
        row[label] = {"mean": result.mean_error, "p95": result.p95_error, "plain": result.plain_relative,
                      "dc_ratio": result.dc_ratio, "seconds": round(time.perf_counter() - started, 1),
                      "rays": baked.rays}
    return row


CONTINUITY_HALF_SIDE = 4.0  # metres: the region baked at both cells, around a valid light-grid node
COARSE_CELL, FINE_CELL = 1.6256, 0.4064  # 64 and 16 Quake units: every coarse point is a fine point


def check_continuity(name: str, rig_path: Path) -> dict[str, Any]:
    """The same region imported at COARSE_CELL and FINE_CELL with the rig: SH at the points both share
    (max and mean relative difference, |a - b| summed over 27 values / (|a| + |b|) summed), and how far
    the fine points lie from the coarse lattice's trilinear interpolation (what the fine cell adds)."""
    from ..core.grid_box import Box
    from ..scenes.importer import import_level
    from .relight import RigLighting

    level = load_level(name)
    lighting = RigLighting.read(rig_path)
    stored = stored_grid(level.bsp)
    centre = quake_to_unity(stored.positions[len(stored.positions) // 2][None])[0]
    box = Box.axis_aligned(centre - CONTINUITY_HALF_SIDE, centre + CONTINUITY_HALF_SIDE)
    coarse, fine = (import_level(level, cell, boxes=[box], lighting=lighting, timings_in_source=False).capture
                    for cell in (COARSE_CELL, FINE_CELL))
    key = np.rint(unity_to_quake(fine.positions.astype(np.float64))).astype(np.int64)
    index = {tuple(k): i for i, k in enumerate(key)}
    pairs = [(i, index.get(tuple(k))) for i, k in
             enumerate(np.rint(unity_to_quake(coarse.positions.astype(np.float64))).astype(np.int64))]
    pairs = [(a, b) for a, b in pairs if b is not None]
    a = coarse.sh[[p[0] for p in pairs]].astype(np.float64)
    b = fine.sh[[p[1] for p in pairs]].astype(np.float64)
    magnitude = (np.abs(a) + np.abs(b)).sum(axis=1)
    relative = np.abs(a - b).sum(axis=1) / np.where(magnitude > 0, magnitude, 1.0)
    return {"level": level.name, "centre": [round(float(v), 3) for v in centre], "coarse_points": coarse.point_count,
            "fine_points": fine.point_count, "shared": len(pairs),
            "shared_max_relative": float(relative.max(initial=0.0)),
            "shared_mean_relative": float(relative.mean()) if len(pairs) else float("nan")}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    rigs = parser.add_mutually_exclusive_group(required=True)
    rigs.add_argument("--rigs", type=Path, help="folder of LEVEL.json rigs")
    rigs.add_argument("--entities", action="store_true", help="the levels' own light entities as the rig")
    parser.add_argument("--levels", nargs="+", required=True)
    parser.add_argument("--directions", type=int, default=GATHER_DIRECTIONS)
    parser.add_argument("--out", type=Path, help="write the rows as JSON here")
    parser.add_argument("--continuity", action="store_true",
                        help=f"instead: import a {2 * CONTINUITY_HALF_SIDE:g} m cube at {COARSE_CELL} and {FINE_CELL} m "
                             f"cells with the rig and compare the shared points")
    args = parser.parse_args(argv)
    if args.continuity:
        if args.rigs is None:
            parser.error("--continuity needs --rigs")
        rows = [check_continuity(name, args.rigs / f"{name}.json") for name in args.levels]
        for row in rows:
            print(json.dumps(row))
        if args.out:
            write_text_atomic(args.out, json.dumps(rows, indent=1) + "\n")
        return 0
    rows = []
    print("| level | lights | nodes | direct+ambient: mean (p95), plain, DC ratio | + bounce: mean (p95), plain, "
          "DC ratio | q3map2 grid rule: mean (p95), plain | bake s (bounce) |\n|---|---|---|---|---|---|---|")
    for name in args.levels:
        row = check_level(name, None if args.entities else args.rigs / f"{name}.json", args.directions)
        rows.append(row)
        cells = [f"{row[k]['mean']:.3f} ({row[k]['p95']:.3f}), {row[k]['plain']:.2f}, {row[k]['dc_ratio']:.2f}"
                 for k in ("direct", "bounce")]
        print(f"| {row['level']} | {row['lights']} | {row['nodes']:,} | {cells[0]} | {cells[1]} | "
              f"{row['grid_rule']['mean']:.3f} ({row['grid_rule']['p95']:.3f}), {row['grid_rule']['plain']:.2f} | "
              f"{row['bounce']['seconds']:.0f} |", flush=True)
    if args.out:
        write_text_atomic(args.out, json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
