#!/usr/bin/env python3
"""The Markdown table of benchmarks.md §4 from `lpnn bench`'s bench.csv: per capture, the error at a
budget as a ratio to the fast reference, the probes needed for the tolerance as a ratio to the
reference's count, and the LPNN / refinement / reference times; then the geometric mean per column
and, beside it, how many ratios it left out (non-finite or zero: the worst cases, e.g. a reference
error of 0; a missing row counts too).

    python3 Tools~/bench-table.py Build~/benchmarks/bench/bench.csv [--budget 0.2]
    python3 Tools~/bench-table.py bench.csv --summary    # one row per method: every budget and the tolerance
"""

import argparse
import csv
import math
import sys

METHODS = ("lpnn", "lpnn-guided", "lpnn-refine", "insertion", "heuristic", "apv", "uniform")
SUMMARY_METHODS = ("lpnn", "lpnn-guided", "lpnn-refine", "lpnn-topk", "insertion", "heuristic", "apv", "uniform", "random")


def geometric_mean(values):
    """(geometric mean of the finite positive values, how many were left out)."""
    usable = [v for v in values if math.isfinite(v) and v > 0]
    mean = math.exp(sum(math.log(v) for v in usable) / len(usable)) if usable else math.nan
    return mean, len(values) - len(usable)


def ratio(row, column):
    """A row's ratio; NaN when the method has no row there (it failed) or the cell is empty."""
    if row is None or not row.get(column):
        return math.nan
    return float(row[column])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", help="bench.csv written by lpnn bench")
    parser.add_argument("--budget", type=float, default=0.2, help="budget row to show (default 0.2)")
    parser.add_argument("--summary", action="store_true",
                        help="one row per method: geometric means over captures at every budget and the tolerance")
    args = parser.parse_args()
    with open(args.csv, newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    if args.summary:
        return summary(rows)
    table = {(r["capture"], r["method"], r["policy"], float(r["parameter"])): r for r in rows}
    tolerances = sorted({float(r["parameter"]) for r in rows if r["policy"] == "tolerance"})
    captures = sorted({r["capture"] for r in rows}, key=lambda c: int(next(r["points"] for r in rows if r["capture"] == c)))
    if not captures or len(tolerances) != 1:
        sys.exit(f"{args.csv}: needs rows of at least one capture and exactly one tolerance (found {tolerances})")
    tau, budget = tolerances[0], args.budget
    header = ([f"{m} ×ref @{budget * 100:g} %" for m in METHODS] + [f"{m} probes ×ref @τ" for m in METHODS]
              + ["LPNN ms", "refine ms", "reference s"])
    print("| level (points) | " + " | ".join(header) + " |")
    print("|" + "---|" * (len(header) + 1))
    columns = {}
    for capture in captures:
        cells = [ratio(table.get((capture, m, "budget", budget)), "error_ratio") for m in METHODS]
        cells += [ratio(table.get((capture, m, "tolerance", tau)), "probes_ratio") for m in METHODS]
        try:
            lpnn, refine, reference = (table[(capture, m, "budget", budget)] for m in ("lpnn", "lpnn-refine", "fast-reference"))
        except KeyError as missing:
            sys.exit(f"{args.csv}: no row {missing} (run lpnn bench with --model and the budget {budget:g})")
        for index, value in enumerate(cells):
            columns.setdefault(index, []).append(value)
        times = [f"{float(lpnn['seconds']) * 1e3:.0f}", f"{float(refine['refine_seconds']) * 1e3:.0f}",
                 f"{float(reference['seconds']):.1f}"]
        name = capture[len("held_"):] if capture.startswith("held_") else capture
        print(f"| {name} ({int(lpnn['points']):,}) | " + " | ".join(f"{v:.2f}" for v in cells) + " | " + " | ".join(times) + " |")
    means = [geometric_mean(columns[i]) for i in range(len(columns))]
    print("| **geometric mean** | " + " | ".join(f"**{mean:.2f}**" for mean, _ in means) + " | | | |")
    print("| ratios left out of the mean | " + " | ".join(str(left_out) for _, left_out in means) + " | | | |")
    return 0


def summary(rows) -> int:
    """Geometric mean over captures of error x reference per budget, and probes x reference at tau;
    "(n)" after a mean: n captures left out of it (non-finite or zero ratio, or no row)."""
    captures = sorted({r["capture"] for r in rows})
    budgets = sorted({float(r["parameter"]) for r in rows if r["policy"] == "budget"})
    tolerances = sorted({float(r["parameter"]) for r in rows if r["policy"] == "tolerance"})
    table = {(r["capture"], r["method"], r["policy"], float(r["parameter"])): r for r in rows}
    header = [f"×ref @{b * 100:g} %" for b in budgets] + [f"probes ×ref @τ={t:g}" for t in tolerances]
    print(f"{len(captures)} captures; geometric means of per-capture ratios, (n) = ratios left out")
    blockwise = sorted({r["capture"] for r in rows if r.get("yardstick") == "blockwise-reference"})
    if blockwise:  # bench.csv files before the column have no yardstick: the fast reference
        print(f"ref = the blockwise reference (quality.md §3.3) for {', '.join(blockwise)}; the fast reference elsewhere")
    print("| method | " + " | ".join(header) + " |")
    print("|" + "---|" * (len(header) + 1))
    for method in SUMMARY_METHODS + ("blockwise-reference",):
        if not any(r["method"] == method for r in rows):
            continue
        cells = []
        for policy, parameters, column in (("budget", budgets, "error_ratio"), ("tolerance", tolerances, "probes_ratio")):
            for parameter in parameters:
                mean, left_out = geometric_mean([ratio(table.get((c, method, policy, parameter)), column)
                                                 for c in captures])
                cells.append(f"{mean:.2f}" + (f" ({left_out})" if left_out else ""))
        print(f"| {method} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
