#!/usr/bin/env python3
"""Guided insertion against plain insertion per capture, without a reference (benchmarks.md "The network"): the probes each
keeps at the tolerance (tau = 0.05) and its mean error at a 5 % budget, with the guide always on (the limit of
quality.md §5.2 lifted: this is the measurement the limit was chosen from). Whole TRAINING or VALIDATION levels only;
held-out levels are refused (they only report).

  lpnn scene import fan --out whole/fan.lpnncap            # whole levels, the importer's defaults
  PYTHONPATH=Training~ python Tools~/experiments/guided-vs-insertion.py whole/*.lpnncap [--model M.onnx]
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from pathlib import Path

TOOLS = Path(__file__).resolve().parent
TOLERANCE = 0.05
BUDGET = 0.05


def _ceilings():
    """score-ceilings.py's held-out refusal and defaults (one definition)."""
    spec = importlib.util.spec_from_file_location("score_ceilings", TOOLS / "score-ceilings.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(argv: list[str] | None = None) -> int:
    ceilings = _ceilings()
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("captures", nargs="+", type=Path, help="captures of training or validation levels")
    parser.add_argument("--model", type=Path, default=ceilings.DEFAULT_MODEL, help="default: the shipped model")
    parser.add_argument("--card", type=Path, default=ceilings.DEFAULT_CARD, help="the card whose held-out levels are refused")
    args = parser.parse_args(argv)
    refused = sorted({ceilings.level_of(p) for p in args.captures} & ceilings.held_out_levels(args.card))
    if refused:
        raise SystemExit(f"held-out level(s) {', '.join(refused)}: never used to select or tune (they only report)")

    from lpnn.core.capture_file import read_capture
    from lpnn.core.grid import EvaluationGrid
    from lpnn.quality.placement.insertion import InsertionOrder, guide_weights
    from lpnn.quality.metric.metric import ReferenceField, placement_error
    from lpnn.quality.placement.policies import budget_count, place_tolerance
    from lpnn.train.onnx_scoring import OnnxScorer

    scorer = OnnxScorer(args.model)
    print(f"| capture | points | insertion: probes @τ={TOLERANCE:g} | guided: probes @τ | guided / insertion @τ | "
          f"error @{BUDGET:.0%}: guided / insertion | seconds (insertion, guided) |\n|---|---|---|---|---|---|---|")
    for path in args.captures:
        capture = read_capture(path)
        field = ReferenceField.from_capture(capture)
        grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
        guide = guide_weights(scorer.score_capture(capture, path.name))
        counts, errors, seconds = [], [], []
        for weights in (None, guide):
            start = time.perf_counter()
            counts.append(place_tolerance(field, InsertionOrder(field, grid, guide=weights).selection(), TOLERANCE)
                          .indices.shape[0])
            select = InsertionOrder(field, grid, guide=weights).selection()
            errors.append(placement_error(field, select(budget_count(BUDGET, capture.point_count))).mean)
            seconds.append(time.perf_counter() - start)
        print(f"| {path.stem} | {capture.point_count:,} | {counts[0]:,} | {counts[1]:,} | {counts[1] / counts[0]:.3f} | "
              f"{errors[1] / errors[0]:.3f} | {seconds[0]:.0f}, {seconds[1]:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
