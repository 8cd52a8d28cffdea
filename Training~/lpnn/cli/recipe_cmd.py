"""`lpnn recipe`: the default model's training recipe (Documentation~/training.md "Default model").

  lpnn recipe run --work DIR [--pak PAK] [--quick] [--variants N] [--install MODELS_DIR]
  lpnn recipe report MODEL.onnx [--check DOCUMENT.md]

`run` imports crops of every level of openarena-081-maps, splits by level (held-out levels chosen by
rule before training), labels with the fast reference, trains, evaluates on the held-out levels and
writes the model card; with --install it copies model and card into MODELS_DIR (the package's
Models/ folder). A rerun on the same --work folder resumes. --quick is the reduced recipe CI runs.
`report` prints the held-out table of a recipe model's card; with --check it fails when DOCUMENT
does not contain exactly that table (benchmarks.md must agree with the shipped card).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("recipe", help="train, evaluate and install the default model",
                                   description="The default model's reproducible training recipe.")
    commands = parser.add_subparsers(dest="recipe_command", required=True, metavar="COMMAND")
    run_parser = commands.add_parser("run", help="run (or resume) the recipe in a work folder")
    run_parser.add_argument("--work", required=True, metavar="DIR", help="work folder (resumable)")
    run_parser.add_argument("--pak", metavar="PAK",
                            help="openarena maps pak (default: $LPNN_OPENARENA_PAK, else the Debian path)")
    run_parser.add_argument("--quick", action="store_true", help="reduced recipe: 6 levels, short training (CI)")
    run_parser.add_argument("--variants", type=int, default=0, metavar="N",
                            help="relit variants per training crop (seeded perturbations of each training level's "
                                 "recovered rig, lights.md §9; never for validation or held-out levels; default 0)")
    run_parser.add_argument("--in-use", choices=("all", "band", "reachable"), default="all",
                            help="the crops' points: 'all' (default; what the shipped model was trained on) or only "
                                 "the points where players go (Documentation~/in-use.md), labelled and trained on")
    run_parser.add_argument("--scheduler", metavar="ADDRESS",
                            help="crop, label and evaluate on the Dask cluster at ADDRESS (e.g. tcp://10.0.0.5:8786; "
                                 "Documentation~/training.md \"On a cluster\"); default: 2 local worker processes")
    run_parser.add_argument("--install", metavar="MODELS_DIR", help="copy the model and its card here when done")
    run_parser.set_defaults(handler=_run)
    report_parser = commands.add_parser("report", help="print the held-out table of a recipe model's card")
    report_parser.add_argument("model", metavar="MODEL.onnx", help="a model whose card has recipe figures")
    report_parser.add_argument("--check", metavar="DOCUMENT.md",
                               help="fail unless DOCUMENT contains exactly this table")
    report_parser.set_defaults(handler=_report)


def _run(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from ..recipe.config import QUICK, RecipeConfig
    from ..recipe.run import run_recipe
    from .errors import UserError
    from .level_args import existing_pak

    pak = existing_pak(args.pak)
    config = QUICK if args.quick else RecipeConfig()
    if args.variants < 0:
        raise UserError(f"--variants {args.variants} must be 0 or more")
    if args.variants:
        config = replace(config, variants_per_crop=args.variants,
                         variant_rig_scheme="quick" if args.quick else config.variant_rig_scheme)
    config = replace(config, in_use=args.in_use)
    result = run_recipe(pak, Path(args.work), config, install_to=Path(args.install) if args.install else None,
                        scheduler=args.scheduler)
    total = sum(result.times.seconds.values())
    print(f"model: {result.model} ({total / 60:.1f} min over " +
          ", ".join(f"{k} {v:.0f} s" for k, v in result.times.seconds.items()) + ")")
    if result.installed:
        print(f"installed: {result.installed[0]} and {result.installed[1].name}")
    return 0


def _report(args: argparse.Namespace) -> int:
    from ..recipe.publish import documented_table, report_markdown
    from ..train.modelcard import ModelCard, card_path
    from ..errors import UserError

    table = report_markdown(ModelCard.read(card_path(args.model)))
    if not args.check:
        sys.stdout.write(table)
        return 0
    document = Path(args.check)
    try:
        found = documented_table(document.read_text(encoding="utf-8"))
    except OSError as exc:
        raise UserError(f"{document}: cannot read: {exc.strerror or exc}") from exc
    if found != table:
        raise UserError(f"{document}: the held-out table differs from {card_path(args.model).name}; "
                        f"replace it with the output of `lpnn recipe report {args.model}`")
    print(f"{document}: the held-out table agrees with {card_path(args.model).name}")
    return 0
