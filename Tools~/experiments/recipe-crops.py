#!/usr/bin/env python3
"""Cut the crops `lpnn recipe run` cuts, from the TRAINING or VALIDATION levels of a model's split (its card's
`training.recipe.levels`), to benchmark or select on them. Held-out levels are refused: they only report.

  PYTHONPATH=Training~ python Tools~/experiments/recipe-crops.py --role validation --crops 2 --out crops/
  lpnn bench crops/*.lpnncap --model Packages/com.lpnn.probes/Models/lpnn_default.onnx --tolerance 0.05 --out bench

Crops are those of `lpnn.recipe.crops.crops_of_level` with the card's recipe options (the same boxes, seeds and
points as the recipe), numbers 0 .. CROPS-1 of each level.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

DEFAULT_CARD = Path(__file__).resolve().parents[2] / "Packages" / "com.lpnn.probes" / "Models" / "lpnn_default.card.json"
ROLES = ("train", "validation")


def levels_for_role(card: dict[str, Any], role: str) -> list[str]:
    """The levels of one role of the card's recipe split; refuses the held-out role and cards without a split."""
    if role not in ROLES:
        raise SystemExit(f"--role {role!r}: choose {' or '.join(ROLES)}; held-out levels are never used to select or tune")
    try:
        levels = card["training"]["recipe"]["levels"][role]
    except (KeyError, TypeError):
        raise SystemExit("the card has no training.recipe.levels split (a model not trained by `lpnn recipe run`)") from None
    return sorted(str(name) for name in levels)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--role", default="validation", help="train or validation (default)")
    parser.add_argument("--crops", type=int, default=2, help="crops per level (numbers 0 .. CROPS-1; default 2)")
    parser.add_argument("--card", type=Path, default=DEFAULT_CARD, help="the model card whose split to use")
    parser.add_argument("--out", type=Path, required=True, help="folder for LEVEL@CELLm__N.lpnncap files")
    args = parser.parse_args(argv)
    card = json.loads(args.card.read_text(encoding="utf-8"))
    levels = levels_for_role(card, args.role)

    from dataclasses import fields

    from lpnn.core.capture_file import write_capture
    from lpnn.recipe.config import RecipeConfig
    from lpnn.recipe.crops import crops_of_level
    from lpnn.scenes.levels import load_level

    options = card["training"]["recipe"].get("options", {})
    simple = {f.name: options[f.name] for f in fields(RecipeConfig)
              if f.name in options and not isinstance(options[f.name], (dict, list))}
    config = RecipeConfig(**simple)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in levels:
        for crop in crops_of_level(load_level(name), config.cell_sizes[0], config):
            if crop.number >= args.crops:
                continue
            path = write_capture(args.out / f"{crop.name}.lpnncap", crop.capture)
            print(f"{path.name}: {crop.capture.point_count:,} points", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
