#!/usr/bin/env python3
"""Points in use, measured (Documentation~/benchmarks.md "Points in use"): per level, the default placement (insertion
refined in batches, tolerance 0.05) on all points, on the band and on the reachable points (in-use.md).

    PYTHONPATH=Training~ <venv python> "Tools~/experiments/in-use-bench.py" LEVEL [LEVEL ...] --out rows.csv [--cell M]

Each level is imported once per rule (the import's own time, lighting and features included). Every placement is
then also evaluated on the `all` capture's field (same SH at the same points, one scene scale) at the reachable
points, the common yardstick: `error_reachable` is the mean error where players go. Rows are written as they finish
(temp file + rename), so an interrupted run keeps the finished levels.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from lpnn.core.atomic import write_text_atomic
from lpnn.core.grid import EvaluationGrid
from lpnn.core.in_use_section import in_use_points
from lpnn.core.lattice_index import IdIndex
from lpnn.quality.metric.metric import ReferenceField, point_errors
from lpnn.quality.placement.refined_insertion import refined_insertion
from lpnn.scenes.defaults import DEFAULT_CELL
from lpnn.scenes.importer import import_level

COLUMNS = ("level", "rule", "points", "import_seconds", "probes", "place_seconds", "mean_error", "error_reachable",
           "reachable_points")
TOLERANCE = 0.05


def measure(level: str, cell: float, rules: tuple[str, ...]) -> list[dict]:
    rows = []
    captures = {}
    for rule in ("all",) + tuple(r for r in rules if r != "all"):
        clock = time.perf_counter()
        captures[rule] = import_level(level, cell, in_use=rule, timings_in_source=False).capture
        captures[rule].source["import_seconds"] = time.perf_counter() - clock
    whole = captures["all"]
    reachable = in_use_points(whole)
    yardstick = ReferenceField.from_capture(whole)
    whole_index = IdIndex.build(whole.ids)
    for rule in rules:
        capture = captures[rule]
        field = ReferenceField.from_capture(capture)
        clock = time.perf_counter()
        placed = refined_insertion(field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids),
                                   tolerance=TOLERANCE)
        seconds = time.perf_counter() - clock
        probes_in_whole = whole_index.lookup(capture.ids[placed.indices])  # every rule's points are the whole's
        errors = point_errors(yardstick, probes_in_whole)
        rows.append({"level": level, "rule": rule, "points": capture.point_count,
                     "import_seconds": capture.source["import_seconds"], "probes": int(placed.indices.shape[0]),
                     "place_seconds": seconds, "mean_error": placed.mean_error,
                     "error_reachable": float(errors[reachable].mean()) if reachable is not None else float("nan"),
                     "reachable_points": int(reachable.sum()) if reachable is not None else 0})
        print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in rows[-1].items()), flush=True)
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("levels", nargs="+")
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--cell", type=float, default=DEFAULT_CELL)
    parser.add_argument("--rules", default="all,band,reachable", help="comma-separated, from all, band, reachable")
    args = parser.parse_args()
    rules = tuple(args.rules.split(","))
    rows: list[dict] = []
    for level in args.levels:
        rows.extend(measure(level, args.cell, rules))
        lines = [",".join(COLUMNS)] + [",".join(format(r[c], ".6g") if isinstance(r[c], float) else str(r[c])
                                                 for c in COLUMNS) for r in rows]
        write_text_atomic(args.out, "\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
