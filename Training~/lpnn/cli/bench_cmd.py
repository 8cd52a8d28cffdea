"""`lpnn bench`: the speed/accuracy benchmark of placement methods (Documentation~/quality.md §6).

  lpnn bench CAPTURES... [--model M.onnx] [--budgets 0.01,0.05,0.1,0.2,0.3] [--tolerance TAU]
             [--repeats 3] [--workers N] [--scheduler ADDRESS] [--methods M1,M2] [--no-budgets]
             [--reference-stop E | --no-reference] [--leaks avoid|ignore] --out DIR

For every capture x method (the table's names, Documentation~/methods.md: uniform, random, heuristic, apv, insertion,
insertion-refined; with --model the methods that read the scores: network-topk, network, guided, guided-refined and
guided-exact-refined, the refined ones at the seed factor RECOMMENDED_REFINE = 2; the fast reference, and the faithful
reference on captures of <= 200 points) x budget, and the tolerance
policy: probes, time (median of repeats; LPNN split into features / inference / selection /
refinement), mean and p95 error and the ratio to the reference — the fast reference, or above
--full-reference-limit points (150,000) the blockwise reference (quality.md §3.3; column `yardstick`); guided-exact-refined
only up to --refine-limit points (20,000). Writes DIR/bench.csv and per capture
DIR/<capture>.error.png and DIR/<capture>.time.png.

Captures are benchmarked side by side on --workers local processes or on the Dask cluster at --scheduler
(lpnn/core/engine.py; the same rows, in capture order; the times are each worker's). Each process first runs every
method once on a synthetic room, not counted (quality/bench/warmup.py), so no capture's time holds numba's compilation
or the loading of its cache. Long runs lose nothing:
bench.csv is rewritten (atomically) as each capture finishes, a method or capture that fails (or whose
worker keeps dying) is reported (DIR/failures.csv: capture, method, reason; and on the console) and the run
goes on; the exit code is 1 when anything failed. The blockwise reference (an hour or more on a level of 10^5-10^6
points) keeps its finished blocks in DIR/<capture>.blockwise.npz as it goes: the same command run again resumes it.

For whole levels where the full run would not fit in the time (the trade table, benchmarks.md): --methods runs a
subset, --no-budgets only the tolerance rows, --reference-stop E stops the fast reference above E (e.g. 2τ: its curve
down to there, without the dearest tail), --no-reference computes none (probes, error and time without ratios).
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any


def register(subparsers: argparse._SubParsersAction) -> None:
    from ..quality.placement.methods import BENCH_METHODS
    from ..quality.placement.policy_rules import (DEFAULT_BUDGETS, DEFAULT_TOLERANCE, FULL_REFERENCE_LIMIT, LEAK_CHOICES,
                                                  REFINE_BENCH_LIMIT)
    from .arguments import add_engine_arguments, fractions, tolerance

    parser = subparsers.add_parser("bench", help="speed/accuracy benchmark of placement methods (CSV + PNG)",
                                   description="Benchmark placement methods on captures: probes, time, error.")
    parser.add_argument("captures", nargs="+", metavar="CAPTURE", help="capture files or dataset folders")
    parser.add_argument("--model", metavar="M.onnx", help="also benchmark this LPNN model (with its card)")
    parser.add_argument("--budgets", type=fractions, default=DEFAULT_BUDGETS, metavar="F1,F2,...",
                        help=f"budget fractions (default {','.join(f'{b:g}' for b in DEFAULT_BUDGETS)})")
    parser.add_argument("--tolerance", type=tolerance, default=DEFAULT_TOLERANCE, metavar="TAU",
                        help=f"tolerance policy's mean error (default {DEFAULT_TOLERANCE:g})")
    parser.add_argument("--no-tolerance", action="store_true", help="skip the tolerance policy rows")
    parser.add_argument("--repeats", type=int, default=3, help="timing repeats of the cheap methods (median; default 3)")
    parser.add_argument("--reference-repeats", type=int, default=1, help="timing repeats of the references (default 1)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random baseline (default 0)")
    add_engine_arguments(parser, "the captures")
    parser.add_argument("--full-reference-limit", type=int, default=FULL_REFERENCE_LIMIT, metavar="N",
                        help="above N points the yardstick is the blockwise reference (quality.md §3.3) and the methods "
                             f"that run the full reference are skipped (default {FULL_REFERENCE_LIMIT:,})")
    parser.add_argument("--refine-limit", type=int, default=REFINE_BENCH_LIMIT, metavar="N",
                        help="above N points the guided-exact-refined method is skipped: each of its rows decimates again "
                             f"(default {REFINE_BENCH_LIMIT:,})")
    parser.add_argument("--methods", type=method_names, metavar="M1,M2,...",
                        help="run only these methods (default: every one; the yardstick always runs): "
                             + ", ".join(BENCH_METHODS))
    parser.add_argument("--no-budgets", action="store_true", help="skip the budget rows (the tolerance rows only)")
    parser.add_argument("--reference-stop", type=float, metavar="E",
                        help="stop the fast reference once its mean error exceeds E, e.g. 2x the tolerance: its curve is "
                             "the full one down to there, without the last and dearest removals (a budget whose count "
                             "lies below gets no ratio)")
    parser.add_argument("--no-reference", action="store_true",
                        help="compute no reference (every ratio NaN; yardstick column 'none'): where neither the full nor "
                             "the blockwise reference fits in the time, the rows still give probes, error and time")
    parser.add_argument("--leaks", choices=LEAK_CHOICES, default="avoid",
                        help="the refined rows (insertion-refined, guided-refined): avoid light leaking through walls "
                             "where the capture's geometry is known (default; Documentation~/leaks.md) or ignore them")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (bench.csv and PNG figures)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from ..core.capture_file import dataset_files
    from ..core.engine import Engine
    from ..quality.bench.results import BenchConfig, BenchFailure, CaptureResult, failure_reason
    from .arguments import engine_and_inner_workers
    from ..quality.bench.plots import error_plot, time_plot
    from ..errors import UserError

    if args.repeats < 1 or args.reference_repeats < 1:
        raise UserError("--repeats and --reference-repeats must be >= 1")
    if args.full_reference_limit < 4:
        raise UserError(f"--full-reference-limit {args.full_reference_limit} must be at least 4 points")
    if args.refine_limit < 0:
        raise UserError(f"--refine-limit {args.refine_limit} must be >= 0 points (0 skips the guided-exact-refined method)")
    files = dataset_files(args.captures)
    if not files:
        raise UserError("no capture files found in " + ", ".join(args.captures))
    if args.model is not None:
        from ..train.onnx_scoring import OnnxScorer

        OnnxScorer(args.model)  # a missing or unreadable model is reported before any work starts
    engine_workers, inner_workers = engine_and_inner_workers(args, len(files))
    if args.no_budgets and args.no_tolerance:
        raise UserError("--no-budgets with --no-tolerance leaves no row to measure")
    if args.reference_stop is not None and args.no_reference:
        raise UserError("--reference-stop and --no-reference exclude each other: the first stops the reference, the second skips it")
    if args.reference_stop is not None and not args.reference_stop > 0:
        raise UserError(f"--reference-stop {args.reference_stop:g} must be a positive mean error (e.g. 0.1, twice τ = 0.05)")
    config = BenchConfig(budgets=() if args.no_budgets else tuple(args.budgets),
                         tolerance=None if args.no_tolerance else args.tolerance,
                         repeats=args.repeats, reference_repeats=args.reference_repeats, seed=args.seed,
                         workers=inner_workers, full_reference_limit=args.full_reference_limit,
                         refine_limit=args.refine_limit, checkpoints=args.out, methods=args.methods,
                         reference_stop=args.reference_stop, yardstick="none" if args.no_reference else "auto",
                         leaks=args.leaks)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stems = figure_stems(files)
    results: dict[int, CaptureResult] = {}  # capture number -> its result, written in capture order
    failed: dict[int, BenchFailure] = {}  # capture number -> why the whole capture failed
    tasks = [BenchTask(number, path, config, args.model, scorer_threads=None if engine_workers == 1 else 1)
             for number, path in enumerate(files)]
    with Engine(engine_workers, args.scheduler) as engine:
        for finished, done in enumerate(engine.unordered(bench_one, tasks), start=1):
            number, path = done.task.number, done.task.path
            print(f"[{finished}/{len(files)}] {path}", flush=True)
            if done.error is not None:  # reported, and the run goes on (user_errors words the known ones)
                failed[number] = BenchFailure(path.stem, "*", failure_reason(done.error))
                print(f"  FAILED {path.stem}: {failed[number].reason}", flush=True)
            else:
                result = results[number] = done.result
                error_plot(result, out / f"{stems[number]}.error.png")
                time_plot(result, out / f"{stems[number]}.time.png")
                _print_result(result)
            _write_results(out, *_in_capture_order(results, failed))  # as each capture finishes: nothing is lost
    rows, failures = _in_capture_order(results, failed)
    print(f"wrote {out / 'bench.csv'} ({len(rows)} rows) and figures to {out}")
    if failures:
        print(f"{len(failures)} failure(s), listed in {out / 'failures.csv'}:")
        for failure in failures:
            print(f"  {failure.capture}: {failure.method}: {failure.reason}")
        return 1
    return 0


def method_names(text: str) -> frozenset[str]:
    """argparse type: comma-separated names of `lpnn bench` methods."""
    from ..quality.placement.methods import BENCH_METHODS

    names = [name.strip() for name in text.split(",") if name.strip()]
    unknown = [name for name in names if name not in BENCH_METHODS]
    if not names or unknown:
        raise argparse.ArgumentTypeError(f"unknown method(s) {', '.join(unknown) or '(none given)'}; "
                                         f"choose from {', '.join(BENCH_METHODS)}")
    return frozenset(names)


@dataclass(frozen=True)
class BenchTask:
    """One capture to benchmark (sent to a worker)."""

    number: int
    path: Path
    config: Any  # BenchConfig
    model: str | None
    scorer_threads: int | None  # None: the scorer's default; 1 in each of several workers


def bench_one(task: BenchTask) -> Any:
    """In a worker: every method on one capture (a CaptureResult)."""
    from ..core.capture_file import read_capture
    from ..quality.bench.run import bench_capture
    from ..quality.placement.leak_aware import NO_GEOMETRY
    from ..scenes.capture_geometry import capture_raycaster
    from .errors import user_errors

    with user_errors(str(task.path)):
        capture = read_capture(task.path)
        scorer = None
        if task.model is not None:
            from ..train.onnx_scoring import OnnxScorer

            scorer = (OnnxScorer(task.model) if task.scorer_threads is None
                      else OnnxScorer(task.model, threads=task.scorer_threads))
            scorer.check_capture(capture, str(task.path))
        # The level's surfaces when the tools can load them (an OpenArena import): every row then reports its leaks,
        # and the default placement's rows avoid them.
        geometry = capture_raycaster(capture)[0]
        if geometry is None and task.config.leaks == "avoid" and task.config.wants("insertion-refined"):
            print(f"{task.path.stem}: insertion-refined: {NO_GEOMETRY}", file=sys.stderr, flush=True)
        _warm_up_once(task.config, scorer)
        return bench_capture(task.path.stem, capture, task.config, scorer, geometry=geometry)


_warmed_up = False  # in this process (each worker warms itself up once)


def _warm_up_once(config: Any, scorer: Any) -> None:
    """The first capture of a process would count numba's compilation (or the loading of its cache) and the scorer's
    graph optimisation as its methods' time: every method runs once on a synthetic room first
    (quality/bench/warmup.py)."""
    global _warmed_up
    if _warmed_up:
        return
    from ..quality.bench.warmup import warm_up_bench

    start = time.perf_counter()
    warm_up_bench(config, scorer)
    _warmed_up = True
    print(f"warm-up (every method on a synthetic room, not counted): {time.perf_counter() - start:.1f} s",
          file=sys.stderr, flush=True)


def figure_stems(files: list[Path]) -> list[str]:
    """A distinct file stem per capture, for its figures (a repeated name gets underscores, in capture order)."""
    from ..core.capture_file import safe_file_stem

    stems: list[str] = []
    for path in files:
        stem = safe_file_stem(path.stem)
        while stem in stems:
            stem += "_"
        stems.append(stem)
    return stems


def _in_capture_order(results: dict[int, Any], failed: dict[int, Any]) -> tuple[list, list]:
    rows, failures = [], []
    for number in sorted(set(results) | set(failed)):
        if number in failed:
            failures.append(failed[number])
        else:
            rows.extend(results[number].rows)
            failures.extend(results[number].failures)
    return rows, failures


def _print_result(result: Any) -> None:
    from ..core.in_use_section import in_use_text

    for row in result.rows:
        versus = (f"probes x ref {row.probes_ratio:.2f}" if row.probes_ratio is not None
                  else f"error x ref {row.error_ratio:.2f}")
        print(f"  {row.method:>18} {row.policy:>9} {row.parameter:<6g} probes {row.probes:>6,} "
              f"time {row.seconds * 1000:>10.1f} ms  mean {row.mean_error:.4f}  p95 {row.p95_error:.4f}  "
              f"in use {in_use_text(row.in_use_error)}  leaking {in_use_text(row.leaking)}  {versus}")
    for failure in result.failures:
        print(f"  FAILED {failure.method} on {failure.capture}: {failure.reason}", flush=True)


def _write_results(out: Path, rows: list, failures: list) -> None:
    from ..core.atomic import write_text_atomic
    from ..quality.bench.results import failures_csv, rows_csv

    write_text_atomic(out / "bench.csv", rows_csv(rows))
    if failures:
        write_text_atomic(out / "failures.csv", failures_csv(failures))
