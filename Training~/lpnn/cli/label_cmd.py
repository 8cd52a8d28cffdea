"""`lpnn label`: reference-placement labels for captures (Documentation~/quality.md §3).

  lpnn label CAPTURES... (--budget FRACTION | --tolerance TAU) [--method fast|faithful]
             (--out-dir DIR | --in-place) [--workers N] [--scheduler ADDRESS]

A point is positive when the reference placement keeps it: the top FRACTION of the reference
ordering, or the smallest reference prefix whose mean error is <= TAU. The capture's
`label_source` records method and parameter, e.g. "reference:fast-greedy budget=0.2". Files are
written atomically; with --out-dir an existing file is never replaced, only --in-place rewrites.
Captures are labelled side by side on --workers local processes or on the Dask cluster at --scheduler
(lpnn/core/engine.py; same labels either way). Each capture is written as soon as it is labelled; a
capture that fails (or whose worker keeps dying) is reported (path and reason) and the others go on;
the exit code is 1 when any failed.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    from ..quality.placement.policy_rules import REFERENCE_METHODS
    from .arguments import add_engine_arguments, add_policy_arguments

    parser = subparsers.add_parser("label", help="label captures with an error-driven reference placement",
                                   description="Write reference-placement labels into captures (quality.md).")
    parser.add_argument("captures", nargs="+", metavar="CAPTURE", help="capture files or dataset folders")
    add_policy_arguments(parser)
    parser.add_argument("--method", choices=REFERENCE_METHODS, default="fast",
                        help="fast (exact greedy with local updates, default) or faithful (LumiProbes' "
                             "exhaustive loop, <= 200 points)")
    output = parser.add_mutually_exclusive_group(required=True)
    output.add_argument("--out-dir", metavar="DIR", help="write labelled copies here (never replaces a file)")
    output.add_argument("--in-place", action="store_true", help="rewrite each capture in place (atomically)")
    add_engine_arguments(parser, "the captures")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from ..core.capture_file import dataset_files
    from ..core.engine import Engine
    from ..quality.bench.results import failure_reason
    from .arguments import engine_and_inner_workers
    from ..quality.placement.policies import reference_label_source
    from ..errors import UserError

    files = dataset_files(args.captures)
    if not files:
        raise UserError("no capture files found in " + ", ".join(args.captures))
    out_dir = None if args.in_place else Path(args.out_dir)
    if out_dir is not None:
        names = [f.name for f in files]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise UserError(f"several inputs are named {duplicates[0]!r}; label them into separate --out-dir folders")
        taken = [out_dir / n for n in names if (out_dir / n).exists()]
        if taken:
            raise UserError(f"{taken[0]} exists; choose an empty --out-dir or use --in-place (nothing was written)")
    source = reference_label_source(args.method, args.budget, args.tolerance)
    engine_workers, inner_workers = engine_and_inner_workers(args, len(files))
    options = LabelOptions(args.method, args.budget, args.tolerance, source, out_dir, inner_workers,
                           quiet=args.quiet or engine_workers > 1 or args.scheduler is not None)
    failed: list[tuple[Path, str]] = []
    with Engine(engine_workers, args.scheduler) as engine:
        for number, done in enumerate(engine.unordered(_label_one, [(path, options) for path in files]), start=1):
            path = done.task[0]
            if done.error is None:
                print(f"[{number}/{len(files)}] {done.result}", flush=True)
            else:  # reported; the other captures go on
                failed.append((path, failure_reason(done.error)))
                print(f"[{number}/{len(files)}] FAILED {path}: {failed[-1][1]}", file=sys.stderr, flush=True)
    if failed and len(files) > 1:
        print(f"{len(failed)} of {len(files)} capture(s) failed and were not labelled: "
              + ", ".join(str(path) for path, _ in sorted(failed)), file=sys.stderr)
    return 1 if failed else 0


@dataclass(frozen=True)
class LabelOptions:
    """What every capture is labelled with (sent to the workers)."""

    method: str
    budget: float | None
    tolerance: float | None
    source: str
    out_dir: Path | None
    workers: int  # processes of one fast reference
    quiet: bool


def _label_one(task: tuple[Path, LabelOptions]) -> str:
    """In a worker: label one capture and write it (atomically, never replacing a file with --out-dir); returns
    what to print."""
    from .errors import user_errors

    path, options = task
    with user_errors(str(path)):
        return _label_capture(path, options)


def _label_capture(path: Path, options: LabelOptions) -> str:
    import numpy as np

    from ..core.atomic import write_new_atomic
    from ..core.capture_encoder import encode_capture
    from ..core.capture_file import read_capture, write_capture
    from ..quality.placement.reference import run_reference
    from .progress import progress_bar
    from ..quality.metric.metric import ReferenceField
    from ..quality.placement.policies import budget_count, reference_count, reference_tolerance
    from ..errors import UserError

    capture = read_capture(path)
    field = ReferenceField.from_capture(capture)
    update, close = progress_bar(f"{path.name}: {options.method} reference", disable=options.quiet)
    try:
        decimation = run_reference(field, options.method, str(path), options.workers, update)
    finally:
        close()
    if options.budget is not None:
        placement = reference_count(decimation, budget_count(options.budget, field.point_count))
    else:
        placement = reference_tolerance(decimation, options.tolerance)
    labels = np.zeros(field.point_count, dtype=np.uint8)
    labels[placement.indices] = 1
    labelled = capture.with_labels(labels, options.source)
    if options.out_dir is None:
        target = write_capture(path, labelled)
    else:
        target = options.out_dir / path.name
        data = encode_capture(labelled)
        if not write_new_atomic(target, lambda handle: handle.write(data)):
            raise UserError(f"{target} appeared while labelling; nothing was replaced")
    return (f"{path}: {placement.indices.shape[0]:,} of {field.point_count:,} points positive "
            f"(mean error {placement.mean_error:.4g}, {decimation.seconds:.1f} s) -> {target}")
