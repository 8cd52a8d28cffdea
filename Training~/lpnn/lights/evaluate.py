"""The evaluation of Documentation~/benchmarks.md "The light rig": schemes x levels, with the real rig as yardstick.

    python -m lpnn.lights.evaluate --levels aggressor kaos oa_bases3 q3dm6ish --schemes adam lbfgs mixed --out DIR

Per level, the scene is built once; per scheme, a fresh fit from the same initial grid writes
DIR/LEVEL.SCHEME.json (the rig) and .curve.csv, and one PNG per level overlays the schemes' curves.
The yardstick row ("real rig") is the level's own light entities and worldspawn ambient through the
same forward model and the same light-grid comparison: what a perfect recovery of q3map2's point
lights would score with this model (levels that kept no light entities have no such row).
Prints one Markdown table row per (level, scheme) and writes DIR/summary.json.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from ..core.atomic import write_text_atomic
from ..scenes.levels import load_level
from .compare import compare_grid, compare_rigs, relight_stored_grid, stored_grid
from .curves import write_curve_csv, write_curve_png
from .emitters import emitter_bytes
from .pipeline import (add_surface_lights, fit_scene, fits_spots, fits_sun, level_emitters, load_scene, point_lights_of,
                       real_rig, rig_emitters, rig_of, shader_power, surface_pieces)
from .rig import Rig, entity_lights, write_rig
from .settings import (AMBIENTS, DEFAULT_AMBIENT, DEFAULT_GRID, DEFAULT_SCRIPT_LIGHTS, DEFAULT_START, PEAK_START, SCHEMES,
                       SCRIPT_LIGHTS, STARTS)
from .starts import DEFAULT_PEAKS, PeakSettings

HEADER = ("| level | scheme | target points | lights | objective | iterations | s / iteration | rays/s | "
          "matched within 1 m | distance real→rec. | grid error mean (p95) |\n|---|---|---|---|---|---|---|---|---|---|---|")


def evaluate_level(name: str, schemes: list[str], grid: tuple[int, int, int], out: Path,
                   surfaces: bool = False, spots: bool | None = None, start: str = DEFAULT_START,
                   peaks: PeakSettings = DEFAULT_PEAKS, yardstick: bool = True,
                   suns: bool | None = None, ambient: str = DEFAULT_AMBIENT,
                   scripts: str = DEFAULT_SCRIPT_LIGHTS) -> list[dict[str, Any]]:
    level = load_level(name)
    scene = load_scene(level)
    raycaster = scene.model.raycaster
    real = entity_lights(level.bsp.entities, level.name)
    stored = stored_grid(level.bsp)
    rows: list[dict[str, Any]] = []
    started = time.perf_counter()
    emitters = level_emitters(level, real) if real.rig.count else None
    if emitters is not None and yardstick:
        lights = point_lights_of(real)
        scene.model.fixed = emitter_bytes(scene.model.points, scene.model.normals, emitters, raycaster)
        objective = scene.model.objective(lights, scene.model.visibility(lights), with_gradient=False).value
        scene.model.fixed = np.zeros_like(scene.model.points)
        point_rig = Rig.from_quake(lights.positions, lights.colours, lights.intensities, ambient=lights.ambient)
        g = compare_grid(stored, relight_stored_grid(level.bsp, stored, point_rig, raycaster, scene.is_open, emitters))
        print(f"{level.name}: real rig {objective:.4f}, grid {g.mean_error:.3f} in {time.perf_counter() - started:.1f} s "
              f"({emitters.spots.count} spotlights, {emitters.areas.count} area lights of "
              f"{len(emitters.shaders)} shaders, {emitters.suns.count} suns)", flush=True)
        rows.append(dict(level=level.name, scheme="real rig", points=scene.target.point_count, lights=real.rig.count,
                         objective=objective, grid_mean=g.mean_error, grid_p95=g.p95_error,
                         grid_plain=g.plain_relative, ambient=real.rig.ambient.tolist()))
    if emitters is not None:  # the real rig as a rig file (lights.md §5): point lights, spots, surfaces, suns
        write_rig(out / f"{level.name}.real.json", real_rig(level, real, emitters))
    suffix = ""
    basis_seconds = 0.0
    if surfaces and schemes:
        add_surface_lights(scene)
        basis_seconds = scene.seconds["surface lights"]
        suffix = "+surfaces"
        print(f"{level.name}: {len(scene.surface_shaders)} surface-light shaders to recover in {basis_seconds:.1f} s",
              flush=True)
    spots = fits_spots(scene, spots, start, peaks) if schemes else False
    suffix += "+spots" if spots else ""
    suns = fits_sun(scene, suns) if schemes else False
    suffix += "+suns" if suns else ""
    suffix += "+peaks" if start == PEAK_START else ""
    curves = {}
    for scheme in schemes:
        rays_before, cast_before = scene.model.rays, raycaster.cast_seconds
        started = time.perf_counter()
        result = fit_scene(scene, grid, scheme, spots=spots, start=start, peaks=peaks, suns=suns, ambient=ambient,
                           scripts=scripts)
        seconds = time.perf_counter() - started
        rig = rig_of(scene, result, grid, scheme, start)
        write_rig(out / f"{level.name}.{scheme}{suffix}.json", rig)
        write_curve_csv(out / f"{level.name}.{scheme}{suffix}.curve.csv", result.curve)
        curves[scheme] = result.curve
        cast = raycaster.cast_seconds - cast_before
        own = rig_emitters(level, rig) if rig.surfaces or rig.suns else None
        row = dict(level=level.name, scheme=scheme + suffix, points=scene.target.point_count, lights=rig.count,
                   spotlights=int(rig.spot.sum()),
                   surface_lights=len(rig.surfaces), basis_seconds=basis_seconds,
                   initial_lights=result.initial_lights, objective=result.objective, iterations=result.iterations,
                   seconds=seconds, seconds_per_iteration=seconds / max(result.iterations, 1),
                   rays=scene.model.rays - rays_before,
                   rays_per_second=(scene.model.rays - rays_before) / cast if cast > 0 else 0.0,
                   ambient=rig.ambient.tolist(), suns=[dict(direction=sun.direction.tolist(), colour=sun.colour.tolist(),
                                                            intensity=sun.intensity) for sun in rig.suns])
        if emitters is not None and emitters.suns.count and rig.suns:
            row.update(sun_error(rig, emitters))
        if emitters is not None:
            c = compare_rigs(rig, real.rig, real_surfaces=surface_pieces(level.bsp, emitters),
                             shader_power=shader_power(level.bsp, own) if own is not None else {})
            row.update(matched=c.matched_share, real_to_recovered=c.real_to_recovered,
                       recovered_to_real=c.recovered_to_real, surface_share=c.surface_share,
                       surface_matched=c.surface_matched_share)
        g = compare_grid(stored, relight_stored_grid(level.bsp, stored, rig, raycaster, scene.is_open, own))
        row.update(grid_mean=g.mean_error, grid_p95=g.p95_error, grid_plain=g.plain_relative)
        rows.append(row)
        print(table_row(row), flush=True)
    if not curves:
        return rows
    write_curve_png(out / f"{level.name}{suffix}.curves.png", curves, f"{level.name}: objective by scheme "
                    f"({'x'.join(map(str, grid))} initial grid)")
    return rows


def sun_error(rig: Rig, emitters) -> dict[str, float]:
    """The recovered sun against the level's brightest real one: the angle between their directions (degrees) and
    the ratio of their intensities x largest colour component (photons at normal incidence, brightest channel)."""
    real = int(np.argmax(emitters.suns.photons * emitters.suns.colours.max(axis=1)))
    found = max(rig.suns, key=lambda sun: sun.intensity * float(np.max(sun.colour)))
    cosine = float(np.clip(found.quake_direction() @ emitters.suns.directions[real], -1.0, 1.0))
    real_power = float(emitters.suns.photons[real] * emitters.suns.colours[real].max())
    return dict(sun_angle=float(np.degrees(np.arccos(cosine))),
                sun_intensity_ratio=found.intensity * float(np.max(found.colour)) / real_power)


def table_row(row: dict[str, Any]) -> str:
    def fmt(key: str, pattern: str) -> str:
        return pattern.format(row[key]) if key in row else "–"

    return (f"| {row['level']} | {row['scheme']} | {row['points']:,} | {row['lights']} | {row['objective']:.4f} | "
            f"{fmt('iterations', '{}')} | {fmt('seconds_per_iteration', '{:.2f}')} | {fmt('rays_per_second', '{:,.0f}')} | "
            f"{fmt('matched', '{:.0%}')} | {fmt('real_to_recovered', '{:.2f} m')} | "
            f"{row['grid_mean']:.3f} ({row['grid_p95']:.3f}) |")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--levels", nargs="+", required=True, metavar="LEVEL")
    parser.add_argument("--schemes", nargs="*", default=["adam", "lbfgs", "mixed"], choices=sorted(SCHEMES))
    parser.add_argument("--grid", default="x".join(map(str, DEFAULT_GRID)), metavar="NxNxM")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR")
    parser.add_argument("--surfaces", action="store_true", help="the fits also recover surface lights (lights.md §4)")
    parser.add_argument("--spots", action=argparse.BooleanOptionalAction, default=None,
                        help="the fits also start spotlights (default: with the peak start, where a spotlight's disc "
                             "explains the floor's light better than a point light, lights.md §4; --no-spots: never)")
    parser.add_argument("--start", default=DEFAULT_START, choices=STARTS,
                        help="where the lights start: the grid's cells, or the peaks of the baked light (lights.md §4)")
    parser.add_argument("--suns", action=argparse.BooleanOptionalAction, default=None,
                        help="the fits also recover one sun (default: where the level has sky surfaces, lights.md §4)")
    parser.add_argument("--ambient", default=DEFAULT_AMBIENT, choices=AMBIENTS,
                        help="the level's ambient: held at the worldspawn's, or fitted (lights.md §4)")
    parser.add_argument("--scripts", default=DEFAULT_SCRIPT_LIGHTS, choices=SCRIPT_LIGHTS,
                        help="the surface lights' values and suns the level's shader scripts give: held at them, or "
                             "fitted (lights.md §4)")
    parser.add_argument("--no-yardstick", action="store_true",
                        help="skip the real rig's row (its objective and grid; the fits are still matched against it)")
    args = parser.parse_args(argv)
    grid = tuple(int(p) for p in args.grid.split("x"))
    args.out.mkdir(parents=True, exist_ok=True)
    print(HEADER, flush=True)
    rows = []
    for name in args.levels:
        level_rows = evaluate_level(name, args.schemes, grid, args.out, args.surfaces,  # type: ignore[arg-type]
                                    args.spots, args.start, yardstick=not args.no_yardstick, suns=args.suns,
                                    ambient=args.ambient, scripts=args.scripts)
        rows += level_rows
        for row in level_rows:
            if row["scheme"] == "real rig":
                print(table_row(row), flush=True)
    write_text_atomic(args.out / "summary.json", json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
