"""The warm-up's partner: a second process that compiles, first, the kernels the warm-up reaches last.

numba compiles on one core, and the warm-up (warmup.compile_placement_kernels) reaches its kernels one after the other:
the import's, insertion's rounds and tolerance search, the leak repair, the batched refinement, the hull projection. On a
fresh checkout that took 42–44 s on two cores, one of them idle. This process, started beside it on the other core, runs
the same synthetic room's hull projection, a leak-weighted batched refinement from every point and a leak repair whose
rounds are derived by insertion. Each kernel it compiles lands in numba's disk cache (core/cache.py), where the warm-up,
reaching it later, loads it instead of compiling it; core/cache_guard.py keeps each entry whole while both read and
write the cache, and defers a stop until a save is done. The warm-up still calls every kernel itself, so what it
compiles does not depend on this process, which it stops once it is done; it also stops when its stdin closes, so
that it never outlives the warm-up's process (`python -m lpnn.quality.placement.warmup_partner`).
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from dataclasses import dataclass

import numpy as np

from ..metric.triangulation import tetrahedralize
from .batched_refinement import batched_refinement
from .insertion_tetrahedra import InsertionTetrahedra
from .leak_aware import LeakWeighting, leak_repaired_with_mesh
from .warmup import WARM_UP_TOLERANCE, project_outside_a_hull, warm_up_room

REPAIR_SEED_STRIDE = 7  # the repair starts from every 7th point of the room: sparse enough that some points leak


@dataclass(frozen=True)
class PartnerWork:
    """What the partner ran (its tests check that it reached the refinement's rounds and the repair's)."""

    refinement_rounds: int
    repair_seed: int
    repaired: int


def compile_late_kernels() -> PartnerWork:
    """The warm-up's last stages on its room, in reverse order (module text)."""
    scene, _, field = warm_up_room()
    project_outside_a_hull()
    refined = batched_refinement(field, np.arange(field.point_count), tolerance=WARM_UP_TOLERANCE,
                                 leaks=LeakWeighting(scene.raycaster))
    seed = np.arange(0, field.point_count, REPAIR_SEED_STRIDE)
    mesh = tetrahedralize(field.world[seed], field.frame, seed)
    repaired, _ = leak_repaired_with_mesh(field, seed, scene.raycaster, mesh=mesh, tetrahedra=InsertionTetrahedra())
    return PartnerWork(refinement_rounds=refined.rounds, repair_seed=int(seed.shape[0]),
                       repaired=int(repaired.shape[0]))


def _stop_when_stdin_closes() -> None:
    """Reads stdin to its end (the warm-up's process closed it or died), then stops this process as the warm-up's
    terminate does (SIGTERM, which cache_guard defers until a save is done)."""
    while os.read(sys.stdin.fileno(), 4096):  # the raw descriptor: no buffer lock held at the interpreter's exit
        pass
    os.kill(os.getpid(), signal.SIGTERM)


if __name__ == "__main__":
    threading.Thread(target=_stop_when_stdin_closes, daemon=True).start()
    compile_late_kernels()
