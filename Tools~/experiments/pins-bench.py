#!/usr/bin/env python3
"""What pinned probes cost (Documentation~/benchmarks.md "Pinned probes"): per capture, the default placement
(insertion refined in batches, tolerance 0.05) without pins, with a uniform sub-lattice pinned (every STRIDE-th lattice
point along each axis, on the grid) and with a random 5 % of the points pinned, each moved a quarter cell in a random
direction (off the grid, as an artist's probes are; they still stand for the point they were moved from, pins.md).

    PYTHONPATH=Training~ <venv python> "Tools~/experiments/pins-bench.py" CAPTURE [CAPTURE ...] --out rows.csv [--stride 4]

Rows are written as they finish (temp file + rename). Only training and validation levels belong here (never the
held-out ones, training.md).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from lpnn.core.atomic import write_text_atomic
from lpnn.core.capture_file import read_capture
from lpnn.core.grid import EvaluationGrid
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.placement.pins import pin_probes
from lpnn.quality.placement.refined_insertion import refined_insertion

COLUMNS = ("capture", "points", "pins", "pinned", "blocked", "probes", "new_probes", "mean_error", "seconds")
TOLERANCE = 0.05
RANDOM_FRACTION = 0.05
OFFSET_CELLS = 0.25  # < half a cell: a moved pin still stands for the point it was moved from


def pin_sets(capture, stride: int, seed: int) -> list[tuple[str, np.ndarray | None]]:
    ids = np.asarray(capture.ids, dtype=np.int64).reshape(-1, 3)
    lattice = np.flatnonzero(np.all(ids % stride == 0, axis=1))
    rng = np.random.default_rng(seed)
    chosen = np.sort(rng.choice(capture.point_count, int(round(RANDOM_FRACTION * capture.point_count)), replace=False))
    direction = rng.normal(size=(chosen.shape[0], 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    moved = capture.positions[chosen].astype(np.float64) + OFFSET_CELLS * capture.cell_size * direction
    return [("none", None), (f"lattice/{stride}", capture.positions[lattice].astype(np.float64)),
            ("random-5%-moved", moved)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("captures", nargs="+")
    parser.add_argument("--out", required=True)
    parser.add_argument("--stride", type=int, default=4)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rows: list[str] = [",".join(COLUMNS)]
    for path in args.captures:
        capture = read_capture(path)
        field = ReferenceField.from_capture(capture)
        grid = EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids)
        for name, positions in pin_sets(capture, args.stride, args.seed):
            pins = None if positions is None else pin_probes(positions, capture.positions, capture.cell_size)
            clock = time.perf_counter()
            placed = refined_insertion(field, grid, tolerance=TOLERANCE, pins=pins)
            seconds = time.perf_counter() - clock
            pinned = 0 if pins is None else pins.count
            blocked = 0 if pins is None else int(np.count_nonzero(pins.blocked)) - pinned
            values = (Path(path).stem, capture.point_count, name, pinned, blocked, placed.indices.shape[0],
                      placed.indices.shape[0] - pinned, f"{placed.mean_error:.5f}", f"{seconds:.1f}")
            rows.append(",".join(str(v) for v in values))
            print(rows[-1], flush=True)
            write_text_atomic(args.out, "\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
