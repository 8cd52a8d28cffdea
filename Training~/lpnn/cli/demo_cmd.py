"""`lpnn demo`: the README's main job (Documentation~/benchmarks.md "Demo").

  lpnn demo --model M.onnx --out DIR [--pak PAK] [--level oa_dm1] [--tolerance 0.05]

Imports a level the model never saw, scores it, keeps the fewest probes whose mean error is within the
tolerance by insertion refined in batches (the package's default) and by LPNN's tiers, compares with the reference,
insertion, a uniform grid and the heuristic, prints a table and writes DIR/probes.json (the default's probes; Unity:
LPNN volume > Import .probes.json…), probes-batched.json, probes-guided.json, probes-spread.json, probes-refined.json,
demo.png, table.txt and summary.json.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    from ..core import in_use_defaults as in_use
    from ..demo import DEMO_LEVEL
    from ..quality.placement.policy_rules import DEFAULT_TOLERANCE
    from .arguments import tolerance

    parser = subparsers.add_parser("demo", help="place probes on a held-out level and compare (the README's main job)",
                                   description="Headless demo on a real level with a model.")
    parser.add_argument("--model", required=True, metavar="M.onnx", help="model with its card beside it")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    parser.add_argument("--pak", metavar="PAK", help="openarena maps pak (default: $LPNN_OPENARENA_PAK, else the Debian path)")
    parser.add_argument("--level", default=DEMO_LEVEL, help=f"level name in the pak (default {DEMO_LEVEL}, held out)")
    parser.add_argument("--tolerance", type=tolerance, default=DEFAULT_TOLERANCE, metavar="TAU",
                        help=f"mean irradiance error allowed (default {DEFAULT_TOLERANCE:g})")
    parser.add_argument("--in-use", choices=in_use.RULES, default=in_use.DEFAULT_RULE,
                        help="which points the placement serves (Documentation~/in-use.md; default "
                             f"{in_use.DEFAULT_RULE}); unless 'all', the default placement on every point is shown too")
    parser.set_defaults(handler=_run)


def _run(args: argparse.Namespace) -> int:
    from ..demo.report import table, write_outputs
    from ..demo.run import held_out_in_card, run_demo
    from .errors import user_errors
    from ..scenes.importer import DEFAULT_CELL, import_level
    from ..scenes.levels import load_pak_member
    from ..quality.placement.warmup import compile_placement_kernels
    from ..train.onnx_scoring import OnnxScorer
    from .level_args import existing_pak, level_user_errors

    pak = existing_pak(args.pak)
    scorer = OnnxScorer(args.model)
    held_out = held_out_in_card(scorer.card, args.level)
    log = lambda text: print(text, file=sys.stderr, flush=True)  # noqa: E731 - progress to stderr, table to stdout
    # Before the import too: the warm-up's synthetic room runs the import's kernels (solid, in use, features) as well as
    # the placement's, so on a checkout's first run neither the import nor any method counts numba's compilation.
    log("compiling the import and placement kernels (once per checkout; cached)")
    compile_seconds = compile_placement_kernels()
    log(f"importing {args.level} from {pak.name} at {DEFAULT_CELL:g} m cells")
    with level_user_errors():
        start = time.perf_counter()
        level = load_pak_member(pak, f"maps/{args.level}.bsp")
        imported = import_level(level, cell_size=DEFAULT_CELL, drop_unlit=True, timings_in_source=True,
                                in_use=args.in_use)
        seconds = {"import (grid, solid, in use, SH, features)": time.perf_counter() - start}
        # The old behaviour beside it, so the dilution by the air stays visible (in-use.md): every point kept.
        every_point = (None if args.in_use == "all" else
                       import_level(level, cell_size=DEFAULT_CELL, drop_unlit=True, timings_in_source=True).capture)
    with user_errors(args.level):
        result = run_demo(imported.capture, args.level, scorer, seconds, held_out, args.tolerance, log,
                          every_point=every_point, compile_seconds=compile_seconds)
    files = write_outputs(result, Path(args.out), Path(args.model).name)
    sys.stdout.write(table(result))
    print("\nwrote " + ", ".join(str(path) for path in files.values()))
    return 0
