"""The reference decimation of one capture, by the method a command names (`lpnn label`, `lpnn place`)."""

from __future__ import annotations

from typing import Callable

from ...errors import UserError
from .decimation.decimation import Decimation
from ..metric.metric import ReferenceField
from .policy_rules import REFERENCE_METHODS
from .decimation.reference_faithful import FAITHFUL_MAX_CANDIDATES, faithful_decimation
from .decimation.reference_fast import fast_decimation


def run_reference(field: ReferenceField, method: str, source: str, workers: int | None = None,
                  progress: Callable[[int, int], None] | None = None) -> Decimation:
    """The reference decimation of one capture; UserError when the faithful one would take too long."""
    if method == "faithful":
        if field.point_count > FAITHFUL_MAX_CANDIDATES:
            raise UserError(f"{source}: the faithful decimation is O(n^3) and limited to {FAITHFUL_MAX_CANDIDATES} "
                            f"candidates; this capture has {field.point_count:,}: use --method fast")
        return faithful_decimation(field, progress=progress)
    if method == "fast":
        return fast_decimation(field, workers=workers, progress=progress)
    raise UserError(f"unknown reference method {method!r}: use one of {', '.join(REFERENCE_METHODS)}")
