#!/usr/bin/env python3
"""Where the default's distance from the exact greedy comes from, at a tolerance (benchmarks.md "Measured and not
merged (2026-11-29, late): where the whole-level gap to the exact greedy comes from"): per capture and seed factor F,
the default (`refined_insertion(..., refine=F)`), the exact greedy from the default's own seed
(`fast_decimation(initial=seed)`), and the batched refinement from that seed at other commit fractions, with and
without settled commits (`batched_refinement(..., settled_commits=True)`: commits only in rounds that start with every
cost fresh; at fraction 0 the exact greedy's removals); with --reference also the exact greedy from every point.

  PYTHONPATH=Training~ python Tools~/experiments/greedy-gap.py ctf_compromise.lpnncap --leaks ignore \\
      [--factors 2,4] [--fractions 0.1,0.02,0.005,0] [--settled-fractions 0.1,0.002,0] [--reference]

Leak-aware by default, as `lpnn place` (the seed then includes the leak repair's points, and every error summed is
leak-weighted; a capture without its level's geometry runs leak-blind, said once). Prints one JSON line per
measurement as it goes (probes at tau, mean error — leak-aware, the batched and greedy rows' leak-weighted one, the
default's plain —, stop reason, rounds, seconds, one process; the default's seconds are the whole placement's, its
refinement's apart), then a table. Minutes to hours on whole levels (the exact greedy
from a seed took 0.03 s a removal on ctf_compromise); choose on validation levels only.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Sequence

from lpnn.cli.arguments import numbers

TOLERANCE = 0.05
# The exact greedies stop once the mean error passes this multiple of tau (their last removals are the dearest): their
# tau answer is the smallest count within tau up to there, so a dip back below tau after the curve passed 1.2 tau
# would be missed (the project's benchmarks stop the reference at 2 tau: lpnn bench --reference-stop).
GREEDY_STOP = 1.2


def _timed(function):
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def measure(name: str, field, grid, raycaster, tolerance: float, factors: Sequence[float], fractions: Sequence[float],
            settled_fractions: Sequence[float], reference: bool, emit) -> None:
    """The rows of one capture (`field`, its `grid`; `raycaster` the leaks to avoid, None: leak-blind) to `emit`."""
    from lpnn.quality.placement.batched_refinement import batched_refinement
    from lpnn.quality.placement.decimation.reference_fast import fast_decimation
    from lpnn.quality.placement.leak_aware import LeakWeighting
    from lpnn.quality.placement.refined_insertion import refined_insertion

    mode = "leak-aware" if raycaster is not None else "leak-blind"

    def weighting():  # a fresh weighting (and segment memo) per run, as each command makes its own
        return None if raycaster is None else LeakWeighting(raycaster)

    def greedy(initial) -> dict:
        decimation, seconds = _timed(lambda: fast_decimation(field, initial=initial, stop_above=GREEDY_STOP * tolerance,
                                                             leaks=weighting()))
        probes = decimation.smallest_count_within(tolerance)
        return {"method": "exact greedy", "probes": probes, "stop_reason": decimation.stop_reason,
                "mean_error": None if probes is None else round(float(decimation.error_curve[probes]), 6),
                "seconds": round(seconds, 3)}

    base = {"capture": name, "points": field.point_count, "mode": mode, "tolerance": tolerance}
    if reference:
        emit({**base, "seed": "every point", **greedy(None)})
    for factor in factors:
        placed, seconds = _timed(lambda: refined_insertion(field, grid, tolerance=tolerance, refine=factor,
                                                           leaks=raycaster))
        seed = placed.seed
        row = {**base, "seed": f"{factor:g} K0", "seed_points": int(seed.shape[0])}
        emit({**row, "method": "default", "probes": int(placed.indices.shape[0]),
              "mean_error": round(placed.mean_error, 6), "rounds": placed.rounds, "seconds": round(seconds, 3),
              "refinement_seconds": round(placed.refinement_seconds, 3)})
        emit({**row, **greedy(seed)})
        for settled, values in ((False, fractions), (True, settled_fractions)):
            for fraction in values:
                refined, seconds = _timed(lambda: batched_refinement(field, seed, tolerance=tolerance, fraction=fraction,
                                                                     leaks=weighting(), settled_commits=settled))
                emit({**row, "method": "batched, settled commits" if settled else "batched", "fraction": fraction,
                      "probes": int(refined.indices.shape[0]), "mean_error": round(refined.mean_error, 6),
                      "stop_reason": refined.stop_reason, "rounds": refined.rounds, "seconds": round(seconds, 3)})


def table(rows: list[dict]) -> str:
    keys = ("capture", "mode", "seed", "method", "fraction", "probes", "mean_error", "stop_reason", "rounds", "seconds")
    lines = [" | ".join(keys), "|".join("---" for _ in keys)]
    for row in rows:
        lines.append(" | ".join("" if row.get(key) is None else str(row[key]) for key in keys))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("captures", nargs="+", type=Path)
    parser.add_argument("--leaks", choices=("avoid", "ignore"), default="avoid")
    parser.add_argument("--tolerance", type=float, default=TOLERANCE)
    parser.add_argument("--factors", type=numbers, default=numbers("2"),
                        help="seed factors F (seed: insertion's first F x K0 points)")
    parser.add_argument("--fractions", type=numbers, default=numbers("0.1,0.02,0.005"),
                        help="commit fractions, batched from each seed")
    parser.add_argument("--settled-fractions", type=numbers, default=numbers("0.1,0.002,0"),
                        help="commit fractions with settled commits (0: the exact greedy's removals, slowly)")
    parser.add_argument("--reference", action="store_true", help="also the exact greedy from every point (slow)")
    args = parser.parse_args(argv)
    for path in args.captures:
        if not path.is_file():
            parser.error(f"no capture {path}")
    # Checked before any placement: a bad value would otherwise surface after minutes of work on a whole level.
    if not (math.isfinite(args.tolerance) and args.tolerance > 0):
        parser.error(f"--tolerance {args.tolerance!r} must be a mean error > 0 (e.g. {TOLERANCE})")
    for factor in args.factors:
        if not (math.isfinite(factor) and factor > 1):
            parser.error(f"--factors: {factor!r} must be > 1 (the seed holds F x K0 points)")
    for fraction in args.fractions + args.settled_fractions:
        if not 0 <= fraction <= 1:
            parser.error(f"commit fraction {fraction!r} must be in [0, 1]")
    rows: list[dict] = []

    def emit(row: dict) -> None:
        rows.append(row)
        print(json.dumps(row), flush=True)

    from lpnn.core.capture_file import read_capture
    from lpnn.core.grid import EvaluationGrid
    from lpnn.quality.metric.leaks import field_with_geometry
    from lpnn.quality.placement.leak_aware import leaks_to_avoid

    for path in args.captures:
        capture = read_capture(path)
        field = field_with_geometry(capture)
        raycaster = leaks_to_avoid(field, args.leaks, warn=lambda text: print(f"{path.name}: {text}", file=sys.stderr))
        measure(path.name, field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids), raycaster,
                args.tolerance, args.factors, args.fractions, args.settled_fractions,
                args.reference, emit)
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
