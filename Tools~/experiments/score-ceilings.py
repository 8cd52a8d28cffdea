#!/usr/bin/env python3
"""How far can per-point scores carry a placement? Ceilings measured with the reference's own ranking as the "perfect
network" (benchmarks.md 'The network', quality.md §5.2), on crops of TRAINING or VALIDATION levels (held-out levels are refused:
they only report).

  PYTHONPATH=Training~ python Tools~/experiments/recipe-crops.py --role validation --crops 4 --out crops/
  PYTHONPATH=Training~ python Tools~/experiments/score-ceilings.py crops/*.lpnncap [--model M.onnx] [--workers 2]

For every crop, the fast reference (quality.md §3.2) gives every point's rank r (0 = kept longest); the "oracle
score" is 1 - r / N, whose top-K IS the reference's placement at every K. Rankings compared (error at 1/5/10/20/30 %
budgets as a ratio to the reference's at the same count, probes at tau = 0.05 as a ratio to its smallest count;
geometric means over crops):
- insertion, and insertion guided by the model's scores (the `guided` tier), by the oracle score (through the
  same weights, sqrt(score / median): a network's output range) and by the oracle importance N / (r + 1) (weights
  sqrt(importance / median), up to sqrt(2N): the ceiling of guiding);
- the spread ranking (selection.md) of the model's scores (exponent 0.5, the `lpnn` tier) and of the oracle score
  (exponents 0.5, 4, 8: larger exponents follow the scores more, 0 is plain farthest-point sampling);
- the spread ranking of a smoothed oracle: the reference's local probe density (the fraction of points kept within
  1.5 x the budget's typical spacing, geometric mean over the five budgets), what a network predicting "how many
  probes belong here" could learn at best.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

DEFAULT_CARD = Path(__file__).resolve().parents[2] / "Packages" / "com.lpnn.probes" / "Models" / "lpnn_default.card.json"
DEFAULT_MODEL = DEFAULT_CARD.with_name("lpnn_default.onnx")
BUDGETS = (0.01, 0.05, 0.1, 0.2, 0.3)
TOLERANCE = 0.05


def held_out_levels(card_path: Path) -> set[str]:
    card = json.loads(card_path.read_text(encoding="utf-8"))
    try:
        return set(card["training"]["recipe"]["levels"]["held_out"])
    except (KeyError, TypeError):
        raise SystemExit(f"{card_path}: the card has no training.recipe.levels split") from None


def level_of(path: Path) -> str:
    return path.stem.split("@")[0]


def density_oracle(positions: np.ndarray, rank: np.ndarray, cell: float) -> np.ndarray:
    """Geometric mean over the budgets of (fraction of points within 1.5 x the budget's spacing that the reference keeps
    at that budget) / budget; a floor of half a point in a 3 x 3 x 3 block keeps empty neighbourhoods finite."""
    from scipy.spatial import cKDTree

    from lpnn.quality.placement.policies import budget_count

    tree = cKDTree(positions)
    n = rank.shape[0]
    log_density = np.zeros(n)
    for budget in BUDGETS:
        kept = (rank < budget_count(budget, n)).astype(np.float64)
        radius = 1.5 * cell * budget ** (-1.0 / 3.0)
        neighbours = tree.query_ball_point(positions, radius)
        fraction = np.array([kept[list_].mean() for list_ in neighbours])
        log_density += np.log((fraction + 0.5 / 27.0) / budget)
    density = np.exp(log_density / len(BUDGETS))
    return density / density.max()


def crop_ratios(task: tuple[str, str | None]) -> dict[str, list[float]]:
    """Every ranking's ratios on one crop (runs in a worker)."""
    from lpnn.core.capture_file import read_capture
    from lpnn.core.grid import EvaluationGrid
    from lpnn.core.spread import spread_ranking
    from lpnn.quality.placement.insertion import guide_weights, insertion_ranking
    from lpnn.quality.metric.metric import ReferenceField, placement_error
    from lpnn.quality.placement.policies import budget_count, place_tolerance, prefix_selection, reference_tolerance
    from lpnn.quality.placement.decimation.reference_fast import fast_decimation

    path, model = task
    capture = read_capture(path)
    field = ReferenceField.from_capture(capture)
    grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
    n = capture.point_count
    reference = fast_decimation(field, workers=1)
    rank = np.empty(n, dtype=np.int64)
    rank[reference.ordering] = np.arange(n)
    oracle = 1.0 - rank / n
    importance = n / (rank + 1.0)  # heavy-tailed: the last survivors weigh up to N times the median point
    positions = capture.positions
    rankings = {
        "insertion": insertion_ranking(field, grid),
        "insertion guided by the oracle score": insertion_ranking(field, grid, guide=guide_weights(oracle)),
        "insertion guided by the oracle importance": insertion_ranking(field, grid, guide=np.sqrt(importance / np.median(importance))),
        "spread of the oracle, exponent 0.5": spread_ranking(positions, oracle, 0.5),
        "spread of the oracle, exponent 4": spread_ranking(positions, oracle, 4.0),
        "spread of the oracle, exponent 8": spread_ranking(positions, oracle, 8.0),
        "spread of the density oracle": spread_ranking(positions, density_oracle(positions.astype(np.float64), rank,
                                                                                 capture.cell_size), 0.5),
    }
    if model is not None:
        from lpnn.train.onnx_scoring import OnnxScorer

        scores = OnnxScorer(model, threads=1).score_capture(capture, Path(path).name)
        rankings["insertion guided by the model (guided)"] = insertion_ranking(field, grid, guide=guide_weights(scores))
        rankings["spread of the model (lpnn)"] = spread_ranking(positions, scores)
    target = reference_tolerance(reference, TOLERANCE).indices.shape[0]
    ratios = {}
    for name, ranking in rankings.items():
        select = prefix_selection(grid, ranking)
        row = []
        for budget in BUDGETS:
            count = budget_count(budget, n)
            row.append(placement_error(field, select(count)).mean / float(reference.error_curve[max(count, 4)]))
        row.append(place_tolerance(field, select, TOLERANCE).indices.shape[0] / target)
        ratios[name] = row
    return ratios


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("captures", nargs="+", type=Path, help="crops of training or validation levels (*.lpnncap)")
    parser.add_argument("--model", type=Path, default=DEFAULT_MODEL, help="the model whose tiers to show (default: shipped)")
    parser.add_argument("--no-model", action="store_true", help="only the oracle rows")
    parser.add_argument("--card", type=Path, default=DEFAULT_CARD, help="the card whose held-out levels are refused")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    args = parser.parse_args(argv)
    refused = sorted({level_of(p) for p in args.captures} & held_out_levels(args.card))
    if refused:
        raise SystemExit(f"held-out level(s) {', '.join(refused)}: never used to select or tune (they only report); "
                         "cut crops of training or validation levels with Tools~/experiments/recipe-crops.py")
    from lpnn.core.engine import Engine

    tasks = [(str(p), None if args.no_model else str(args.model)) for p in args.captures]
    with Engine(args.workers) as engine:
        results = list(engine.ordered(crop_ratios, tasks))
    header = " | ".join(f"×ref @{b * 100:g} %" for b in BUDGETS) + f" | probes ×ref @τ={TOLERANCE:g}"
    print(f"{len(results)} crops; geometric means of per-crop ratios\n\n| ranking | {header} |\n|---|" + "---|" * 6)
    for name in results[0]:
        values = np.array([r[name] for r in results], dtype=np.float64)
        finite = np.isfinite(values) & (values > 0)
        means = [math.exp(float(np.mean(np.log(values[finite[:, j], j])))) for j in range(values.shape[1])]
        print(f"| {name} | " + " | ".join(f"{m:.2f}" for m in means) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
