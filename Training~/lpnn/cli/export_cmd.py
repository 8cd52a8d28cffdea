"""`lpnn export CHECKPOINT --out model.onnx`: a training checkpoint -> checked ONNX model + card."""

from __future__ import annotations

import argparse


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "export",
        help="export a training checkpoint (.ckpt.npz) to ONNX with op check, parity check and model card",
    )
    parser.add_argument("checkpoint", metavar="CHECKPOINT", help="checkpoint written by `lpnn train`")
    parser.add_argument("--out", required=True, metavar="MODEL.onnx", help="model to write (card: MODEL.card.json)")
    parser.add_argument("--data", nargs="+", default=[], metavar="CAPTURE",
                        help="captures (or folders) whose features join the parity check as real inputs")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from ..train.modelcard import card_path
    from ..train.pipeline import export_checkpoint

    card = export_checkpoint(args.checkpoint, args.out, args.data)
    print(f"parity onnxruntime vs Keras: max abs diff {card.parity['max_abs_diff']:.2e}; ops: {', '.join(card.ops)}")
    print(f"wrote {args.out}, {card_path(args.out)}")
    return 0
