#!/usr/bin/env python3
"""Leak-aware variants of the default placement on real levels (benchmarks.md "Light leaks", leaks.md).

Per level (imported at the default cell, `lpnn scene import` defaults) and variant at tau: probes, probes added over
the default, mean irradiance error over all points and over the points within one cell of geometry (near_surface_mask),
the share of points that leak (leaks.md) and their mean error, and the time. Variants:

  default          refined_insertion(field, grid, tolerance=tau)  (leak-blind: the default until 2026-11-27, now
                   `lpnn place --leaks ignore`; the name is kept so benchmarks.md "Light leaks"'s commands still run)
  repair3          the default's probes + 3 rounds of leak_repaired (the naive repair: a probe per leaking tetrahedron)
  seed-repair      refined_insertion(..., leaks=raycaster, leak_weight=1): the repaired seed, refined as usual
  weight4          refined_insertion(..., leaks=raycaster, leak_weight=4, repair_rounds=0): weighting only
  aware2/4/8/16    refined_insertion(..., leaks=raycaster, leak_weight=2/4/8/16): repaired seed + weighted refinement
                   (aware8 is today's default, `lpnn place`'s `--leaks avoid`: leaks.md "A leak-aware default")
  aware8-r1/-r3    aware8 with 1 or 3 repair rounds instead of REPAIR_ROUNDS
  count-of-aware8  refined_insertion(field, grid, budget=K/N) with K = aware8's probes (the control: the count alone)

  PYTHONPATH=Training~ python Tools~/experiments/leak-variants.py LEVEL [LEVEL ...] [--pak PAK] [--tolerance 0.05]
                                                      [--variants default,aware4] [--in-use all|band|reachable]

Prints one JSON line per level x variant as it goes, then a markdown table. Levels are chosen on training/validation
levels only (lpnn.recipe.levels); held-out levels report (the role column says which).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import zipfile
from pathlib import Path
from typing import Callable

import numpy as np

from lpnn.core.capture import Capture
from lpnn.core.features import Raycaster
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.leak_aware import leak_repaired
from lpnn.quality.metric.leaks import leak_report, near_surface_mask
from lpnn.quality.metric.metric import ReferenceField, mean_placement_error
from lpnn.quality.placement.refined_insertion import refined_insertion
from lpnn.recipe.config import RecipeConfig
from lpnn.recipe.levels import split_levels

TOLERANCE = 0.05
NAIVE_REPAIR_ROUNDS = 3
UNIMPORTABLE = ("oa_ctf2",)  # ships without a light grid (benchmarks.md "Real levels as captures")

Placer = Callable[[ReferenceField, EvaluationGrid, Raycaster, float], np.ndarray]


def _aware(weight: float, rounds: int | None = None) -> Placer:
    def place(field: ReferenceField, grid: EvaluationGrid, raycaster: Raycaster, tau: float) -> np.ndarray:
        options = {} if rounds is None else {"repair_rounds": rounds}
        return refined_insertion(field, grid, tolerance=tau, leaks=raycaster, leak_weight=weight, **options).indices
    return place


def _plain_at_the_count_of(leak_aware: Placer) -> Placer:
    """The default's refinement with a budget of exactly the leak-aware answer's probes: are leaks gone by the count
    alone? (K = floor(f N + 0.5) with f = K / N gives K back.)"""
    def place(field: ReferenceField, grid: EvaluationGrid, raycaster: Raycaster, tau: float) -> np.ndarray:
        count = leak_aware(field, grid, raycaster, tau).shape[0]
        return refined_insertion(field, grid, budget=count / field.point_count).indices
    return place


VARIANTS: dict[str, Placer] = {
    "default": lambda field, grid, raycaster, tau: refined_insertion(field, grid, tolerance=tau).indices,
    "repair3": lambda field, grid, raycaster, tau: leak_repaired(
        field, refined_insertion(field, grid, tolerance=tau).indices, raycaster, NAIVE_REPAIR_ROUNDS),
    "seed-repair": _aware(1.0),
    "weight4": _aware(4.0, rounds=0),
    "aware2": _aware(2.0),
    "aware4": _aware(4.0),
    "aware8": _aware(8.0),
    "aware16": _aware(16.0),
    "aware8-r1": _aware(8.0, rounds=1),
    "aware8-r3": _aware(8.0, rounds=3),
    "count-of-aware8": _plain_at_the_count_of(_aware(8.0)),
}


def measure(level: str, role: str, capture: Capture, raycaster: Raycaster, tolerance: float,
            variants: list[str]) -> list[dict]:
    """One row per variant (the first variant is the baseline of `added`)."""
    field = ReferenceField.from_capture(capture)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    near = near_surface_mask(capture.feature_names, capture.features)
    rows: list[dict] = []
    for name in variants:
        start = time.perf_counter()
        probes = VARIANTS[name](field, grid, raycaster, tolerance)
        seconds = time.perf_counter() - start
        report = leak_report(field, probes, raycaster, near_surface=near)
        baseline = rows[0]["probes"] if rows else int(probes.shape[0])
        rows.append({"level": level, "role": role, "points": capture.point_count, "variant": name,
                     "probes": int(probes.shape[0]),
                     "added": (int(probes.shape[0]) - baseline) / baseline if baseline else 0.0,
                     "mean": mean_placement_error(field, probes), "near": report.near_surface_error,
                     "leaking": report.leaking_share, "leaking_error": report.leaking_error, "seconds": seconds})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def table(rows: list[dict]) -> str:
    lines = ["| level (role) | points | variant | probes | added | mean error | near surfaces | leaking | their error "
             "| time |", "|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        lines.append(f"| {row['level']} ({row['role']}) | {row['points']:,} | {row['variant']} | {row['probes']:,} "
                     f"| {row['added']:+.0%} | {row['mean']:.4f} | {row['near']:.4f} | {row['leaking']:.1%} "
                     f"| {row['leaking_error']:.3f} | {row['seconds']:.1f} s |")
    return "\n".join(lines)


def level_roles(pak: Path) -> dict[str, str]:
    """train / validation / held_out of every importable level of the pack, by the recipe's rule."""
    with zipfile.ZipFile(pak) as archive:
        names = sorted(n[len("maps/"):-len(".bsp")] for n in archive.namelist()
                       if n.startswith("maps/") and n.endswith(".bsp"))
    split = split_levels([n for n in names if n not in UNIMPORTABLE], RecipeConfig())
    return {name: split.role(name) for name in names}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="+")
    parser.add_argument("--pak", type=Path, default=None, help="openarena-081-maps pak (default: the installed one)")
    parser.add_argument("--tolerance", type=float, default=TOLERANCE)
    parser.add_argument("--variants", default=",".join(VARIANTS))
    parser.add_argument("--in-use", default="all", choices=("all", "band", "reachable"),
                        help="the points imported and placed on (in-use.md; default all, as §12's first table)")
    args = parser.parse_args(argv)
    variants = [v for v in args.variants.split(",") if v]
    unknown = [v for v in variants if v not in VARIANTS]
    if unknown or not variants:
        raise SystemExit(f"unknown variant(s) {unknown}: use some of {', '.join(VARIANTS)}")
    from lpnn.scenes.capture_geometry import capture_raycaster
    from lpnn.scenes.importer import import_level
    from lpnn.scenes.levels import default_pak, load_pak_member
    pak = args.pak if args.pak is not None else default_pak()
    roles = level_roles(pak)
    rows: list[dict] = []
    for level in args.levels:
        capture = import_level(load_pak_member(pak, f"maps/{level}.bsp"), timings_in_source=False,
                               in_use=args.in_use).capture
        raycaster, why = capture_raycaster(capture, pak)
        if raycaster is None:
            raise SystemExit(f"{level}: no ray geometry ({why})")
        rows += measure(level, roles.get(level, "unknown"), capture, raycaster, args.tolerance, variants)
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
