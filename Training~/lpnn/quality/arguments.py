"""Command-line argument types shared by `lpnn label`, `lpnn place` and `lpnn bench`.

Light on purpose (argparse and math only): the commands register their options at `lpnn --help`
time, before any heavy import.
"""

from __future__ import annotations

import argparse
import math

REFERENCE_METHODS = ("fast", "faithful")
# Mean irradiance error of the tolerance policy (~10 % relative irradiance error) in the benchmark, the
# recipe's evaluation and the demo: at 0.02 the noisy Quake light grids need 2/3 of all points.
DEFAULT_TOLERANCE = 0.05
# Budgets of `lpnn bench` and the recipe's evaluation: down to 1 %, where artists' smallest counts lie.
# Here, not in bench.py, so that building the CLI parser imports no numerical library.
DEFAULT_BUDGETS = (0.01, 0.05, 0.1, 0.2, 0.3)


def _number(text: str, example: str) -> float:
    """A number written with '.' decimals, whatever the locale; the error shows an example."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number (use '.' for decimals, e.g. {example})") from None


def budget_problem(value: float) -> str | None:
    """Why `value` is not a budget fraction, or None: the one rule of the CLI and of quality/policies.py."""
    if math.isfinite(value) and 0.0 < value <= 1.0:
        return None
    return "must be a fraction of the points in (0, 1], e.g. 0.2 for 20 %"


def tolerance_problem(value: float) -> str | None:
    """Why `value` is not a tolerance (a mean error), or None: the one rule of the CLI and of quality/policies.py."""
    if math.isfinite(value) and value > 0.0:
        return None
    return f"must be a mean error > 0, e.g. {DEFAULT_TOLERANCE:g} (the default of bench, the demo and the editor)"


def fraction(text: str) -> float:
    """argparse type: a budget fraction in (0, 1] written with '.' decimals."""
    value = _number(text, "0.2")
    problem = budget_problem(value)
    if problem:
        raise argparse.ArgumentTypeError(f"{text!r} {problem}")
    return value


def tolerance(text: str) -> float:
    """argparse type: a mean error > 0 written with '.' decimals."""
    value = _number(text, f"{DEFAULT_TOLERANCE:g}")
    problem = tolerance_problem(value)
    if problem:
        raise argparse.ArgumentTypeError(f"{text!r} {problem}")
    return value


def refine_factor(text: str) -> float:
    """argparse type: a refinement seed factor > 1 written with '.' decimals."""
    value = _number(text, "2")
    if not (math.isfinite(value) and value > 1.0):
        raise argparse.ArgumentTypeError(f"{text!r} must be a factor > 1 (the seed holds F x K points), e.g. 2")
    return value


def fractions(text: str) -> tuple[float, ...]:
    """argparse type: comma-separated budget fractions, e.g. 0.1,0.2,0.3."""
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if not parts:
        raise argparse.ArgumentTypeError("give at least one budget, e.g. 0.1,0.2,0.3")
    return tuple(fraction(p) for p in parts)


def add_policy_arguments(parser: argparse.ArgumentParser) -> None:
    policy = parser.add_mutually_exclusive_group(required=True)
    policy.add_argument("--budget", type=fraction, metavar="FRACTION",
                        help="keep this fraction of the points (0.2 = the best 20 %%)")
    policy.add_argument("--tolerance", type=tolerance, metavar="TAU",
                        help=f"keep the fewest probes whose mean error is <= TAU ({DEFAULT_TOLERANCE:g} recommended: the default of bench, the demo and the editor)")
