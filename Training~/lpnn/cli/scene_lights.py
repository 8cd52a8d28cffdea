"""`lpnn scene lights`: recover a level's point-light rig from its baked lightmaps (Documentation~/lights.md).

  lpnn scene lights LEVEL [--grid NxNxM] [--start grid|peaks] [--scheme NAME] --out RIG.json
  lpnn scene lights --compare RIG.json LEVEL
"""

from __future__ import annotations

import argparse
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from ..errors import UserError
from .level_args import LEVEL_HELP, level_user_errors


def register(actions: argparse._SubParsersAction) -> None:
    from ..lights.settings import AMBIENTS, DEFAULT_AMBIENT, DEFAULT_GRID, DEFAULT_MAX_EDGE, DEFAULT_REFRESH, \
        DEFAULT_SCHEME, DEFAULT_SCRIPT_LIGHTS, DEFAULT_START, SCHEMES, SCRIPT_LIGHTS, STARTS

    lights = actions.add_parser("lights", help="recover the level's point lights from its lightmaps (a rig file)",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    lights.add_argument("level", metavar="LEVEL", help=LEVEL_HELP)
    what = lights.add_mutually_exclusive_group(required=True)
    what.add_argument("--out", type=Path, metavar="RIG.json", help="write the recovered rig here (and its objective "
                      "curve as RIG.curve.csv / RIG.curve.png beside it)")
    what.add_argument("--compare", type=Path, metavar="RIG.json",
                      help="compare this rig with the level's light entities (when it kept them) and its light grid")
    lights.add_argument("--grid", default="x".join(map(str, DEFAULT_GRID)), metavar="NxNxM",
                        help=f"initial lights: cells of the world box along x, y, z; only cells centred in open space "
                             f"get a light (default {'x'.join(map(str, DEFAULT_GRID))})")
    lights.add_argument("--start", default=DEFAULT_START, choices=STARTS,
                        help=f"where the lights start: 'grid', the open cells of --grid, or 'peaks', the peaks of the "
                             f"baked light pushed out by their fitted height with those cells as fallback where "
                             f"nothing peaks (lights.md §4; default {DEFAULT_START})")
    lights.add_argument("--scheme", default=DEFAULT_SCHEME, choices=sorted(SCHEMES),
                        help=f"optimisation phases (seed Table 5.1; default {DEFAULT_SCHEME})")
    lights.add_argument("--max-edge", default=str(DEFAULT_MAX_EDGE), metavar="UNITS",
                        help=f"subdivide target triangles to this longest edge in Quake units, or 'none' for the "
                             f"BSP's vertices only (default {DEFAULT_MAX_EDGE:g})")
    lights.add_argument("--refresh", type=int, default=DEFAULT_REFRESH, metavar="N",
                        help=f"recompute shadow rays every N iterations (default {DEFAULT_REFRESH})")
    lights.add_argument("--no-textures", action="store_true", help="albedo 0.5 everywhere instead of the pk3 textures")
    lights.add_argument("--surfaces", action="store_true",
                        help="also recover surface lights: one q3map_surfacelight value per shader that may emit "
                             "(its script says so, or it is sky or named *light* without a script); the rig then "
                             "holds them (lights.md §4-5; the probe baker does not bake them yet)")
    lights.add_argument("--spots", action=argparse.BooleanOptionalAction, default=None,
                        help="also start q3map2 spotlights (pointing down) beside the point lights: their axes and cones "
                             "(radiusByDist) are fitted too, and the rig holds them as spots (lights.md §4; default: "
                             "with the peak start, where a spotlight's disc explains the floor's light better than a "
                             "point light's bump; --no-spots: never)")
    lights.add_argument("--suns", action=argparse.BooleanOptionalAction, default=None,
                        help="also recover one q3map2 sun (direction, colour, intensity in photons) lighting what sees "
                             "the level's sky surfaces; the rig then holds it (lights.md §4-5; default: where the level "
                             "has sky surfaces; --no-suns: never)")
    lights.add_argument("--ambient", default=DEFAULT_AMBIENT, choices=AMBIENTS,
                        help=f"the level's ambient: 'worldspawn' holds it at what the worldspawn records (`_ambient`; "
                             f"fitted where it records none, or `_minlight`), 'fitted' fits it with the intensities "
                             f"(lights.md §4; default {DEFAULT_AMBIENT})")
    lights.add_argument("--scripts", default=DEFAULT_SCRIPT_LIGHTS, choices=SCRIPT_LIGHTS,
                        help=f"the surface lights' values and suns the level's shader scripts give (where the level was "
                             f"compiled with them): 'held' holds them there, 'fitted' fits them from the lightmaps "
                             f"alone (lights.md §4; default {DEFAULT_SCRIPT_LIGHTS})")
    lights.add_argument("--quiet", action="store_true", help="no progress bar")
    lights.set_defaults(handler=_lights)


def parse_grid(text: str) -> tuple[int, int, int]:
    parts = text.lower().split("x")
    try:
        dims = tuple(int(p) for p in parts)
    except ValueError:
        dims = ()
    if len(dims) != 3 or not all(1 <= d <= 64 for d in dims):
        raise UserError(f"--grid {text!r} must be three whole numbers from 1 to 64 joined by 'x', e.g. 8x8x3")
    return dims  # type: ignore[return-value]


def parse_max_edge(text: str) -> float | None:
    if text.lower() == "none":
        return None
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (value >= 1.0 and value < float("inf")):
        raise UserError(f"--max-edge {text!r} must be a number of Quake units >= 1, or 'none'")
    return value


@contextmanager
def rig_user_errors() -> Iterator[None]:
    from ..lights.rig import RigError

    with level_user_errors():
        try:
            yield
        except RigError as exc:
            raise UserError(str(exc)) from exc


def _lights(args: argparse.Namespace) -> None:
    if args.compare is not None:
        _compare(args)
        return
    from tqdm import tqdm

    from ..lights.curves import write_curve_csv, write_curve_png
    from ..lights.pipeline import add_surface_lights, fit_scene, load_scene, rig_of
    from ..lights.rig import write_rig
    from ..scenes.levels import load_level

    grid = parse_grid(args.grid)
    max_edge = parse_max_edge(args.max_edge)
    if args.refresh < 1:
        raise UserError(f"--refresh {args.refresh} must be at least 1 iteration")
    with rig_user_errors():
        level = load_level(args.level)
        scene = load_scene(level, max_edge=max_edge, textures=not args.no_textures)
        if args.surfaces:
            add_surface_lights(scene)
            print(f"{level.name}: {len(scene.surface_shaders)} surface-light shaders to recover "
                  f"({scene.surface_emitters.areas.count:,} area lights) in {scene.seconds['surface lights']:.1f} s")
    print(f"{level.name}: {scene.target.point_count:,} target points (max edge "
          f"{scene.max_edge if scene.max_edge is not None else 'none'}), projection loss "
          f"{scene.target.projection_loss:.3f}, textures {scene.albedo.found} of {len(scene.albedo.images)} shaders")
    bar = tqdm(desc=f"fit {args.scheme}", unit="it", file=sys.stderr, disable=args.quiet)

    def progress(done: int, budget: int) -> None:
        bar.total = budget
        bar.update(done - bar.n)

    try:
        with rig_user_errors():
            try:
                result = fit_scene(scene, grid, args.scheme, args.refresh, progress, spots=args.spots,
                                   start=args.start, suns=args.suns, ambient=args.ambient, scripts=args.scripts)
            except ValueError as exc:
                raise UserError(str(exc)) from exc
    finally:
        bar.close()
    rig = rig_of(scene, result, grid, args.scheme, args.start)
    with rig_user_errors():
        path = write_rig(args.out, rig)
    stem = args.out.with_suffix("")
    write_curve_csv(stem.with_name(stem.name + ".curve.csv"), result.curve)
    write_curve_png(stem.with_name(stem.name + ".curve.png"), {args.scheme: result.curve}, f"{level.name}: {args.scheme}")
    if "suns" in rig.extra:
        print(f"{path}: suns " + (", ".join(f"toward {', '.join(f'{v:.3f}' for v in sun.direction)} (Unity axes), "
                                           f"{sun.intensity:.1f} photons" for sun in rig.suns) or "none"))
    casting = scene.model.raycaster.cast_seconds if scene.model.raycaster is not None else 0.0
    if args.surfaces:
        print(f"{path}: surface lights " + (", ".join(f"{s.shader} {s.value:.0f}" for s in rig.surfaces) or "none"))
    print(f"{path}: {rig.count} lights (of {result.initial_lights} initial), objective {result.objective:.4f}, "
          f"{result.iterations} iterations in {result.seconds:.1f} s ({result.seconds / max(result.iterations, 1):.2f} s "
          f"an iteration), {result.rays:,} shadow rays ({result.rays / casting if casting > 0 else 0:,.0f} rays/s "
          f"inside the raycaster)")


def _compare(args: argparse.Namespace) -> None:
    from ..lights.compare import compare_grid, compare_rigs, relight_stored_grid, stored_grid
    from ..lights.pipeline import level_emitters, point_lights_of, rig_emitters, shader_power, surface_pieces
    from ..lights.rig import Rig, entity_lights, read_rig
    from ..scenes.solid import SolidTester
    from ..scenes.levels import load_level
    from ..lights.shadows import shadow_raycaster

    with rig_user_errors():
        rig = read_rig(args.compare)
        level = load_level(args.level)
        real = entity_lights(level.bsp.entities, level.name)
        stored = stored_grid(level.bsp)
        own_emitters = rig_emitters(level, rig) if rig.surfaces or rig.suns else None
    if rig.bsp_sha256 and rig.bsp_sha256 != level.sha256:
        print(f"warning: {args.compare} was recovered from a different file than {level.location} "
              f"(sha256 {rig.bsp_sha256[:12]}... vs {level.sha256[:12]}...)", file=sys.stderr)
    real_emitters = level_emitters(level, real) if real.rig.count else None
    if real_emitters is not None:
        c = compare_rigs(rig, real.rig, real_surfaces=surface_pieces(level.bsp, real_emitters),
                         shader_power=shader_power(level.bsp, own_emitters) if own_emitters is not None else {})
        print(f"rig vs the level's {c.real_lights} light entities and {len(real_emitters.shaders)} surface-light "
              f"shaders ({c.surface_share:.0%} of the real intensity; {c.recovered_lights} lights and "
              f"{len(rig.surfaces)} surface lights recovered): {c.matched_share:.1%} of real intensity matched "
              f"(a recovered light within 1 m, or a recovered surface light of the same shader; surface lights "
              f"{c.surface_matched_share:.1%}); intensity-weighted distance real->recovered "
              f"{c.real_to_recovered:.2f} m, recovered->real {c.recovered_to_real:.2f} m (lights only); total "
              f"intensity recovered {c.recovered_power:,.0f} vs real {c.real_power:,.0f} (surface lights as the "
              f"point light of equal flux)")
    else:
        print(f"{level.name} kept no point-light entities: no rig-vs-rig comparison")
    raycaster = shadow_raycaster(level.bsp)  # q3map2's shadow casters (lights.md §3)
    solid = SolidTester(level.bsp)

    def is_open(points):
        return ~solid.solid_or_outside(points)

    sets = [("the rig", rig, own_emitters)]
    if real_emitters is not None:
        own = point_lights_of(real)
        sets.append(("the level's own lights, spotlights and surface lights (yardstick)",
                     Rig.from_quake(own.positions, own.colours, own.intensities, ambient=own.ambient),
                     real_emitters))
    for label, lights, emitters in sets:
        g = compare_grid(stored, relight_stored_grid(level.bsp, stored, lights, raycaster, is_open, emitters))
        print(f"light grid re-lit from {label} vs stored, {g.nodes:,} valid nodes: relative irradiance error mean "
              f"{g.mean_error:.3f}, p95 {g.p95_error:.3f} (quality.md); plain relative error {g.plain_relative:.3f}")
