"""The reference decimation of one capture, by the method a command names (`lpnn label`, `lpnn place`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

from ...errors import UserError
from .decimation.decimation import Decimation
from ..metric.metric import ReferenceField
from .policy_rules import REFERENCE_METHODS
from .decimation.reference_faithful import FAITHFUL_MAX_CANDIDATES, faithful_decimation
from .decimation.reference_fast import fast_decimation

if TYPE_CHECKING:
    from .leak_aware import LeakWeighting


def run_reference(field: ReferenceField, method: str, source: str, workers: int | None = None,
                  progress: Callable[[int, int], None] | None = None, leaks: LeakWeighting | None = None) -> Decimation:
    """The reference decimation of one capture; UserError when the faithful one would take too long. `leaks`: the fast
    one of the leak-weighted error (the leak-aware reference, quality.md §3.2)."""
    if leaks is not None and method != "fast":
        raise UserError(f"{source}: only the fast reference decimates the leak-weighted error, not {method!r}")
    if method == "faithful":
        if field.point_count > FAITHFUL_MAX_CANDIDATES:
            raise UserError(f"{source}: the faithful decimation is O(n^3) and limited to {FAITHFUL_MAX_CANDIDATES} "
                            f"candidates; this capture has {field.point_count:,}: use --method fast")
        return faithful_decimation(field, progress=progress)
    if method == "fast":
        return fast_decimation(field, workers=workers, progress=progress, leaks=leaks)
    raise UserError(f"unknown reference method {method!r}: use one of {', '.join(REFERENCE_METHODS)}")
