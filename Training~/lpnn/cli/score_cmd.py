"""`lpnn score CAPTURE --model M.onnx --out scores.csv`: importance of every point of a capture."""

from __future__ import annotations

import argparse


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("score", help="score every point of a capture with an ONNX model (CSV out)")
    parser.add_argument("capture", metavar="CAPTURE", help="capture file (*.lpnncap)")
    parser.add_argument("--model", required=True, metavar="MODEL.onnx", help="model with its MODEL.card.json")
    parser.add_argument("--out", required=True, metavar="SCORES.csv", help="CSV: index,i,j,k,score")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..core.capture_file import read_capture
    from ..train.onnx_scoring import OnnxScorer
    from .scores_file import write_scores_csv

    scorer = OnnxScorer(args.model)
    capture = read_capture(args.capture)
    scores = scorer.score_capture(capture, args.capture)
    write_scores_csv(args.out, capture.ids, scores)
    print(f"scored {capture.point_count:,} points (min {scores.min():.4f}, median {np.median(scores):.4f}, "
          f"max {scores.max():.4f}); wrote {args.out}")
    return 0
