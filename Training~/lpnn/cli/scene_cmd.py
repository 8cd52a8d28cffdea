"""`lpnn scene ...`: OpenArena (Quake III BSP) levels as light-probe captures (Documentation~/openarena.md).

  lpnn scene info LEVEL
  lpnn scene import LEVEL [--cell M] [--lighting grid|rig:RIG.json] [--bounds auto | x0,y0,z0,x1,y1,z1 ...]
                    (--out FILE | --append-to DIR)
  lpnn scene check-pack [PAK]
  lpnn scene lights LEVEL [--grid NxNxM] [--scheme NAME] (--out RIG.json | --compare RIG.json)

LEVEL is a .bsp path, `pak.pk3:maps/x.bsp`, or a map name looked up in the default pak.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

from ..core import in_use_defaults as in_use
from ..scenes.defaults import DEFAULT_CELL, DEFAULT_POINT_LIMIT
from ..errors import UserError
from .level_args import LEVEL_HELP, level_user_errors

def register(subparsers: argparse._SubParsersAction) -> None:
    scene = subparsers.add_parser("scene", help="OpenArena / Quake III levels as captures (no Unity needed)",
                                  description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    actions = scene.add_subparsers(dest="scene_command", metavar="ACTION", required=True)

    info = actions.add_parser("info", help="counts, bounds, light grid and ray geometry of a level")
    info.add_argument("level", metavar="LEVEL", help=LEVEL_HELP)
    info.add_argument("--json", action="store_true", help="print JSON instead of text")
    info.set_defaults(handler=_info)

    imp = actions.add_parser("import", help="import a level as a capture (grid, SH from the light grid, features)")
    imp.add_argument("level", metavar="LEVEL", help=LEVEL_HELP)
    _add_import_options(imp)
    imp.add_argument("--bounds", nargs="+", default=["auto"], metavar="BOX",
                     help="'auto' (the light grid's extent) or one or more boxes x0,y0,z0,x1,y1,z1 in Unity metres")
    where = imp.add_mutually_exclusive_group(required=True)
    where.add_argument("--out", type=Path, metavar="CAPTURE", help="write (or replace) this .lpnncap file")
    where.add_argument("--append-to", type=Path, metavar="FOLDER",
                       help="add the capture to this dataset folder as LEVEL.lpnncap (-2, -3... if taken)")
    imp.add_argument("--validity", choices=("bsp", "rays", "both"), default="bsp",
                     help="which points cannot hold a probe: 'bsp' (default) in solid or outside the map by the exact "
                          "BSP test; 'rays' by Unity's probe-validity rule (more than a quarter of 26 rays hit back "
                          "faces); 'both' either (Documentation~/openarena.md)")
    imp.add_argument("--lighting", default="grid", metavar="grid|rig:RIG.json",
                     help="the SH of the capture: 'grid' samples the level's light grid (default); 'rig:RIG.json' bakes "
                          "them from a rig of lpnn scene lights (direct light, shadows and one bounce, lights.md §8)")
    imp.add_argument("--in-use", choices=in_use.RULES, default=None,
                     help="which points count (Documentation~/in-use.md): 'reachable' (default; 'band' on a level "
                          "without spawns or items) the points within the band above walkable floors that a player "
                          "walks to from the level's spawns and items; "
                          "'band' every point within the band above a walkable floor; 'all' every point (for objects "
                          "that fly; the capture then marks the reachable points so reports show the error there)")
    imp.add_argument("--band-height", type=float, default=in_use.BAND_HEIGHT, metavar="METRES",
                     help=f"height above a walkable floor in use (default {in_use.BAND_HEIGHT:g})")
    imp.add_argument("--slope-limit", type=float, default=in_use.SLOPE_LIMIT_DEGREES, metavar="DEGREES",
                     help=f"steepest walkable floor (default {in_use.SLOPE_LIMIT_DEGREES:g})")
    imp.add_argument("--step-height", type=float, default=in_use.STEP_HEIGHT, metavar="METRES",
                     help=f"highest step a player climbs (default {in_use.STEP_HEIGHT:g})")
    imp.add_argument("--reproducible", action="store_true",
                     help="leave the wall-clock feature_seconds out of the capture: same level + cell = same bytes")
    imp.add_argument("--quiet", action="store_true", help="no progress bars")
    imp.set_defaults(handler=_import)

    check = actions.add_parser("check-pack", help="import every level of a pak and report those that fail")
    check.add_argument("pak", nargs="?", type=Path, metavar="PAK", help="a .pk3 (default: the default pak)")
    _add_import_options(check)
    check.add_argument("--levels", nargs="+", metavar="NAME", help="only these map names")
    check.add_argument("--out", type=Path, metavar="FOLDER", help="also append every capture to this dataset folder")
    check.set_defaults(handler=_check_pack)

    from .scene_lights import register as register_lights  # issue 15: the light rig from baked lighting

    register_lights(actions)


def _add_import_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--cell", type=float, default=DEFAULT_CELL, metavar="METRES",
                        help=f"cell size in metres (default {DEFAULT_CELL:g} = 64 Quake units, the light grid's xy spacing)")
    parser.add_argument("--point-limit", type=int, default=DEFAULT_POINT_LIMIT, metavar="N",
                        help=f"most evaluation points kept after removing those in solid (default {DEFAULT_POINT_LIMIT:,})")
    parser.add_argument("--drop-unlit", action="store_true",
                        help="also remove points where the light grid has no light (all 8 corners zero; "
                             "default: keep them with black SH)")


# ---------------------------------------------------------------------------------------- handlers

def _info(args: argparse.Namespace) -> None:
    import json

    from ..scenes.info import format_summary, level_summary
    from ..scenes.levels import load_level

    with level_user_errors():
        summary = level_summary(load_level(args.level))
    print(json.dumps(summary, indent=2) if args.json else format_summary(summary))


def _import(args: argparse.Namespace) -> None:
    from ..core.capture_file import append_capture, write_capture
    from ..core.in_use import InUseError, InUseParameters
    from ..lights.relight import parse_lighting
    from ..scenes.levels import load_level
    from ..scenes.importer import import_level

    _check_settings(args.cell, args.point_limit)
    boxes, label = _parse_bounds(args.bounds)
    parameters = InUseParameters(band_height=args.band_height, slope_limit_degrees=args.slope_limit,
                                 step_height=args.step_height)
    with level_user_errors(), _progress_bars(enabled=not args.quiet) as progress:
        level = load_level(args.level)

        def imported(rule: str) -> Any:
            return import_level(level, args.cell, boxes=boxes, point_limit=args.point_limit, bounds_label=label,
                                drop_unlit=args.drop_unlit, timings_in_source=not args.reproducible,
                                progress=progress, validity=args.validity, lighting=parse_lighting(args.lighting),
                                in_use=rule, in_use_parameters=parameters)

        if args.in_use is not None:
            result = imported(args.in_use)
        else:  # the default: reachable where the level's spawns and items lead somewhere, else the band
            try:
                args.in_use, result = in_use.DEFAULT_RULE, imported(in_use.DEFAULT_RULE)
            except InUseError as exc:
                print(f"{exc}; the points in use are the band's instead (--in-use band)")
                args.in_use, result = "band", imported("band")
    clock = time.perf_counter()
    if args.out is not None:
        path = write_capture(args.out, result.capture)
    else:
        path = append_capture(args.append_to, result.capture, result.level.name)
    result.seconds["write"] = time.perf_counter() - clock

    seconds = result.seconds
    total = sum(v for k, v in seconds.items() if k != "rays")  # rays are part of features
    ray_rate = result.rays / seconds["rays"] if seconds["rays"] > 0 else float("inf")
    print(f"{path}: {result.capture.point_count:,} points of {result.lattice_points:,} "
          f"({result.removed_solid:,} in solid or outside removed, "
          + (f"{result.removed_invalid:,} inside geometry by the rays removed, " if args.validity != "bsp" else "")
          + f"{result.removed_unlit:,} unlit removed, "
          f"{result.unlit_points:,} unlit kept), cell {args.cell:g} m, "
          f"{result.triangles:,} ray triangles")
    section = result.capture.extra_sections.get("in_use")
    in_use_summary = (f"{result.capture.point_count:,} of {result.points_before_in_use:,} points in use ({args.in_use})"
              if args.in_use != "all" else
              f"all {result.capture.point_count:,} points kept; "
              + (f"{int(section.sum()):,} in use ({result.capture.source['in_use_report_rule']}, reported)"
                 if section is not None else "no walkable floor under any point: in use n/a"))
    print(f"in use: {in_use_summary}; {result.capture.source['in_use_seeds']} seeds (spawns and items)")
    print("seconds: " + ", ".join(f"{k} {v:.2f}" for k, v in seconds.items()) + f"; total {total:.2f}")
    print(f"rays: {result.rays:,} ({ray_rate:,.0f} rays/s inside the raycaster)")


def _check_pack(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from ..scenes.levels import default_pak, pak_members
    from ..scenes.pack import check_pack

    _check_settings(args.cell, args.point_limit)
    pak = args.pak if args.pak is not None else default_pak()
    with level_user_errors():
        members = pak_members(pak)
        if args.levels:
            wanted = {f"maps/{name.lower()}.bsp" for name in args.levels}
            missing = sorted(wanted - {m.lower() for m in members})
            if missing:
                raise UserError(f"{pak}: no such levels: {', '.join(missing)}")
            members = [m for m in members if m.lower() in wanted]
    bar = tqdm(total=len(members), desc="levels", unit="level", file=sys.stderr)

    def report(check: Any) -> None:
        bar.update(1)
        status = (f"ok   {check.points:>9,} points  {check.removed_solid:>9,} in solid  "
                  f"{check.removed_unlit + check.unlit_points:>7,} unlit  "
                  f"{check.rays:>11,} rays"
                  if check.ok else f"FAIL {check.reason}")
        tqdm.write(f"{Path(check.member).stem:<18} {check.seconds:7.1f} s  {status}")

    results = check_pack(pak, args.cell, args.point_limit, drop_unlit=args.drop_unlit, out_folder=args.out,
                         members=members, on_level=report)
    bar.close()
    failed = [r for r in results if not r.ok]
    print(f"{pak}: {len(results) - len(failed)} of {len(results)} levels imported at cell {args.cell:g} m, "
          f"{len(failed)} failed" + ("".join(f"\n  {Path(r.member).stem}: {r.reason}" for r in failed)))
    return 1 if failed else 0


# ----------------------------------------------------------------------------------------- helpers

def _check_settings(cell: float, point_limit: int) -> None:
    if not (math.isfinite(cell) and cell > 0):
        raise UserError(f"--cell {cell!r} must be a finite number of metres > 0 (default {DEFAULT_CELL:g})")
    if point_limit < 1:
        raise UserError(f"--point-limit {point_limit} must be at least 1")


def _parse_bounds(values: list[str]) -> tuple[list[Any] | None, str]:
    """(boxes, label): boxes None for 'auto'."""
    from ..core.grid import GridError
    from ..core.grid_box import Box

    if values == ["auto"]:
        return None, "auto"
    if "auto" in values:
        raise UserError("--bounds: 'auto' cannot be combined with boxes; give either 'auto' or boxes")
    boxes = []
    for text in values:
        parts = text.split(",")
        try:
            numbers = [float(p) for p in parts]
        except ValueError:
            numbers = []
        if len(numbers) != 6 or not all(math.isfinite(v) for v in numbers):
            raise UserError(f"--bounds: {text!r} is not six finite numbers x0,y0,z0,x1,y1,z1 (Unity metres)")
        try:
            boxes.append(Box.axis_aligned(numbers[:3], numbers[3:]))
        except GridError as exc:
            raise UserError(f"--bounds {text!r}: {exc}") from exc
    return boxes, " ".join(values)


@contextmanager
def _progress_bars(enabled: bool) -> Iterator[Any]:
    """A progress(step, done, total) callback drawing one tqdm bar per step on stderr."""
    from tqdm import tqdm

    bars: dict[str, Any] = {}

    def progress(step: str, done: int, total: int) -> None:
        bar = bars.get(step)
        if bar is None:
            bar = bars[step] = tqdm(total=total, desc=step, unit="pt", file=sys.stderr, disable=not enabled)
        bar.update(done - bar.n)
        if done >= total:
            bar.close()  # one finished line per step

    try:
        yield progress
    finally:
        for bar in bars.values():
            bar.close()
