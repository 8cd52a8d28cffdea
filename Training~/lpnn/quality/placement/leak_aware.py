"""Leak-aware placement (Documentation~/leaks.md "A leak-aware default"): the two pieces the default placement uses when
it is given the scene's raycaster (refined_insertion(..., leaks=raycaster)).

    weighting = LeakWeighting(raycaster)                     # leaking points' errors count LEAK_WEIGHT times
    weighting = weighting.remembering(field)                 # each segment cast once for the whole placement
    repaired = leak_repaired(field, probes, raycaster)       # a probe inside every leaking tetrahedron, a few rounds
    repaired = leak_repaired(field, probes, raycaster, blocked=pins.blocked)   # none within the pins' keep distance
    repaired = leak_repaired(field, probes, raycaster, visibility=weighting.visibility)   # sharing the memo
    leaks_to_avoid(field, "avoid", warn)                     # the default's raycaster: field.geometry, or None (warned)

- The weighting makes the refinement's removal costs and its tolerance read leaks: a removal that lets a point's
  stencil reach through a wall costs that point's error LEAK_WEIGHT times, so the refinement keeps the probes that
  stop leaks unless their removal is cheap anyway. Only the error is weighted, so a leak that changes nothing (both
  sides equally lit, or both black) costs nothing.
- The repair gives the refinement a seed with few leaks to start from: decimation only removes probes, so a leak of
  the seed cannot be undone by it.
- With pinned probes (pins.py) the repair never adds a probe within a pin's keep distance: a leaking point there is
  left to the pinned probe (the artist put a probe there; pins.md "Every method"), and its tetrahedron gets the worst
  leaking point that may become a probe, if it holds one.
- Both ask the same segments again and again (a point's new stencil usually shares 3 of its 4 probes with the old
  one), and a segment's visibility never changes: one SegmentVisibility (metric/leak_rule.py) per placement remembers
  each point's recent answers, so the repair, every trial and every commit cast a segment about once, with the same
  answers (on ctf_compromise whole: see leaks.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ...core.features import Raycaster
from ..metric.leak_rule import SegmentVisibility, stencil_leaks
from ..metric.location import Stencil
from ..metric.metric import MetricError, ReferenceField, checked_segments, probe_mesh, stencil_point_errors
from ..metric.triangulation import Tetrahedralization
from .insertion_kernel import TIE, first_per_cell
from .insertion_tetrahedra import InsertionTetrahedra
from .policy_rules import LEAK_CHOICES

NO_GEOMETRY = ("leaks cannot be checked for this capture (the tools cannot load its geometry): the placement is the "
               "leak-blind one")
LEAK_WEIGHT = 8.0  # a leaking point's error counts this many times (benchmarks.md "Light leaks": 2, 4, 8, 16 measured)
REPAIR_ROUNDS = 2  # leak repair rounds on the seed (1 and 3 measured: benchmarks.md "Light leaks")


@dataclass(frozen=True)
class LeakWeighting:
    """Errors of leaking points multiplied by `weight` (>= 1): what batched refinement sums when told about leaks."""

    raycaster: Raycaster
    weight: float = LEAK_WEIGHT
    visibility: SegmentVisibility | None = None  # remembered segments of the raycaster (remembering()), else none

    def __post_init__(self) -> None:
        weight = float(self.weight)
        if not (math.isfinite(weight) and weight >= 1.0):
            raise MetricError(f"leak weight {self.weight!r} must be a finite number >= 1 (1: leaks count as any error; "
                              f"{LEAK_WEIGHT:g} is recommended)")
        object.__setattr__(self, "weight", weight)
        if self.visibility is not None and self.visibility.raycaster is not self.raycaster:
            raise MetricError("the leak weighting's remembered segments must come from its own raycaster")

    def remembering(self, field: ReferenceField) -> "LeakWeighting":
        """This weighting with a fresh memo of the segments between `field`'s points (module text): the same answers,
        fewer rays. Use it for one placement on that field."""
        return LeakWeighting(self.raycaster, self.weight, SegmentVisibility(self.raycaster, field.world))

    def weighted(self, field: ReferenceField, indices: np.ndarray, others: np.ndarray, stencil: Stencil,
                 errors: np.ndarray) -> np.ndarray:
        """errors (N,) with the entries of the leaking points among `others` (their stencils `stencil`, vertices
        positions in the probe indices `indices`) multiplied by the weight; a new array."""
        leaking = self.leaking(field, others, indices, stencil.vertices, stencil.weights)
        out = np.array(errors, dtype=np.float64, copy=True)
        out[others[leaking]] *= self.weight
        return out

    def leaking(self, field: ReferenceField, points: np.ndarray, probes: np.ndarray, vertices: np.ndarray,
                weights: np.ndarray) -> np.ndarray:
        """(M,) bool: the points `points` (field indices) whose stencil (vertices (M, 4): positions in the point indices
        `probes`; weights (M, 4)) leaks: the points `weighted` multiplies. The leak-aware exact reference asks it of
        the stencils a removal would give, which no triangulation holds yet (decimation/decimation_mesh.py)."""
        return _stencil_leaks(field, probes, points, vertices, weights, self.raycaster, self.visibility)


def leaks_to_avoid(field: ReferenceField, choice: str = "avoid",
                   warn: Callable[[str], None] | None = None) -> Raycaster | None:
    """The raycaster the default placement avoids leaks with (refined_insertion(..., leaks=)): with "avoid" (the
    default, leaks.md "A leak-aware default") the field's geometry, or None when the capture's geometry is not known,
    which `warn` is told (NO_GEOMETRY); with "ignore" (the opt-out: fewer probes, leaks accepted) None."""
    if choice not in LEAK_CHOICES:
        raise MetricError(f"leaks {choice!r}: choose one of {', '.join(LEAK_CHOICES)}")
    if choice == "ignore":
        return None
    if field.geometry is None and warn is not None:
        warn(NO_GEOMETRY)
    return field.geometry


def _stencil_leaks(field: ReferenceField, indices: np.ndarray, others: np.ndarray, vertices: np.ndarray,
                   weights: np.ndarray, raycaster: Raycaster, visibility: SegmentVisibility | None) -> np.ndarray:
    """stencil_leaks of the points `others` under the stencils `vertices` (positions in the probe indices `indices`)
    and `weights`, through the remembered segments when there are some (they must be of `field`'s points)."""
    if visibility is None:
        return stencil_leaks(field.world[others], field.world[indices], vertices, weights, raycaster)
    return checked_segments(visibility, field).stencil_leaks(others, indices, vertices, weights)


def leak_repaired(field: ReferenceField, probes: np.ndarray, raycaster: Raycaster,
                  rounds: int = REPAIR_ROUNDS, blocked: np.ndarray | None = None,
                  visibility: SegmentVisibility | None = None) -> np.ndarray:
    """leak_repaired_with_mesh's probes, each round tetrahedralised (module text of leak_repaired_with_mesh)."""
    return leak_repaired_with_mesh(field, probes, raycaster, rounds, blocked, visibility)[0]


def leak_repaired_with_mesh(field: ReferenceField, probes: np.ndarray, raycaster: Raycaster,
                            rounds: int = REPAIR_ROUNDS, blocked: np.ndarray | None = None,
                            visibility: SegmentVisibility | None = None, mesh: Tetrahedralization | None = None,
                            tetrahedra: InsertionTetrahedra | None = None
                            ) -> tuple[np.ndarray, Tetrahedralization | None]:
    """`probes` (point indices) plus, in each of up to `rounds` rounds, the leaking point of largest error (ties, errors
    within TIE of the largest: the lower index) of every tetrahedron some leaking point lies in (outside the hull: the
    tetrahedron owning its hull triangle). A probe at a leaking point ends that point's leak, and its tetrahedron is
    split where it leaked worst. `blocked` ((N,) bool, e.g. Pins.blocked): points that never become a probe; a leaking
    one is passed over (module text). Stops early when no point that may become a probe leaks. `visibility`: remembered
    segments of `raycaster` between the field's points (LeakWeighting.remembering), shared with the refinement that
    follows. `mesh`: the tetrahedralisation of the sorted `probes` when it is known; `tetrahedra` (the insertion order's
    InsertionTetrahedra): each round's new probes inserted into the last round's tetrahedra instead of tetrahedralising
    them (quality.md §5.1 step 6). Sorted point indices, and their tetrahedralisation when `tetrahedra` derived it or
    `mesh` was it (else None)."""
    if int(rounds) < 0:
        raise MetricError(f"leak repair rounds {rounds!r} must be >= 0")
    if blocked is not None and np.shape(blocked) != (field.point_count,):
        raise MetricError(f"blocked must flag each of the {field.point_count:,} points, got shape {list(np.shape(blocked))}")
    if visibility is not None and visibility.raycaster is not raycaster:
        raise MetricError("the remembered segments must come from the raycaster the repair is given")
    current = np.sort(np.asarray(probes, dtype=np.int64))
    for _ in range(int(rounds)):
        indices, others, located, stencil = probe_mesh(field, current, coherent=True, mesh=mesh)
        leaking = _stencil_leaks(field, indices, others, stencil.vertices, stencil.weights, raycaster, visibility)
        if blocked is not None:
            leaking &= ~np.asarray(blocked, dtype=bool)[others]
        mesh = located
        if not leaking.any():
            break
        errors = stencil_point_errors(field, indices, others, stencil)
        points, cells = others[leaking], stencil.cell[leaking]
        # Per cell the lowest index whose error is within TIE of the cell's largest (points ascend): errors where the
        # light is even are round-off (~1e-15) whose last bits hang on the arithmetic's order, so an exact comparison
        # would let rounding pick the probe, and the C# core picked another (oa_koth1: quality.md §5.1).
        first = first_per_cell(cells, np.ascontiguousarray(errors[points]), int(cells.max()) + 1, TIE)
        repaired = np.union1d(current, points[first])
        mesh = None if tetrahedra is None else tetrahedra.of_superset(field, located, indices, repaired)
        current = repaired
    return current, mesh
