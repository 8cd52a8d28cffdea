#!/usr/bin/env python3
"""The Markdown table of benchmarks.md "The speed/accuracy trade, every method" from `lpnn bench`'s bench.csv: per capture, the error at a
budget as a ratio to the fast reference, the probes needed for the tolerance as a ratio to the
reference's count, and the LPNN / refinement / reference times; then the geometric mean per column
and, beside it, how many ratios it left out (non-finite or zero: the worst cases, e.g. a reference
error of 0; a missing row counts too).

    python3 Tools~/experiments/bench-table.py Build~/benchmarks/bench/bench.csv [--budget 0.2]
    python3 Tools~/experiments/bench-table.py bench.csv --summary    # one row per method: every budget and the tolerance
    python3 Tools~/experiments/bench-table.py --trade "held-out crops=heldbench/bench.csv" "ctf_compromise=ctf/bench.csv" \
        "the demo=Build~/demo/summary.json" ...

--trade prints the speed/accuracy trade on one page (benchmarks.md "The speed/accuracy trade, every method"): for each
set (LABEL=CSV, one `lpnn bench` run; or LABEL=summary.json, `make demo`'s answers at tau) and every method, the geometric means of error x reference at each budget and
of probes x reference at tau, and the median seconds per capture at a 20 % budget and at tau; a method without rows
says why (no model, above a size limit, failed: DIR/failures.csv, or --note).

Leak-aware rows (the default placed leak-aware: bench.csv's leak_* columns, quality/bench/run.py's module text) get a
second line, "METHOD ×leak-aware ref": the same means against the leak-aware reference instead of the leak-blind one.
"""

import argparse
import csv
import math
import sys
from pathlib import Path

# The table of placement methods (Documentation~/methods.md; a light module: dataclasses only).
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "Training~"))
from lpnn.quality.placement.methods import DEFAULT_METHOD, METHODS as TABLE, SCORED  # noqa: E402

METHODS = ("network", "guided", "guided-exact-refined", "insertion", "heuristic", "apv", "uniform")
# Every method of `lpnn bench`, in the table's order: the default first, insertion, the methods that read the scores,
# the fast reference, the baselines and the bench-only yardsticks.
METHOD_ORDER = tuple(method.name for method in TABLE)
LPNN_TIERS = SCORED
YARDSTICKS = ("fast-reference", "blockwise-reference")
LEAK_AWARE_COLUMNS = {"error_ratio": "leak_error_ratio", "probes_ratio": "leak_probes_ratio"}  # the same, leak-aware
# lpnn bench's defaults (quality/placement/policy_rules.py, quality/placement/insertion.py): the reasons a method has no rows.
REFINE_LIMIT, GUIDED_POINT_LIMIT = 20_000, 32_768
LABELS = {DEFAULT_METHOD: f"**{DEFAULT_METHOD}** (default)"}  # every other method by its name


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
    parser.add_argument("csv", nargs="+", help="bench.csv written by lpnn bench (--trade: LABEL=CSV, one per set)")
    parser.add_argument("--budget", type=float, default=0.2, help="budget row to show (default 0.2)")
    parser.add_argument("--summary", action="store_true",
                        help="one row per method: geometric means over captures at every budget and the tolerance")
    parser.add_argument("--trade", action="store_true",
                        help="the one-page trade table of every set given as LABEL=CSV (module text)")
    parser.add_argument("--note", action="append", default=[], metavar="LABEL:METHOD=TEXT",
                        help="--trade: a note on a method's row of a set (e.g. why it was not run); repeatable")
    parser.add_argument("--given-yardstick", action="append", default=[], metavar="LABEL=COUNT",
                        help="--trade: for a set run without a reference (lpnn bench --no-reference), the probes at tau "
                             "of a yardstick measured elsewhere; probes x ref divide by it (marked †)")
    args = parser.parse_args()
    if args.trade:
        return trade(args.csv, args.note, args.given_yardstick)
    if len(args.csv) != 1:
        sys.exit("give one bench.csv (several only with --trade)")
    args.csv = args.csv[0]
    rows = read_rows(args.csv)
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
            lpnn, refine, reference = (table[(capture, m, "budget", budget)] for m in ("network", "guided-exact-refined", "fast-reference"))
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


def read_rows(path):
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def ordered_methods(rows, leave_out=()):
    """The methods present in `rows`, in METHOD_ORDER, then any other in their order of appearance."""
    present = list(dict.fromkeys(r["method"] for r in rows))
    return [m for m in METHOD_ORDER if m in present and m not in leave_out] + [
        m for m in present if m not in METHOD_ORDER and m not in leave_out]


def measured_leak_aware(rows, method) -> bool:
    """Whether `method`'s rows were also measured against the leak-aware reference (a leak_error_ratio cell)."""
    return any(r.get("leak_error_ratio") not in (None, "", "nan") for r in rows if r["method"] == method)


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
    for method in ordered_methods(rows, leave_out=("fast-reference",)):  # every method (issue 34: some were left out)
        for label, columns in ((method, {}), (f"{method} ×leak-aware ref", LEAK_AWARE_COLUMNS)):
            if columns and not measured_leak_aware(rows, method):
                continue
            cells = []
            for policy, parameters, column in (("budget", budgets, "error_ratio"),
                                               ("tolerance", tolerances, "probes_ratio")):
                for parameter in parameters:
                    mean, left_out = geometric_mean([ratio(table.get((c, method, policy, parameter)),
                                                           columns.get(column, column)) for c in captures])
                    cells.append(f"{mean:.2f}" + (f" ({left_out})" if left_out else ""))
            print(f"| {label} | " + " | ".join(cells) + " |")
    return 0


def _split_spec(spec: str, what: str):
    if "=" not in spec:
        sys.exit(f"{what} {spec!r}: expected LABEL=VALUE")
    label, value = spec.rsplit("=", 1)
    return label.strip(), value.strip()


def _seconds(value: float) -> str:
    if not math.isfinite(value):
        return "–"
    if value < 0.1:
        return f"{value:.3f}"
    return f"{value:.2f}" if value < 10 else f"{value:.1f}" if value < 100 else f"{value:,.0f}"


def _failures(path: Path):
    """{method: reason} from failures.csv beside a bench.csv (lpnn bench writes it when something failed)."""
    failures = path.parent / "failures.csv"
    if not failures.exists():
        return {}
    return {row["method"]: row["reason"] for row in read_rows(failures)}


def demo_rows(path):
    """`make demo`'s summary.json (Build~/demo) as tolerance rows of bench.csv: probes over the fast reference's, the
    time of each method's stages summed (its features and inference included, as lpnn bench counts them)."""
    import json

    with open(path, encoding="utf-8") as handle:
        summary = json.load(handle)
    methods, tau = summary["methods"], summary["tolerance"]
    reference = methods["fast-reference"]["probes"]
    return [{"capture": summary["level"], "points": str(summary["points"]), "method": method, "policy": "tolerance",
             "parameter": str(tau), "probes": str(m["probes"]), "seconds": str(sum(m["seconds"].values())),
             "mean_error": str(m["mean_error"]), "probes_ratio": str(m["probes"] / reference),
             "reference_probes": str(reference), "yardstick": "fast-reference", "source": "demo"}
            for method, m in methods.items()]


def _why_not_run(method: str, rows, failures) -> str:
    """Why a method of `lpnn bench` has no rows in a set."""
    if rows and rows[0].get("source") == "demo":
        return "not among make demo's methods"
    for failed, reason in failures.items():
        if failed == method or failed.startswith(method + " ") or failed == "*":
            return f"failed: {reason[:120]}"
    points = max(int(r["points"]) for r in rows)
    yardsticks = {r.get("yardstick") or "fast-reference" for r in rows}
    has_lpnn = any(r["method"] in LPNN_TIERS for r in rows)
    if method == "fast-reference" and "blockwise-reference" in yardsticks:
        return "not run: above lpnn bench's --full-reference-limit the blockwise reference is the yardstick"
    if method in ("fast-reference", "leak-aware-reference") and yardsticks == {"none"}:
        return "not run: no reference (lpnn bench --no-reference)"
    if method == "guided-exact-refined" and (points > REFINE_LIMIT or yardsticks != {"fast-reference"}):
        return f"not run: above {REFINE_LIMIT:,} points (lpnn bench --refine-limit; each row decimates again)"
    if method == "leak-aware-reference":
        return "not run: the capture's geometry is not known here, or lpnn bench --leaks ignore"
    if method in LPNN_TIERS and not has_lpnn:
        return "not run: no --model"
    return "not run"


def _same_answers(rows, method: str, twin: str) -> bool:
    """True when `method`'s rows give exactly `twin`'s answers (the guided tiers above the guide's point limit)."""
    mine = {(r["capture"], r["policy"], r["parameter"]): (r["probes"], r["mean_error"]) for r in rows if r["method"] == method}
    theirs = {(r["capture"], r["policy"], r["parameter"]): (r["probes"], r["mean_error"]) for r in rows if r["method"] == twin}
    return bool(mine) and mine == theirs


def trade(specs, notes, given) -> int:
    """The one-page table (module text): a row per set and method."""
    sets = []
    for spec in specs:
        label, path = _split_spec(spec, "set") if "=" in spec else (Path(spec).parent.name, spec)
        if not Path(path).is_file():
            sys.exit(f"set {label!r}: no file {path}")
        sets.append((label, Path(path), demo_rows(path) if path.endswith(".json") else read_rows(path)))
    extra = {}
    for note in notes:
        key, text = _split_spec(note, "--note")
        if ":" not in key:
            sys.exit(f"--note {note!r}: expected LABEL:METHOD=TEXT")
        label, method = key.rsplit(":", 1)
        extra.setdefault((label.strip(), method.strip()), []).append(text)
    yardstick_counts = {label: int(count.replace(",", "")) for label, count in (_split_spec(g, "--given-yardstick") for g in given)}
    unknown = ({label for label, _ in extra} | set(yardstick_counts)) - {label for label, _, _ in sets}
    if unknown:
        sys.exit(f"--note/--given-yardstick name no set: {', '.join(sorted(unknown))}")
    budgets = sorted({float(r["parameter"]) for _, _, rows in sets for r in rows if r["policy"] == "budget"})
    tolerances = sorted({float(r["parameter"]) for _, _, rows in sets for r in rows if r["policy"] == "tolerance"})
    if len(tolerances) > 1:
        sys.exit(f"the sets hold different tolerances {tolerances}: one table needs one τ")
    tau = tolerances[0] if tolerances else None
    time_budget = 0.2 if 0.2 in budgets else (budgets[-1] if budgets else None)
    header = ([f"error ×ref @{b * 100:g} %" for b in budgets] + ([f"probes ×ref @τ={tau:g}"] if tau is not None else [])
              + ([f"median s @{time_budget * 100:g} %"] if time_budget is not None else [])
              + (["median s @τ"] if tau is not None else []) + ["note"])
    print("| set | method | " + " | ".join(header) + " |")
    print("|" + "---|" * (len(header) + 2))
    for label, path, rows in sets:
        captures = sorted({r["capture"] for r in rows})
        table = {(r["capture"], r["method"], r["policy"], float(r["parameter"])): r for r in rows}
        failures = _failures(path)
        yardsticks = {r.get("yardstick") or "fast-reference" for r in rows}
        methods = [m for m in METHOD_ORDER if m != "faithful-reference" or any(r["method"] == m for r in rows)]
        methods = [m for m in methods if m != "blockwise-reference" or "blockwise-reference" in yardsticks]
        methods += [m for m in ordered_methods(rows) if m not in methods]
        methods += [m for (on, m) in extra if on == label and m not in methods]  # a note names it: show its row
        name = f"{label} ({len(captures)} captures)" if len(captures) > 1 else (
            f"{label} ({int(rows[0]['points']):,} points)" if rows else label)
        for number, method in enumerate(methods):
            shown = name if number == 0 else ""  # the set's name on its first row only
            notes_here = list(extra.get((label, method), []))
            if not any(r["method"] == method for r in rows):
                cells = ["–"] * (len(header) - 1)
                why = _why_not_run(method, rows, failures)
                if why != "not run" or not notes_here:  # a bare "not run" gives way to the note that says why
                    notes_here.insert(0, why)
                print(f"| {shown} | {LABELS.get(method, method)} | " + " | ".join(cells) + " | " + "; ".join(notes_here) + " |")
                continue
            cells = []
            for budget in budgets:
                cells.append(_mean_cell([table.get((c, method, "budget", budget)) for c in captures], "error_ratio"))
            if tau is not None:
                rows_at_tau = [table.get((c, method, "tolerance", tau)) for c in captures]
                if label in yardstick_counts and not any(r and r.get("probes_ratio") for r in rows_at_tau):
                    count = yardstick_counts[label]
                    ratios = [int(r["probes"]) / count if r else math.nan for r in rows_at_tau]
                    mean, left_out = geometric_mean(ratios)
                    cells.append(f"{mean:.2f}†" + (f" ({left_out})" if left_out else "") if math.isfinite(mean) else "–")
                else:
                    cells.append(_mean_cell(rows_at_tau, "probes_ratio"))
            if time_budget is not None:
                cells.append(_seconds(_median_seconds([table.get((c, method, "budget", time_budget)) for c in captures])))
            if tau is not None:
                cells.append(_seconds(_median_seconds([table.get((c, method, "tolerance", tau)) for c in captures])))
            if method in YARDSTICKS:
                notes_here.insert(0, "the yardstick")
            for guided, plain in (("guided", "insertion"), ("guided-refined", "insertion-refined")):
                if method == guided and _same_answers(rows, guided, plain) and min(int(r["points"]) for r in rows) > GUIDED_POINT_LIMIT:
                    notes_here.insert(0, f"{plain}'s answers (no guide above {GUIDED_POINT_LIMIT:,} points) + the inference")
            print(f"| {shown} | {LABELS.get(method, method)} | " + " | ".join(cells) + " | " + "; ".join(notes_here) + " |")
            if measured_leak_aware(rows, method):  # the same placements against the leak-aware reference
                cells = [_mean_cell([table.get((c, method, "budget", b)) for c in captures], "leak_error_ratio")
                         for b in budgets]
                if tau is not None:
                    cells.append(_mean_cell([table.get((c, method, "tolerance", tau)) for c in captures],
                                            "leak_probes_ratio"))
                cells += ["–"] * (len(header) - 1 - len(cells))
                print(f"|  | {LABELS.get(method, method)} ×leak-aware ref | " + " | ".join(cells)
                      + " | against the leak-aware reference |")
    if yardstick_counts:
        print("\n† probes over the yardstick's count given with --given-yardstick (" +
              ", ".join(f"{label}: {count:,}" for label, count in yardstick_counts.items()) + ").")
    return 0


def _mean_cell(rows, column: str) -> str:
    """The geometric mean of a column over captures, "(n)" when n ratios were left out; "–" when no capture has a row."""
    if not any(rows):
        return "–"
    mean, left_out = geometric_mean([ratio(row, column) for row in rows])
    return ("–" if not math.isfinite(mean) else f"{mean:.2f}") + (f" ({left_out})" if left_out else "")


def _median_seconds(rows) -> float:
    values = sorted(float(r["seconds"]) for r in rows if r and r.get("seconds") not in (None, "", "nan"))
    if not values:
        return math.nan
    middle = len(values) // 2
    return values[middle] if len(values) % 2 else (values[middle - 1] + values[middle]) / 2


if __name__ == "__main__":
    sys.exit(main())
