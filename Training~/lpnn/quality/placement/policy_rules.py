"""The rules of the placement policies' parameters and their defaults, shared by the commands,
`quality/placement/policies.py`, the benchmark, the recipe and the demo: one definition each.

Light on purpose (math only): the CLI registers its options at `lpnn --help` time, before any heavy import.
"""

from __future__ import annotations

import math

REFERENCE_METHODS = ("fast", "faithful")
# Mean irradiance error of the tolerance policy (~10 % relative irradiance error) in the benchmark, the
# recipe's evaluation and the demo: at 0.02 the noisy Quake light grids need 2/3 of all points.
DEFAULT_TOLERANCE = 0.05
# Budgets of `lpnn bench` and the recipe's evaluation: down to 1 %, where artists' smallest counts lie.
# Here, not in bench.py, so that building the CLI parser imports no numerical library.
DEFAULT_BUDGETS = (0.01, 0.05, 0.1, 0.2, 0.3)
# Points above which `lpnn bench` measures against the blockwise reference (quality.md §3.3) instead of the full fast
# reference. The full reference is exact and no slower: 1,118 s and 3.1 GB peak at 136,512 points on one core
# (ctf_compromise), where the blockwise one decimates 2.2x the points; on sparse levels the blockwise answer is far
# from it (islanddm, 63,185 points: 191 probes at tau against the full reference's 4, found in 480 s). So the blockwise
# reference is for what the full one cannot hold: above ~150,000 points its memory passes ~3.5 GB (benchmarks.md "References and scale-out").
FULL_REFERENCE_LIMIT = 150_000
# Points above which `lpnn bench` skips the guided-exact-refined tier: each of its rows decimates again (a seeded greedy, or the
# full reference for seeds above 0.4 N), minutes per row on a whole level, about the reference's time each.
REFINE_BENCH_LIMIT = 20_000
# The tolerance search's bisection stops once the last failing count is within 1/SEARCH_RESOLUTION of the first
# passing one (quality.md §4): the answer passes tau and keeps at most 1/256 more probes than a unit-resolution
# search would (within the error's own non-monotonic noise), for about log2(256) fewer error evaluations, each a
# tetrahedralisation and a pass over every point. Answers below 256 probes are found to the unit, as before.
# C#: Selection.ToleranceSearch.Resolution.
SEARCH_RESOLUTION = 256


def budget_problem(value: float) -> str | None:
    """Why `value` is not a budget fraction, or None: the one rule of the CLI and of quality/placement/policies.py."""
    if math.isfinite(value) and 0.0 < value <= 1.0:
        return None
    return "must be a fraction of the points in (0, 1], e.g. 0.2 for 20 %"


def tolerance_problem(value: float) -> str | None:
    """Why `value` is not a tolerance (a mean error), or None: the one rule of the CLI and of quality/placement/policies.py."""
    if math.isfinite(value) and value > 0.0:
        return None
    return f"must be a mean error > 0, e.g. {DEFAULT_TOLERANCE:g} (the default of bench, the demo and the editor)"


# `--leaks` of `lpnn place` and `lpnn bench` (Documentation~/leaks.md "A leak-aware default"): the default placement
# avoids light leaks where the capture's geometry is known; "ignore" is the opt-out (fewer probes, leaks accepted).
LEAK_CHOICES = ("avoid", "ignore")
