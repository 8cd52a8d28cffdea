#!/usr/bin/env python3
"""A network trained on the default's own answers as the default's seed (issue #30 item 2; benchmarks.md "The network",
"A network trained on the default's answers, as its seed").

The default (`insertion-refined`, quality.md §5.3) runs insertion rounds and the tolerance search up to ~2 K0 points,
then refines 2 K0 points down in batches. The idea measured here: a network that predicts which points the default
keeps gives a seed near its answer, so insertion continues from the seed instead of from 12 points (the rounds below
it are skipped) and the refinement starts near its end. Three steps, each a sub-command:

  labels WHOLE.lpnncap ... --out DIR   the default at tau on whole levels (leak-aware as `lpnn place` runs it, or
                                        --leaks ignore); per point 1 = kept; written as labelled tiles of at most
                                        --tile points (the trainer's clouds), plus DIR/answers.json (the default's
                                        probes, seconds per level)
  lpnn train TRAIN_DIR --val VAL_DIR/*.lpnncap --out seed.onnx --config options.json
                                        the ordinary trainer on the training levels' tiles, selected on the
                                        validation levels' tiles (benchmarks.md gives the options used)
  compare CAPTURE ... --model seed.onnx  per capture: the default and the seeded default, probes at tau, mean error
                                        (a fresh evaluation), seconds; the seed is the --factor x (expected kept
                                        count) points the network ranks highest, its expected count being the sum of
                                        its calibrated probabilities (the trainer weighs positives by the card's
                                        positive_weight w: p_true = p / (p + w (1 - p)))
  place CAPTURE --model seed.onnx       the seeded default alone; with --unseeded instead of --model the default,
                                        through the same reading and evaluation (`paired-time.py` compares the two)

The seeded default = refined_insertion(field, grid, tolerance=tau, head=seed, refine=F): insertion starts from its
usual start plus the seed, the tolerance search from the seed's count (so K0 >= the seed), and the refinement from
F x K0 points. Scores are taken per tile of at most --tile points (the network was trained on such clouds and pools
over the whole cloud). Held-out levels (the shipped card's) are refused by every sub-command: they only report.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import time
from pathlib import Path

import numpy as np

from lpnn.quality.placement.policy_rules import DEFAULT_TOLERANCE  # math only: --help stays quick

TOOLS = Path(__file__).resolve().parent
TOLERANCE = DEFAULT_TOLERANCE  # the default's tau (lpnn place, bench, the editor), whose answers label the points
TILE_POINTS = 4096  # the trainer's max_points: the clouds the network was trained on
SEED_FACTOR = 1.0  # seed = this x the network's expected kept count (chosen on validation: benchmarks.md)
REFINE_FACTOR = 1.2  # the refinement starts from this x K0 points (the default's own: 2)
MIN_SEED = 4  # points at least in a seed: the tolerance search's own smallest count (insertion.InsertionOrder)


def _ceilings():
    """score-ceilings.py's held-out refusal and defaults (one definition)."""
    spec = importlib.util.spec_from_file_location("score_ceilings", TOOLS / "score-ceilings.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def refuse_held_out(paths: list[Path], card: Path) -> None:
    ceilings = _ceilings()
    refused = sorted({ceilings.level_of(p) for p in paths} & ceilings.held_out_levels(card))
    if refused:
        raise SystemExit(f"held-out level(s) {', '.join(refused)}: never used to train, select or tune (they only report)")


def tiles(ids: np.ndarray, max_points: int) -> list[np.ndarray]:
    """Point indices of boxes of at most `max_points` points covering every point once: the points split at the median
    of their longest lattice axis, recursively (boxes, not scattered subsets: the network pools over a neighbourhood)."""
    pending, done = [np.arange(ids.shape[0])], []
    while pending:
        part = pending.pop()
        if part.shape[0] <= max_points:
            done.append(part)
            continue
        coordinates = ids[part]
        axis = int(np.argmax(coordinates.max(axis=0) - coordinates.min(axis=0)))
        order = part[np.argsort(coordinates[:, axis], kind="stable")]
        half = order.shape[0] // 2
        pending += [np.sort(order[:half]), np.sort(order[half:])]
    return sorted(done, key=lambda part: int(part[0]))


def kept_probabilities(scorer, capture, tile_points: int) -> np.ndarray:
    """(N,) the network's probability that the default keeps each point, scored per tile and calibrated for the
    trainer's positive weight w (weighted BCE trains the odds w times too high: p / (p + w (1 - p)))."""
    weight = float(scorer.card.training["positive_weight"])
    scores = np.empty(capture.point_count, dtype=np.float64)
    for part in tiles(np.asarray(capture.ids), tile_points):
        scores[part] = scorer.score(np.asarray(capture.features[part], dtype=np.float32))
    return scores / (scores + weight * (1.0 - scores))


def network_seed(probabilities: np.ndarray, factor: float) -> np.ndarray:
    """The round(factor x sum p) likeliest points (at least MIN_SEED, at most all), likeliest first (ties: lower
    index)."""
    count = min(probabilities.shape[0], max(MIN_SEED, int(round(factor * float(probabilities.sum())))))
    return np.lexsort((np.arange(probabilities.shape[0]), -probabilities))[:count]


def _default(field, grid, tolerance: float, leaks, head=None, refine=None):
    from lpnn.quality.placement.refined_insertion import RECOMMENDED_REFINE, refined_insertion

    return refined_insertion(field, grid, tolerance=tolerance, leaks=leaks, head=head,
                             refine=RECOMMENDED_REFINE if refine is None else refine)


def _field(path: Path, leaks: str):
    from lpnn.core.capture_file import read_capture
    from lpnn.core.grid import EvaluationGrid
    from lpnn.quality.metric.leaks import field_with_geometry
    from lpnn.quality.placement.leak_aware import leaks_to_avoid

    capture = read_capture(path)
    field = field_with_geometry(capture)
    return capture, field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids), leaks_to_avoid(field, leaks)


def labels(args: argparse.Namespace) -> int:
    from lpnn.core.capture_file import write_capture
    from lpnn.core.validity import without_invalid

    refuse_held_out(args.captures, args.card)
    args.out.mkdir(parents=True, exist_ok=True)
    answers_path = args.out / "answers.json"
    answers = json.loads(answers_path.read_text(encoding="utf-8")) if answers_path.exists() else {}
    source = f"default:insertion-refined tolerance={args.tolerance:g} leaks={args.leaks}"
    for path in args.captures:
        capture, field, grid, leaks = _field(path, args.leaks)
        start = time.perf_counter()
        answer = _default(field, grid, args.tolerance, leaks)
        seconds = time.perf_counter() - start
        kept = np.zeros(capture.point_count, dtype=np.uint8)
        kept[answer.indices] = 1
        written = 0
        for number, part in enumerate(tiles(np.asarray(capture.ids), args.tile)):
            if part.shape[0] < args.min_tile or kept[part].min() == kept[part].max():
                continue  # too small to train on, or one class only (no ranking to learn there)
            inside = np.zeros(capture.point_count, dtype=bool)
            inside[part] = True
            write_capture(args.out / f"{path.stem}__t{number}.lpnncap",
                          without_invalid(capture, inside).with_labels(kept[part], source))
            written += 1
        answers[path.stem] = {"points": capture.point_count, "probes": int(answer.indices.shape[0]),
                              "mean_error": round(answer.mean_error, 6), "seconds": round(seconds, 2), "tiles": written}
        print(f"{path.stem}: {capture.point_count:,} points, the default keeps {answer.indices.shape[0]:,} "
              f"({answer.mean_error:.4f}) in {seconds:.1f} s; {written} labelled tiles", flush=True)
    answers_path.write_text(json.dumps(answers, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    return 0


def _seeded(scorer, capture, field, grid, leaks, args, oracle=None):
    """The seeded default: (placement, seed size, seconds of scoring, seconds in all). `oracle` (the default's answer):
    the seed is that answer itself, the best a network could predict (no scoring)."""
    start = time.perf_counter()
    if oracle is None:
        seed = network_seed(kept_probabilities(scorer, capture, args.tile), args.factor)
    else:
        probabilities = np.zeros(capture.point_count)
        probabilities[oracle] = 1.0
        seed = network_seed(probabilities, 1.0)
    scoring = time.perf_counter() - start
    placed = _default(field, grid, args.tolerance, leaks, head=seed, refine=args.refine)
    return placed, int(seed.shape[0]), scoring, time.perf_counter() - start


def _where_the_time_goes(placed) -> str:
    """compare's last columns: the count the refinement started from, insertion's rounds, seconds of insertion and the
    tolerance search + seconds of refinement."""
    return (f"{placed.seed_count:,}, {placed.rounds}, {placed.selection_seconds:.1f} + "
            f"{placed.refinement_seconds:.1f}")


def compare(args: argparse.Namespace) -> int:
    from lpnn.quality.metric.metric import mean_placement_error
    from lpnn.train.onnx_scoring import OnnxScorer

    refuse_held_out(args.captures, args.card)
    scorer = None if args.oracle else OnnxScorer(args.model)
    seeded_by = "the default's answer" if args.oracle else f"factor {args.factor:g}"
    print(f"| capture | points | default: probes @τ={args.tolerance:g} | error | s | seeded ({seeded_by}, "
          f"refine {args.refine:g}): seed | probes | error | s (scoring) | probes ×default | s ×default | "
          "default: refined from, rounds, s insertion + refinement | seeded: the same |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    ratios = []
    for path in args.captures:
        capture, field, grid, leaks = _field(path, args.leaks)
        start = time.perf_counter()
        default = _default(field, grid, args.tolerance, leaks)
        default_seconds = time.perf_counter() - start
        seeded, seed_size, scoring, seconds = _seeded(scorer, capture, field, grid, leaks, args,
                                                      default.indices if args.oracle else None)
        # A fresh evaluation of both answers (the placement's own errors are incremental ones).
        errors = [mean_placement_error(field, placed.indices) for placed in (default, seeded)]
        counts = [int(placed.indices.shape[0]) for placed in (default, seeded)]
        ratios.append((counts[1] / counts[0], seconds / default_seconds))
        print(f"| {path.stem} | {capture.point_count:,} | {counts[0]:,} | {errors[0]:.4f} | {default_seconds:.2f} | "
              f"{seed_size:,} | {counts[1]:,} | {errors[1]:.4f} | {seconds:.2f} ({scoring:.2f}) | {ratios[-1][0]:.3f} | "
              f"{ratios[-1][1]:.2f} | {_where_the_time_goes(default)} | {_where_the_time_goes(seeded)} |", flush=True)
    mean = np.exp(np.log(np.asarray(ratios)).mean(axis=0))
    print(f"geometric mean over {len(ratios)} captures: probes ×default {mean[0]:.3f}, seconds ×default {mean[1]:.2f}")
    return 0


def place(args: argparse.Namespace) -> int:
    from lpnn.quality.metric.metric import mean_placement_error
    from lpnn.train.onnx_scoring import OnnxScorer

    refuse_held_out([args.capture], args.card)
    capture, field, grid, leaks = _field(args.capture, args.leaks)
    if args.unseeded:  # the default itself, through the same reading and evaluation (paired-time.py's other command)
        placed, seed_size, scoring = _default(field, grid, args.tolerance, leaks), 0, 0.0
    else:
        placed, seed_size, scoring, _ = _seeded(OnnxScorer(args.model), capture, field, grid, leaks, args)
    print(f"{args.capture.name}: {placed.indices.shape[0]:,} probes from a seed of {seed_size:,}, mean error "
          f"{mean_placement_error(field, placed.indices):.4f}; scoring {scoring:.2f} s, insertion and search "
          f"{placed.selection_seconds:.2f} s, refinement {placed.refinement_seconds:.2f} s ({placed.rounds} rounds)")
    return 0


def main(argv: list[str] | None = None) -> int:
    ceilings = _ceilings()
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True)
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--tolerance", type=float, default=TOLERANCE)
    common.add_argument("--leaks", choices=("avoid", "ignore"), default="avoid", help="as lpnn place's --leaks")
    common.add_argument("--tile", type=int, default=TILE_POINTS, help="points per tile at most")
    common.add_argument("--card", type=Path, default=ceilings.DEFAULT_CARD, help="the card whose held-out levels are refused")
    labelling = commands.add_parser("labels", parents=[common], help="the default's answers as labelled tiles")
    labelling.add_argument("captures", nargs="+", type=Path)
    labelling.add_argument("--out", type=Path, required=True)
    labelling.add_argument("--min-tile", type=int, default=64, help="smaller tiles are not written (the trainer's min_points)")
    seeded = argparse.ArgumentParser(add_help=False)
    seeded.add_argument("--model", type=Path, help="a network trained on `labels`' tiles")
    seeded.add_argument("--factor", type=float, default=SEED_FACTOR, help="seed = factor x the expected kept count")
    seeded.add_argument("--refine", type=float, default=REFINE_FACTOR, help="the refinement's seed: this x K0 points")
    comparing = commands.add_parser("compare", parents=[common, seeded], help="the default against the seeded default")
    comparing.add_argument("captures", nargs="+", type=Path)
    comparing.add_argument("--oracle", action="store_true",
                           help="seed with the default's own answer (the ceiling of any network; --model unused)")
    placing = commands.add_parser("place", parents=[common, seeded], help="the seeded default on one capture")
    placing.add_argument("capture", type=Path)
    placing.add_argument("--unseeded", action="store_true",
                         help="the default itself (no network), for timing against the seeded one; --model unused")
    args = parser.parse_args(argv)
    if args.command != "labels" and args.model is None and not (getattr(args, "oracle", False)
                                                                 or getattr(args, "unseeded", False)):
        parser.error(f"{args.command} needs --model (a network trained on the labels' tiles)"
                     + (" or --oracle" if args.command == "compare" else " or --unseeded"))
    return {"labels": labels, "compare": compare, "place": place}[args.command](args)


if __name__ == "__main__":
    sys.exit(main())
