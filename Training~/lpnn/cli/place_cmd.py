"""`lpnn place`: probe positions for a capture, from a model, scores or a non-learned method.

  lpnn place CAPTURE (--model M.onnx | --scores SCORES.csv | --method fast|uniform|heuristic|random)
             (--budget FRACTION | --tolerance TAU) --out PROBES.json

Budget keeps the top FRACTION of the ranking; tolerance keeps the smallest prefix whose mean
placement error is <= TAU (Documentation~/quality.md §4). Both end with the tetrahedron guarantee.
SCORES.csv is what `lpnn score` writes (index,i,j,k,score). Prints the probes kept and the error.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..core.capture import Capture

PLACE_METHODS = ("fast", "uniform", "heuristic", "random")


def register(subparsers: argparse._SubParsersAction) -> None:
    from ..quality.arguments import add_policy_arguments

    parser = subparsers.add_parser("place", help="place probes in a capture (budget or error tolerance)",
                                   description="Choose probe positions for a capture and write *.probes.json.")
    parser.add_argument("capture", metavar="CAPTURE", help="capture file (*.lpnncap)")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--model", metavar="M.onnx", help="score the points with this model (and its card)")
    source.add_argument("--scores", metavar="SCORES.csv", help="scores from `lpnn score` (index,i,j,k,score)")
    source.add_argument("--method", choices=PLACE_METHODS,
                        help="fast reference, uniform lattice, curvature-weighted farthest-point heuristic, or random (seeded)")
    add_policy_arguments(parser)
    parser.add_argument("--out", required=True, metavar="PROBES.json", help="output probe positions")
    parser.add_argument("--seed", type=int, default=0, help="seed of --method random (default 0)")
    parser.add_argument("--workers", type=int, choices=(1, 2), help="processes for --method fast (default 1; 2 helps only on an idle second core)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from ..core.capture import read_capture
    from ..quality.cli_support import user_errors

    capture = read_capture(args.capture)
    with user_errors(args.capture):
        return _place(args, capture)


def _place(args: argparse.Namespace, capture: Capture) -> int:
    import numpy as np

    from ..core.grid import EvaluationGrid
    from ..core.selection import ensure_tetrahedron, rank
    from ..quality.baselines import heuristic_ranking, random_ranking, uniform_selection
    from ..quality.cli_support import progress_bar, run_reference
    from ..quality.metric import ReferenceField, evaluate_placement
    from ..quality.policies import (budget_count, place_count, place_tolerance, prefix_selection, reference_count,
                                    reference_tolerance)
    from ..quality.probes_file import write_probes_json

    field = ReferenceField.from_capture(capture)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    n = field.point_count
    if args.method == "fast":
        update, close = progress_bar(f"{Path(args.capture).name}: fast reference")
        try:
            decimation = run_reference(field, "fast", args.capture, args.workers, update)
        finally:
            close()
        placement = (reference_count(decimation, budget_count(args.budget, n)) if args.budget is not None
                     else reference_tolerance(decimation, args.tolerance))
        what = "fast reference"
    else:
        if args.method == "uniform":
            grid_order = np.arange(n, dtype=np.int64)

            def select(count: int) -> np.ndarray:
                return ensure_tetrahedron(grid, grid_order, uniform_selection(grid.ids, count))[0]

            what = "uniform lattice"
        else:
            if args.model is not None:
                from ..train.onnx_scoring import OnnxScorer

                ranking = rank(OnnxScorer(args.model).score_capture(capture, args.capture))
                what = f"model {Path(args.model).name}"
            elif args.scores is not None:
                from .scores_file import read_scores_csv

                ranking = rank(read_scores_csv(args.scores, capture.ids))
                what = f"scores {Path(args.scores).name}"
            elif args.method == "heuristic":
                ranking = heuristic_ranking(grid, capture.sh, capture.lighting_scale)
                what = "farthest-point heuristic"
            else:
                ranking = random_ranking(n, args.seed)
                what = f"random (seed {args.seed})"
            select = prefix_selection(grid, ranking)
        placement = (place_count(field, select, budget_count(args.budget, n)) if args.budget is not None
                     else place_tolerance(field, select, args.tolerance))
    quality = evaluate_placement(field, placement.indices)
    policy = f"budget={args.budget:g}" if args.budget is not None else f"tolerance={args.tolerance:g}"
    source = {"capture": Path(args.capture).name, "method": what, "policy": policy,
              "mean_error": round(quality.irradiance.mean, 6), "p95_error": round(quality.irradiance.p95, 6)}
    write_probes_json(args.out, capture.positions[placement.indices], capture.units, source)
    kept = placement.indices.shape[0]
    extra = f" ({placement.added_for_tetrahedron} added for a tetrahedron)" if placement.added_for_tetrahedron else ""
    print(f"{what}, {policy}: kept {kept:,} of {n:,} probes ({100.0 * kept / n:.1f} %){extra}; "
          f"mean error {quality.irradiance.mean:.4g}, p95 {quality.irradiance.p95:.4g} "
          f"(SMAPE mean {quality.smape.mean:.4g}) -> {args.out}")
    return 0
