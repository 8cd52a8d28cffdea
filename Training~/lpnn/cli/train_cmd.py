"""`lpnn train DATASET... --out model.onnx`: captures -> trained, checked ONNX model + model card."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "train",
        help="train the importance model on labelled captures and export it (ONNX + model card)",
        description="Train on labelled captures (one capture = one cloud), validate on held-out captures, "
                    "export an ONNX model that passed the op check and the parity check, with its model card. "
                    "See Documentation~/training.md.",
    )
    parser.add_argument("datasets", nargs="+", metavar="DATASET", help="capture files or dataset folders")
    parser.add_argument("--out", required=True, metavar="MODEL.onnx", help="model to write (card: MODEL.card.json)")
    parser.add_argument("--val", nargs="+", default=[], metavar="CAPTURE",
                        help="held-out captures (default: a seeded fraction of the dataset's captures)")
    parser.add_argument("--seed", type=int, help="random seed (split, initialisation, batches); default 0")
    parser.add_argument("--epochs", type=int, help="maximum epochs (early stopping may end sooner)")
    parser.add_argument("--config", metavar="CONFIG.json", help="training options as JSON (see training.md)")
    parser.add_argument("--checkpoint", metavar="PATH.ckpt.npz",
                        help="best-weights checkpoint (default: MODEL.ckpt.npz beside the model)")
    parser.add_argument("--metric", action="append", default=[], metavar="MODULE:ATTR",
                        help="extra validation metric (a lpnn.train.metrics.CaptureMetric); repeatable")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from ..train.baselines import baselines
    from ..train.checkpoint import default_checkpoint_path
    from ..train.config import TrainConfig, config_from_dict, load_config
    from ..train.diagnostics import is_settled
    from ..train.metrics import load_metric_plugins
    from ..train.modelcard import card_path
    from ..train.pipeline import train_and_export

    config = load_config(args.config) if args.config else TrainConfig()
    overrides = {name: getattr(args, name) for name in ("seed", "epochs") if getattr(args, name) is not None}
    config = config_from_dict(overrides, base=config, where="command line")
    metrics = load_metric_plugins(args.metric)
    checkpoint = Path(args.checkpoint) if args.checkpoint else default_checkpoint_path(args.out)
    run_info = train_and_export(args.datasets, args.out, config, checkpoint, args.val, metrics,
                                progress=not args.quiet)
    result, card = run_info.result, run_info.card
    validation = card.metrics["validation"]
    print(f"trained on {len(result.split.train)} capture(s), validated on {len(result.split.validation)} "
          f"({', '.join(c.name for c in result.split.validation)}); best epoch {result.best_epoch} of "
          f"{result.epochs_run}{' (early stop)' if result.stopped_early else ''}, {result.seconds:.1f} s")
    print("validation: " + ", ".join(f"{k} {validation[k]:.4f}" for k in ("roc_auc", "pr_auc", "roc_auc_mean", "pr_auc_mean")
                                     if isinstance(validation.get(k), float)))
    print(_yardsticks(validation.get("roc_auc"), baselines(result.split.train, result.split.validation, config.seed)))
    batchnorm = card.training["batchnorm_check"]
    print(f"BatchNorm running stats vs data: max mean shift {batchnorm['max_mean_shift']:.3f} std, "
          f"max |log variance ratio| {batchnorm['max_abs_log_variance_ratio']:.3f}"
          + ("" if is_settled(batchnorm) else " -- NOT settled: train longer (more steps or epochs)"))
    print(f"parity onnxruntime vs Keras: max abs diff {card.parity['max_abs_diff']:.2e}; ops: {', '.join(card.ops)}")
    for note in result.notes:
        print(f"note: {note}")
    print(f"wrote {run_info.model_path}, {card_path(run_info.model_path)}, {run_info.checkpoint_path}")
    return 0


MARGIN_OVER_BASELINES = 0.01  # ROC-AUC the network should gain over the simple rules to be worth its cost


def _yardsticks(network: object, base: Any) -> str:
    """One line: the network's validation ROC-AUC beside the best single feature's and a logistic regression's."""
    line = (f"yardsticks on the validation points (ROC-AUC): network {network:.4f}; best single feature "
            f"{base.feature} ({'higher' if base.feature_sign > 0 else 'lower'} = needs a probe) "
            f"{base.feature_roc_auc:.4f}; logistic regression on the features {base.logistic_roc_auc:.4f}"
            if isinstance(network, float) else "yardsticks: no validation ROC-AUC (a validation set with one class)")
    if isinstance(network, float) and network < max(base.feature_roc_auc, base.logistic_roc_auc) + MARGIN_OVER_BASELINES:
        line += " -- the network does not beat these simple rules: more or more varied training captures may help"
    return line
