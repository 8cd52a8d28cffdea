"""Command-line argument types shared by `lpnn label`, `lpnn place` and `lpnn bench` (and the experiment drivers' number
lists, `numbers`).

Light on purpose (argparse and math only): the commands register their options at `lpnn --help`
time, before any heavy import. The rules themselves are `quality/placement/policy_rules.py`'s.
"""

from __future__ import annotations

import argparse
from typing import Callable

from ..quality.placement.policy_rules import DEFAULT_TOLERANCE, budget_problem, tolerance_problem


def _number(text: str, example: str) -> float:
    """A number written with '.' decimals, whatever the locale; the error shows an example."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number (use '.' for decimals, e.g. {example})") from None


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


def _comma_separated(text: str, parse: Callable[[str], float], empty: str) -> tuple[float, ...]:
    """The non-empty comma-separated entries of `text`, each read by `parse`; `empty`: the error when there is none."""
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if not parts:
        raise argparse.ArgumentTypeError(empty)
    return tuple(parse(p) for p in parts)


def numbers(text: str) -> tuple[float, ...]:
    """argparse type: comma-separated numbers with '.' decimals, e.g. 2,4 (the experiment drivers' lists; each caller
    checks its own range)."""
    return _comma_separated(text, lambda part: _number(part, "2,4"), "give at least one number, e.g. 2,4")


def fractions(text: str) -> tuple[float, ...]:
    """argparse type: comma-separated budget fractions, e.g. 0.1,0.2,0.3."""
    return _comma_separated(text, fraction, "give at least one budget, e.g. 0.1,0.2,0.3")


def add_policy_arguments(parser: argparse.ArgumentParser) -> None:
    policy = parser.add_mutually_exclusive_group(required=True)
    policy.add_argument("--budget", type=fraction, metavar="FRACTION",
                        help="keep this fraction of the points (0.2 = the best 20 %%)")
    policy.add_argument("--tolerance", type=tolerance, metavar="TAU",
                        help=f"keep the fewest probes whose mean error is <= TAU ({DEFAULT_TOLERANCE:g} recommended: the default of bench, the demo and the editor)")


def positive_count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a count of workers; give a whole number >= 1, e.g. 2")
    return value


def add_engine_arguments(parser: argparse.ArgumentParser, what: str) -> None:
    """--workers and --scheduler: where `what` (the items of one command) run (lpnn/core/engine.py)."""
    parser.add_argument("--workers", type=positive_count, default=1, metavar="N",
                        help=f"local worker processes for {what} (default 1: in this process); with a single item "
                             "they split its fast reference or blockwise blocks instead")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help=f"run {what} on the Dask cluster at ADDRESS (e.g. tcp://10.0.0.5:8786; "
                             "Documentation~/training.md \"On a cluster\"); --workers is then ignored")


def engine_and_inner_workers(args: argparse.Namespace, items: int) -> tuple[int, int]:
    """(local engine workers, processes inside one item): items fan out over the engine, except a single item on this
    machine, which keeps --workers for its own fast reference or blocks (as before the engine); never both, so
    no worker starts workers of its own."""
    if args.scheduler is None and items <= 1:
        return 1, min(args.workers, FAST_REFERENCE_REPLICAS)
    return args.workers, 1


FAST_REFERENCE_REPLICAS = 2  # the most processes one fast reference uses (quality/placement/decimation/removal_costs.py)
