"""A reduced with/without comparison of relit variants (benchmarks.md "The network", issue [relight] item 5).

    PYTHONPATH=Training~ python Tools~/experiments/relit-comparison.py --pak PAK --work DIR [--variants 2] [--seed 0]
        [--levels A,B,...] [--crops-per-level N] [--epochs N]   (defaults: the documented run; smaller ones smoke-test it)

Runs the recipe twice in DIR/without and DIR/with-N on six levels split as the quick recipe splits them
(QUICK's rule on LEVELS below: training kaos, oa_bases3, oa_dm2; early stopping aggressor; evaluated on the
validation levels fan and oa_bases7 — no held-out level of the shipped model's card is touched) with more
crops per level and a longer training than --quick (CROPS_PER_LEVEL, EPOCHS below), identical except
`variants_per_crop`; both are evaluated on the same evaluation crops under their original light-grid
lighting. Prints one Markdown row per run: ROC-AUC, PR-AUC, the LPNN error ratios to the reference at
10/20/30 % and the tolerance policy's probe ratio. It is a reduced comparison (3 training levels, one
seed), not the full recipe: read its figures as such.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

from lpnn.recipe.config import QUICK
from lpnn.recipe.evaluation import find
from lpnn.recipe.run import run_recipe
from lpnn.train.config import TrainConfig

# Sorted, QUICK's split rule puts fan and oa_bases7 (validation levels of the shipped model) in its held-out
# role and aggressor in its validation role; the three training levels have entity lights or sky to recover.
LEVELS = ("aggressor", "fan", "kaos", "oa_bases3", "oa_bases7", "oa_dm2")
CROPS_PER_LEVEL = 4
EPOCHS, PATIENCE, STEPS = 20, 8, 20


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--pak", type=Path, required=True)
    parser.add_argument("--work", type=Path, required=True)
    parser.add_argument("--variants", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--scheme", default="quick", help="rig recovery scheme for the training levels")
    parser.add_argument("--levels", default=",".join(LEVELS),
                        help="levels, split as the quick recipe splits them (default: LEVELS)")
    parser.add_argument("--crops-per-level", type=int, default=CROPS_PER_LEVEL)
    parser.add_argument("--epochs", type=int, default=EPOCHS)
    args = parser.parse_args()
    base = replace(QUICK, levels=tuple(args.levels.split(",")), seed=args.seed, crops_per_level=args.crops_per_level,
                   workers=1, train=TrainConfig(epochs=args.epochs, patience=PATIENCE, steps_per_epoch=STEPS,
                                                batch_clouds=4, seed=args.seed))
    runs = {"without": base,
            f"with-{args.variants}": replace(base, variants_per_crop=args.variants, variant_rig_scheme=args.scheme)}
    print("| run | training crops | held-out crops | ROC-AUC | PR-AUC | LPNN error / reference at 10 / 20 / 30 % | "
          "LPNN-refine at 20 % | tolerance 0.05: probes / reference |\n|---|---|---|---|---|---|---|---|")
    for label, config in runs.items():
        result = run_recipe(args.pak, args.work / label, config, log=lambda line: print(line, file=sys.stderr))
        summary = result.held_out
        ratios = " / ".join(f"{find(summary, 'network', 'budget', b)['error_vs_reference']:.2f}" for b in (0.1, 0.2, 0.3))
        refine = find(summary, "guided-exact-refined", "budget", 0.2)["error_vs_reference"]
        tolerance = find(summary, "network", "tolerance", summary["tolerance"])
        print(f"| {label} | {len(result.crops['train'])} | {summary['crops']} | {summary['roc_auc']:.3f} | "
              f"{summary['pr_auc']:.3f} | {ratios} | {refine:.2f} | {tolerance['probes_vs_reference']:.2f} "
              f"({tolerance['within_tolerance']} of {tolerance['crops']} within) |", flush=True)
        (args.work / f"{label}.summary.json").write_text(json.dumps(summary, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
