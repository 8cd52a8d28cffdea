"""What the fast decimation needs of a leak weighting (reference_fast.py "Leaks"): placement/leak_aware.LeakWeighting
is one. A protocol, so this lower layer names no module of the placement layer above it (Tools~/lint-python.py)."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ...metric.location import Stencil
from ...metric.metric import ReferenceField


class Weighing(Protocol):
    """Errors of leaking points count `weight` times: `weighted` weighs a placement's errors, `leaking` says which points
    leak under given stencils."""

    weight: float

    def remembering(self, field: ReferenceField) -> "Weighing":
        """This weighting with a fresh segment memo for `field` (one per decimation)."""
        ...

    def weighted(self, field: ReferenceField, indices: np.ndarray, others: np.ndarray, stencil: Stencil,
                 errors: np.ndarray) -> np.ndarray:
        """errors (N,) with the leaking points' among `others` (stencils `stencil` into the probe indices `indices`)
        multiplied by the weight; a new array."""
        ...

    def leaking(self, field: ReferenceField, points: np.ndarray, probes: np.ndarray, vertices: np.ndarray,
                weights: np.ndarray) -> np.ndarray:
        """(M,) bool: the points `points` whose stencil (vertices (M, 4) into the point indices `probes`) leaks."""
        ...
