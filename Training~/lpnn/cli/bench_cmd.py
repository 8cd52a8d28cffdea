"""`lpnn bench`: the speed/accuracy benchmark of placement methods (Documentation~/quality.md §6).

  lpnn bench CAPTURES... [--model M.onnx] [--refine F] [--budgets 0.01,0.05,0.1,0.2,0.3] [--tolerance TAU]
             [--repeats 3] --out DIR

For every capture x method (uniform, random, heuristic, apv, insertion; with --model the LPNN tiers lpnn-topk, lpnn
(spread ranking), lpnn-guided (insertion guided by the scores) and lpnn-refine (guided insertion + seeded exact refinement,
factor F, default 2); the fast
reference, and the faithful reference on captures of <= 200 points) x budget, and the tolerance
policy: probes, time (median of repeats; LPNN split into features / inference / selection /
refinement), mean and p95 error and the ratio to the reference — the fast reference, or above
--full-reference-limit points (150,000) the blockwise reference (quality.md §3.3; column `yardstick`); lpnn-refine
only up to --refine-limit points (20,000). Writes DIR/bench.csv and per capture
DIR/<capture>.error.png and DIR/<capture>.time.png.

Long runs lose nothing: bench.csv is rewritten (atomically) after every method of every capture, a method or capture
that fails is reported (DIR/failures.csv: capture, method, reason; and on the console) and the run
goes on; the exit code is 1 when anything failed. The blockwise reference (an hour or more on a level of 10^5-10^6
points) keeps its finished blocks in DIR/<capture>.blockwise.npz as it goes: the same command run again resumes it.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    from ..quality.policy_rules import DEFAULT_BUDGETS, DEFAULT_TOLERANCE, FULL_REFERENCE_LIMIT, REFINE_BENCH_LIMIT
    from .arguments import fractions, refine_factor, tolerance

    parser = subparsers.add_parser("bench", help="speed/accuracy benchmark of placement methods (CSV + PNG)",
                                   description="Benchmark placement methods on captures: probes, time, error.")
    parser.add_argument("captures", nargs="+", metavar="CAPTURE", help="capture files or dataset folders")
    parser.add_argument("--model", metavar="M.onnx", help="also benchmark this LPNN model (with its card)")
    parser.add_argument("--refine", type=refine_factor, default=2.0, metavar="F",
                        help="seed factor of the lpnn-refine tier (default 2)")
    parser.add_argument("--budgets", type=fractions, default=DEFAULT_BUDGETS, metavar="F1,F2,...",
                        help=f"budget fractions (default {','.join(f'{b:g}' for b in DEFAULT_BUDGETS)})")
    parser.add_argument("--tolerance", type=tolerance, default=DEFAULT_TOLERANCE, metavar="TAU",
                        help=f"tolerance policy's mean error (default {DEFAULT_TOLERANCE:g})")
    parser.add_argument("--no-tolerance", action="store_true", help="skip the tolerance policy rows")
    parser.add_argument("--repeats", type=int, default=3, help="timing repeats of the cheap methods (median; default 3)")
    parser.add_argument("--reference-repeats", type=int, default=1, help="timing repeats of the references (default 1)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random baseline (default 0)")
    parser.add_argument("--workers", type=int, choices=(1, 2), help="processes for the fast reference and the blockwise reference's blocks (default 1; 2 helps only on an idle second core)")
    parser.add_argument("--full-reference-limit", type=int, default=FULL_REFERENCE_LIMIT, metavar="N",
                        help="above N points the yardstick is the blockwise reference (quality.md §3.3) and the methods "
                             f"that run the full reference are skipped (default {FULL_REFERENCE_LIMIT:,})")
    parser.add_argument("--refine-limit", type=int, default=REFINE_BENCH_LIMIT, metavar="N",
                        help="above N points the lpnn-refine tier is skipped: each of its rows decimates again "
                             f"(default {REFINE_BENCH_LIMIT:,})")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (bench.csv and PNG figures)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from ..core.capture_file import dataset_files, read_capture, safe_file_stem
    from ..core.in_use_section import in_use_text
    from ..scenes.capture_geometry import capture_raycaster
    from ..quality.bench import BenchConfig, BenchFailure, BenchRow, bench_capture, failure_reason
    from .errors import user_errors
    from ..quality.plots import error_plot, time_plot
    from ..errors import UserError

    if args.repeats < 1 or args.reference_repeats < 1:
        raise UserError("--repeats and --reference-repeats must be >= 1")
    if args.full_reference_limit < 4:
        raise UserError(f"--full-reference-limit {args.full_reference_limit} must be at least 4 points")
    if args.refine_limit < 0:
        raise UserError(f"--refine-limit {args.refine_limit} must be >= 0 points (0 skips the lpnn-refine tier)")
    files = dataset_files(args.captures)
    if not files:
        raise UserError("no capture files found in " + ", ".join(args.captures))
    scorer = None
    if args.model is not None:
        from ..train.onnx_scoring import OnnxScorer

        scorer = OnnxScorer(args.model)
    config = BenchConfig(budgets=tuple(args.budgets), tolerance=None if args.no_tolerance else args.tolerance,
                         repeats=args.repeats, reference_repeats=args.reference_repeats, seed=args.seed,
                         workers=args.workers, refine=args.refine, full_reference_limit=args.full_reference_limit,
                         refine_limit=args.refine_limit, checkpoints=args.out)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows: list[BenchRow] = []
    failures: list[BenchFailure] = []
    stems: set[str] = set()
    for number, path in enumerate(files, start=1):
        print(f"[{number}/{len(files)}] {path}", flush=True)
        try:
            with user_errors(str(path)):
                capture = read_capture(path)
                if scorer is not None:
                    scorer.check_capture(capture, str(path))
                result = bench_capture(path.stem, capture, config, scorer,
                                       log=lambda message: print(message, flush=True),
                                       partial=lambda done: _write_results(out, rows + done, failures),
                                       geometry=capture_raycaster(capture)[0])
        except Exception as error:  # reported, and the run goes on (user_errors words the known ones)
            failures.append(BenchFailure(path.stem, "*", failure_reason(error)))
            print(f"  FAILED {path.stem}: {failures[-1].reason}", flush=True)
            _write_results(out, rows, failures)
            continue
        stem = safe_file_stem(path.stem)
        while stem in stems:
            stem += "_"
        stems.add(stem)
        rows.extend(result.rows)
        failures.extend(result.failures)
        _write_results(out, rows, failures)  # after every capture: a later failure loses nothing
        error_plot(result, out / f"{stem}.error.png")
        time_plot(result, out / f"{stem}.time.png")
        for row in result.rows:
            versus = (f"probes x ref {row.probes_ratio:.2f}" if row.probes_ratio is not None
                      else f"error x ref {row.error_ratio:.2f}")
            print(f"  {row.method:>18} {row.policy:>9} {row.parameter:<6g} probes {row.probes:>6,} "
                  f"time {row.seconds * 1000:>10.1f} ms  mean {row.mean_error:.4f}  p95 {row.p95_error:.4f}  "
                  f"in use {in_use_text(row.in_use_error)}  leaking {in_use_text(row.leaking)}  {versus}")
        for failure in result.failures:
            print(f"  FAILED {failure.method} on {failure.capture}: {failure.reason}", flush=True)
    print(f"wrote {out / 'bench.csv'} ({len(rows)} rows) and figures to {out}")
    if failures:
        print(f"{len(failures)} failure(s), listed in {out / 'failures.csv'}:")
        for failure in failures:
            print(f"  {failure.capture}: {failure.method}: {failure.reason}")
        return 1
    return 0


def _write_results(out: Path, rows: list, failures: list) -> None:
    from ..core.atomic import write_text_atomic
    from ..quality.bench import failures_csv, rows_csv

    write_text_atomic(out / "bench.csv", rows_csv(rows))
    if failures:
        write_text_atomic(out / "failures.csv", failures_csv(failures))
