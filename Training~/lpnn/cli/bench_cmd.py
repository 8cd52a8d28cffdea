"""`lpnn bench`: the speed/accuracy benchmark of placement methods (Documentation~/quality.md §6).

  lpnn bench CAPTURES... [--model M.onnx] [--refine F] [--budgets 0.1,0.2,0.3] [--tolerance TAU]
             [--repeats 3] --out DIR

For every capture x method (uniform, random, heuristic; with --model the LPNN tiers lpnn-topk, lpnn
(spread ranking) and lpnn-refine (spread + seeded exact refinement, factor F, default 2); the fast
reference, and the faithful reference on captures of <= 200 points) x budget, and the tolerance
policy: probes, time (median of repeats; LPNN split into features / inference / selection /
refinement), mean and p95 error and the ratio to the reference. Writes DIR/bench.csv and per capture
DIR/<capture>.error.png and DIR/<capture>.time.png.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    from ..quality.arguments import DEFAULT_TOLERANCE, fractions, refine_factor, tolerance

    parser = subparsers.add_parser("bench", help="speed/accuracy benchmark of placement methods (CSV + PNG)",
                                   description="Benchmark placement methods on captures: probes, time, error.")
    parser.add_argument("captures", nargs="+", metavar="CAPTURE", help="capture files or dataset folders")
    parser.add_argument("--model", metavar="M.onnx", help="also benchmark this LPNN model (with its card)")
    parser.add_argument("--refine", type=refine_factor, default=2.0, metavar="F",
                        help="seed factor of the lpnn-refine tier (default 2)")
    parser.add_argument("--budgets", type=fractions, default=(0.1, 0.2, 0.3), metavar="F1,F2,...",
                        help="budget fractions (default 0.1,0.2,0.3)")
    parser.add_argument("--tolerance", type=tolerance, default=DEFAULT_TOLERANCE, metavar="TAU",
                        help=f"tolerance policy's mean error (default {DEFAULT_TOLERANCE:g})")
    parser.add_argument("--no-tolerance", action="store_true", help="skip the tolerance policy rows")
    parser.add_argument("--repeats", type=int, default=3, help="timing repeats of the cheap methods (median; default 3)")
    parser.add_argument("--reference-repeats", type=int, default=1, help="timing repeats of the references (default 1)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random baseline (default 0)")
    parser.add_argument("--workers", type=int, choices=(1, 2), help="processes for the fast reference (default 1; 2 helps only on an idle second core)")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (bench.csv and PNG figures)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from ..core.capture import dataset_files, read_capture, safe_file_stem
    from ..core.atomic import write_text_atomic
    from ..quality.bench import BenchConfig, bench_capture, rows_csv
    from ..quality.cli_support import user_errors
    from ..quality.plots import error_plot, time_plot
    from .errors import UserError

    if args.repeats < 1 or args.reference_repeats < 1:
        raise UserError("--repeats and --reference-repeats must be >= 1")
    files = dataset_files(args.captures)
    if not files:
        raise UserError("no capture files found in " + ", ".join(args.captures))
    scorer = None
    if args.model is not None:
        from ..train.onnx_scoring import OnnxScorer

        scorer = OnnxScorer(args.model)
    config = BenchConfig(budgets=tuple(args.budgets), tolerance=None if args.no_tolerance else args.tolerance,
                         repeats=args.repeats, reference_repeats=args.reference_repeats, seed=args.seed,
                         workers=args.workers, refine=args.refine)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    stems: set[str] = set()
    for path in files:
        capture = read_capture(path)
        if scorer is not None:
            scorer.check_capture(capture, str(path))
        stem = safe_file_stem(path.stem)
        while stem in stems:
            stem += "_"
        stems.add(stem)
        with user_errors(str(path)):
            result = bench_capture(path.stem, capture, config, scorer, log=lambda message: print(message, flush=True))
        rows.extend(result.rows)
        error_plot(result, out / f"{stem}.error.png")
        time_plot(result, out / f"{stem}.time.png")
        for row in result.rows:
            versus = (f"probes x ref {row.probes_ratio:.2f}" if row.probes_ratio is not None
                      else f"error x ref {row.error_ratio:.2f}")
            print(f"  {row.method:>18} {row.policy:>9} {row.parameter:<6g} probes {row.probes:>6,} "
                  f"time {row.seconds * 1000:>10.1f} ms  mean {row.mean_error:.4f}  p95 {row.p95_error:.4f}  {versus}")
    write_text_atomic(out / "bench.csv", rows_csv(rows))
    print(f"wrote {out / 'bench.csv'} ({len(rows)} rows) and {2 * len(files)} figures to {out}")
    return 0
