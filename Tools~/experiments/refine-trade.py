#!/usr/bin/env python3
"""guided-exact-refined's speed/accuracy trade by seed factor (benchmarks.md "The speed/accuracy trade, every method"; Documentation~/methods.md: `lpnn place`
fixes F = 2, this calls the Python API with each F): per capture and policy (budgets and the tolerance), guided
(factor 1: no refinement) and `lpnn_placement(..., refine=F)` for each F, as ratios to the
fast reference (error at a budget, probes at tau) and as fractions of the reference's time (selection + refinement
against the full reference in the same process; each timed `--repeats` times, the fastest run kept).

  PYTHONPATH=Training~ python Tools~/experiments/refine-trade.py crops/*.lpnncap [--factors 1.1,1.25,1.5,2] [--repeats 2]

Prints one JSON line per capture x policy x factor as it goes, then a table of geometric means (largest ratio in
brackets; non-finite or zero ratios left out and counted) and of the median and largest time fraction. The factor is chosen on validation crops; held-out crops report.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from collections import defaultdict
from pathlib import Path

from lpnn.cli.arguments import numbers

TOLERANCE = 0.05
DEFAULT_FACTORS = "1.1,1.25,1.5,2"
DEFAULT_BUDGETS = "0.01,0.05,0.1,0.2,0.3"
DEFAULT_MODEL = Path(__file__).resolve().parents[2] / "Packages/com.lpnn.probes/Models/lpnn_default.onnx"


def _fastest(function, repeats: int):
    """(last result, fastest wall time in seconds) of `repeats` runs."""
    best, result = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return result, best


def measure(path: Path, scorer, factors: tuple[float, ...], budgets: tuple[float, ...], repeats: int) -> list[dict]:
    from lpnn.core.capture_file import read_capture
    from lpnn.quality.placement.lpnn_placement import lpnn_placement
    from lpnn.quality.metric.metric import ReferenceField, guarded_ratio, mean_placement_error
    from lpnn.quality.placement.policies import budget_count, reference_count, reference_tolerance
    from lpnn.quality.placement.decimation.reference_fast import fast_decimation

    capture = read_capture(path)
    field = ReferenceField.from_capture(capture)
    scores = scorer.score_capture(capture, path.name)
    reference, reference_seconds = _fastest(lambda: fast_decimation(field, workers=1), repeats)
    reference_probes = reference_tolerance(reference, TOLERANCE).indices.shape[0]  # the same for every factor
    rows = []
    for budget in [*budgets, None]:
        for factor in [1.0, *factors]:
            runs = [lpnn_placement(capture, scores=scores, budget=budget, tolerance=None if budget else TOLERANCE,
                                   refine=None if factor == 1.0 else factor, guided=factor == 1.0, reference=field,
                                   full_ranking=False, report=False) for _ in range(repeats)]
            placement = runs[-1]
            seconds = min(run.timing.selection + (run.timing.refinement or 0.0) for run in runs)  # the fastest run
            if budget is not None:
                count = budget_count(budget, capture.point_count)
                ratio = guarded_ratio(mean_placement_error(field, placement.indices),
                                      reference_count(reference, count).mean_error)
            else:
                ratio = guarded_ratio(placement.indices.shape[0], reference_probes)
            rows.append(dict(capture=path.stem, points=capture.point_count, budget=budget, factor=factor,
                             ratio=ratio, seconds=seconds, reference_seconds=reference_seconds,
                             probes=int(placement.indices.shape[0])))
            print(json.dumps(rows[-1]), flush=True)
    return rows


def table(rows: list[dict], factors: tuple[float, ...], budgets: tuple[float, ...]) -> str:
    from lpnn.quality.metric.metric import guarded_ratio
    from lpnn.recipe.evaluation import geometric_mean

    ratios, fractions = defaultdict(list), defaultdict(list)
    for row in rows:
        key = (row["factor"], row["budget"])
        ratios[key].append(row["ratio"])
        fractions[key].append(guarded_ratio(row["seconds"], row["reference_seconds"]))
    policies = [*budgets, None]
    names = [f"{b:.0%}" if b is not None else f"τ={TOLERANCE:g} (probes)" for b in policies]
    lines = ["| factor | " + " | ".join(f"×ref @{name}" for name in names) + " | time / reference: median (largest) |",
             "|---" * (len(policies) + 2) + "|"]
    for factor in [1.0, *factors]:
        cells = []
        for policy in policies:
            values = ratios[(factor, policy)]
            mean, left_out = geometric_mean(values)
            cells.append(f"{mean:.2f} ({max(values):.2f})" + (f" [{left_out} left out]" if left_out else ""))
        spent = [f for policy in policies for f in fractions[(factor, policy)]]
        label = "1 (guided, no refinement)" if factor == 1.0 else f"{factor:g}"
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {statistics.median(spent):.2f} ({max(spent):.2f}) |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("captures", nargs="+", type=Path)
    parser.add_argument("--model", type=Path, default=DEFAULT_MODEL, help="default: the shipped model")
    parser.add_argument("--factors", type=numbers, default=numbers(DEFAULT_FACTORS), help="seed factors > 1")
    parser.add_argument("--budgets", type=numbers, default=numbers(DEFAULT_BUDGETS), help="budget fractions")
    parser.add_argument("--repeats", type=int, default=2, help="timed runs of each row and of the reference (fastest)")
    args = parser.parse_args(argv)
    if any(not (f > 1.0 and math.isfinite(f)) for f in args.factors):
        listed = ",".join(f"{f:g}" for f in args.factors)
        raise SystemExit(f"--factors {listed}: every factor must be > 1 (the seed holds F x K points)")
    if any(not (0.0 < b <= 1.0) for b in args.budgets) or args.repeats < 1:
        raise SystemExit("--budgets must be fractions in (0, 1] and --repeats >= 1")

    from lpnn.train.onnx_scoring import OnnxScorer

    scorer = OnnxScorer(args.model)
    rows = [row for path in args.captures for row in measure(path, scorer, args.factors, args.budgets, args.repeats)]
    print(f"\n{len(args.captures)} captures\n" + table(rows, args.factors, args.budgets))
    return 0


if __name__ == "__main__":
    sys.exit(main())
