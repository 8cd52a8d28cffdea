"""`lpnn model info|check|bench`: inspect, verify and time ONNX models."""

from __future__ import annotations

import argparse
import json
import os


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("model", help="inspect (info), verify (check) or time (bench) an ONNX model")
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)

    info = actions.add_parser("info", help="print the model card")
    info.add_argument("model", metavar="MODEL.onnx")
    info.set_defaults(handler=run_info)

    check = actions.add_parser("check", help="op check, card vs graph, sanity runs (and scores of captures)")
    check.add_argument("model", metavar="MODEL.onnx")
    check.add_argument("--capture", nargs="+", default=[], metavar="CAPTURE",
                       help="also score these captures (schema checked; ROC/PR-AUC when labelled)")
    check.set_defaults(handler=run_check)

    bench = actions.add_parser("bench", help="onnxruntime scoring time (1k/10k/100k points) and training throughput")
    bench.add_argument("model", nargs="?", metavar="MODEL.onnx",
                       help="model to time (default: the default architecture, untrained)")
    bench.add_argument("--sizes", nargs="+", type=int, default=None, metavar="N", help="cloud sizes (default 1000 10000 100000)")
    bench.add_argument("--repeats", type=int, default=15, help="timed runs per size (median reported)")
    bench.add_argument("--threads", type=int, default=2, help="onnxruntime intra-op threads")
    bench.add_argument("--train-steps", type=int, default=30, help="timed training steps (0: skip training)")
    bench.add_argument("--no-thesis", action="store_true", help="skip the thesis-size network for comparison")
    bench.set_defaults(handler=run_bench)


def run_info(args: argparse.Namespace) -> int:
    from ..train.modelcard import ModelCard, card_path

    print(ModelCard.read(card_path(args.model)).to_json(), end="")
    return 0


def run_check(args: argparse.Namespace) -> int:
    from ..train.model_check import check_model_file
    from ..train.modelcard import json_ready

    report = check_model_file(args.model, args.capture)
    print(json.dumps(json_ready(report), indent=2))
    print(f"{args.model}: ok")
    return 0


def run_bench(args: argparse.Namespace) -> int:
    from ..errors import UserError
    from ..train.benchmark import DEFAULT_SIZES, format_report, scoring_benchmark, training_throughput

    sizes = tuple(args.sizes) if args.sizes else DEFAULT_SIZES
    if args.repeats < 1 or args.threads < 1 or args.train_steps < 0 or min(sizes) < 1:
        raise UserError("--repeats, --threads and --sizes must be >= 1 and --train-steps >= 0")
    load_before = os.getloadavg()[0]
    # Training first: TensorFlow fixes its thread pools at its first op (the export of the timed models).
    training = training_throughput(args.train_steps) if args.train_steps else None
    rows = scoring_benchmark(args.model, sizes, args.repeats, args.threads, compare_thesis=not args.no_thesis)
    print(format_report(rows, training, args.threads, args.repeats))
    # Other processes on the same cores slow multi-threaded runs a lot: say how busy the machine was.
    print(f"load average (1 min): {load_before:.2f} before, {os.getloadavg()[0]:.2f} after; "
          f"{os.cpu_count()} CPU cores")
    return 0
