"""Who computes removal costs for the fast decimation: one process, or two identical replicas.

Both replicas hold the same DecimationState and apply the same removals in the same order, so
their states stay bit-identical; each computes the costs of part of the stale probes (costs do
not depend on which batch a probe is evaluated in) and only the accepted removal's data crosses
the pipe. The result is identical to the single-process run (leak-aware too, when the raycaster can be sent
to the replica: an analytic one can, Embree's scene cannot, and is refused with that reason); on 2 cores it is
0.9-1.2x as fast
(benchmarks.md "References and scale-out": both replicas apply every removal, and hull probes' costs come in lumps), and
slower when other work competes for the cores.
"""

from __future__ import annotations

import multiprocessing
import pickle
import traceback
from dataclasses import dataclass
from multiprocessing.connection import Connection

import numpy as np

from .decimation_mesh import GlobalRemoval, LocalRemoval
from .decimation_state import DecimationState
from ...metric.metric import ReferenceField
from .weighing import Weighing


# The replica is one process in lockstep with this one over a pipe, not a fan-out of independent items (those go
# through core/engine.py). Started with `spawn` for the reasons core/engine.py gives against `fork`.
SPAWN = multiprocessing.get_context("spawn")

MASTER_HANDICAP = 2.0  # interior-removal units of work this process does per step besides evaluating


@dataclass(frozen=True)
class CostEntry:
    vertex: int
    delta: float
    projects_onto: tuple[int, ...]  # surviving tetrahedra owning the hull triangles its points project onto
    is_global: bool  # computed by re-tetrahedralising everything (depends on the whole hull)


def _entry(v: int, removal: LocalRemoval | GlobalRemoval) -> CostEntry:
    if isinstance(removal, GlobalRemoval):
        return CostEntry(v, removal.delta, (), True)
    if removal.shrinks_hull:
        kept = removal.kept_cell[removal.kept_cell >= 0]
        return CostEntry(v, removal.delta, tuple(np.unique(kept).tolist()), False)
    return CostEntry(v, removal.delta, (), False)


class SerialCosts:
    """Costs and removals in this process. initial: the starting probe set (None = every point); leaks: the leak
    weighting every error is weighed with (DecimationMesh), or None."""

    def __init__(self, field: ReferenceField, metric: str, initial: np.ndarray | None = None,
                 leaks: Weighing | None = None):
        self.state = DecimationState(field, metric, initial, leaks)
        self.cached: dict[int, LocalRemoval | GlobalRemoval] = {}

    def _evaluate_here(self, vertices: list[int]) -> list[CostEntry]:
        out = []
        for v, removal in zip(vertices, self.state.removals(vertices)):
            self.cached[v] = removal
            out.append(_entry(v, removal))
        return out

    def forget(self, vertices: list[int]) -> None:
        for v in vertices:
            self.cached.pop(v, None)

    def evaluate(self, vertices: list[int]) -> list[CostEntry]:
        self.forget(vertices)
        return self._evaluate_here(vertices)

    def remove(self, v: int) -> tuple[np.ndarray, np.ndarray, bool]:
        return self.state.remove(v, self.cached.pop(v))

    def close(self) -> None:
        pass

    def __enter__(self) -> "SerialCosts":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _replica(connection: Connection, field: ReferenceField, metric: str, initial: np.ndarray | None,
             leaks: Weighing | None) -> None:
    """Worker loop: a second replica that evaluates what it is sent and applies every removal. With leaks it weighs
    with its own copy of the weighting's segment memo: a segment's visibility never changes, so both replicas' costs
    are the same; only which rays each casts differs."""
    try:
        costs = SerialCosts(field, metric, initial, leaks)
        connection.send(("ready", None))
        while True:
            command, payload = connection.recv()
            if command == "evaluate":
                stale, mine = payload
                costs.forget(stale)
                connection.send(("costs", costs._evaluate_here(mine)))
            elif command == "apply":  # the other replica computed this removal
                v, removal = payload
                costs.forget([v])
                costs.state.remove(v, removal)
            elif command == "apply_own":  # this replica computed it: apply and hand it over
                removal = costs.cached.pop(payload)
                connection.send(("removal", removal))
                costs.state.remove(payload, removal)
            elif command == "stop":
                return
    except BaseException:  # report everything, including errors while building the state
        connection.send(("error", traceback.format_exc()))


class ParallelCosts(SerialCosts):
    """This process plus one worker replica, each evaluating half of every batch."""

    def __init__(self, field: ReferenceField, metric: str, initial: np.ndarray | None = None,
                 leaks: Weighing | None = None):
        self.connection, worker_end = SPAWN.Pipe()
        self.worker = SPAWN.Process(target=_replica, args=(worker_end, field, metric, initial, leaks), daemon=True)
        try:
            self.worker.start()  # `spawn` pickles the arguments here
        except (TypeError, AttributeError, pickle.PicklingError) as error:
            self.connection.close()
            if leaks is None:
                raise
            raycaster = getattr(leaks, "raycaster", leaks)  # LeakWeighting's; the error names what failed
            raise ValueError(f"the leak-aware reference's second process needs its own copy of the raycaster, and "
                             f"{type(raycaster).__name__} cannot be sent to another process ({error}; Embree's "
                             f"scene cannot): run it with workers=1") from error
        super().__init__(field, metric, initial, leaks)
        self.owner: dict[int, int] = {}  # 0 = here, 1 = worker
        self._receive("ready")

    def _receive(self, expected: str) -> object:
        kind, payload = self.connection.recv()
        if kind == "error":
            raise RuntimeError(f"the fast reference's worker process failed:\n{payload}")
        if kind != expected:
            raise RuntimeError(f"the fast reference's worker sent {kind!r}, expected {expected!r}")
        return payload

    def evaluate(self, vertices: list[int]) -> list[CostEntry]:
        self.forget(vertices)
        mine, theirs = self._split(vertices)
        self.connection.send(("evaluate", (vertices, theirs)))
        ours = self._evaluate_here(mine)
        received = self._receive("costs")
        for entry in ours:
            self.owner[entry.vertex] = 0
        for entry in received:  # type: ignore[union-attr]
            self.owner[entry.vertex] = 1
        return ours + list(received)  # type: ignore[arg-type]

    def _split(self, vertices: list[int]) -> tuple[list[int], list[int]]:
        """Share a batch by estimated cost (hull probes cost up to ~100 interior ones): each probe goes
        to the replica with less work so far; this one starts with a handicap for the greedy loop."""
        weight = [self.state.evaluation_weight(v) for v in vertices]
        load = [MASTER_HANDICAP, 0.0]
        side = [0] * len(vertices)
        for i in sorted(range(len(vertices)), key=lambda i: -weight[i]):
            side[i] = 0 if load[0] <= load[1] else 1
            load[side[i]] += weight[i]
        return ([v for v, s in zip(vertices, side) if s == 0], [v for v, s in zip(vertices, side) if s == 1])

    def remove(self, v: int) -> tuple[np.ndarray, np.ndarray, bool]:
        if self.owner.pop(v) == 0:
            removal = self.cached.pop(v)
            self.connection.send(("apply", (v, removal)))
        else:
            self.connection.send(("apply_own", v))
            removal = self._receive("removal")  # type: ignore[assignment]
        return self.state.remove(v, removal)

    def close(self) -> None:
        if self.worker.is_alive():
            try:
                self.connection.send(("stop", None))
            except (BrokenPipeError, OSError):
                pass
            self.worker.join(timeout=5)
            if self.worker.is_alive():
                self.worker.terminate()
        self.connection.close()
