"""Blockwise reference: the quality yardstick for volumes too large for the reference (quality.md §3.3).

    blockwise = blockwise_reference(field, ids)        # one fast reference per overlapping block
    blockwise.ranking                                    # (N,) most important first: budgets are prefixes
    blockwise.within(tau)                                # the probes of the tolerance policy

The fast reference (reference_fast.py) costs seconds per thousand points, so a level of 10^5-10^6
points is cut into cubic blocks of BLOCK_CELLS cells per axis (by lattice id, from the grid's lowest
id). Each block is decimated with the exact greedy over its points plus a margin of MARGIN_CELLS
cells on every side (the margin's points are evaluated and may be probes, so the block's probes see
the lighting beyond its faces as the whole-level reference would); only the block's own (core)
points are kept from it. Blocks are independent, so the union is the reference's answer wherever
the lighting across a block face is reproduced within the margin.

Tolerance tau: each block keeps the smallest prefix of its decimation whose mean error over the
block with its margin is <= tau (its core points of it). Budget: one ranking of all points by the
tolerance at which each point leaves its block's answer: the point at position r (from 0) of its
block's ordering is in that answer for every tau below entry = min over counts c in [4, r] of the
block's error curve[c] (r < 4, a block's last tetrahedron: always), so any tau gives the set
{entry > tau}, and the ranking by entry (descending; ties by position in the block's ordering,
then index) nests them: a budget K is its first K points. Blocks with fewer than
MINIMUM_PROBES + 1 points with margin, or flat ones, keep every core point.

A level of 10^5-10^6 points takes an hour or more (benchmarks.md "References and scale-out"), so with `checkpoint` the finished blocks are
written to that file as they go (atomically, at most every CHECKPOINT_SECONDS, and at the end); a later call with
the same points, lighting, metric, block and margin resumes from it. A file of other inputs, or one that cannot be
read, is started afresh.
"""

from __future__ import annotations

import hashlib
import io
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from ....core.atomic import write_bytes_atomic
from .decimation import MINIMUM_PROBES
from ...metric.metric import PRIMARY_METRIC, ReferenceField
from .reference_fast import fast_decimation
from ...metric.triangulation import Frame, flatness

# The fast reference costs ~5 ms per point at any block size (measured: 4,070 points 19 s, 17,116 points 86 s), and
# every block decimates its margin again, so larger blocks cost less in all: a full lattice decimates (B + 2M)^3 / B^3
# times its points, 2.2x for blocks of 20 cells (26^3 = 17,576 points at most), 4.1x for 10. Larger blocks are also
# nearer the whole-level reference (fewer faces).
BLOCK_CELLS = 20
MARGIN_CELLS = 3  # evaluated beyond each face (benchmarks.md "References and scale-out": the answer lands ~10 % above tau on the level)
CHECKPOINT_SECONDS = 60.0  # finished blocks are written at most this often (and at the end)


@dataclass(frozen=True)
class BlockwiseReference:
    entry: np.ndarray  # (N,) float64: a point is in the tolerance answer for every tau < entry (inf: always)
    ranking: np.ndarray  # (N,) int64: by entry, descending (ties: block order, then index)
    blocks: int
    seconds: float

    def within(self, tolerance: float) -> np.ndarray:
        """Sorted indices of the blockwise tolerance answer."""
        return np.flatnonzero(self.entry > tolerance)


def _sub_field(field: ReferenceField, members: np.ndarray) -> ReferenceField:
    world = field.world[members]
    frame = Frame.for_points(world)
    return ReferenceField(world=world, local=frame.to_local(world), light=field.light[members], scale=field.scale,
                          frame=frame)


def _block_entries(task: tuple[ReferenceField, np.ndarray, np.ndarray, str] | None
                   ) -> tuple[np.ndarray, np.ndarray] | None:
    """One block (runs in a worker when `workers` > 1): its core points' entries and positions in its decimation's
    ordering; None for a block kept whole (task None: too few points with its margin, or flat)."""
    if task is None:
        return None
    field, members, core_rows, metric = task
    decimation = fast_decimation(field, metric=metric)
    curve = decimation.error_curve[1:].copy()  # curve[r] = error with r + 1 probes
    curve[np.isnan(curve)] = np.inf  # counts the decimation never held
    curve[:MINIMUM_PROBES - 1] = np.inf  # fewer than 4 probes: never an answer
    smallest_before = np.minimum.accumulate(np.concatenate([[np.inf], curve[:-1]]))  # min over counts <= r
    position = np.empty(members.shape[0], dtype=np.int64)
    position[decimation.ordering] = np.arange(members.shape[0])  # the ordering lists positions into `members`
    rank = position[core_rows]
    return np.where(rank < MINIMUM_PROBES, np.inf, smallest_before[rank]), rank


def _fingerprint(field: ReferenceField, ids: np.ndarray, block: int, margin: int, metric: str) -> str:
    """What a checkpoint's blocks depend on: the points, their lighting and ids, the metric and the blocking."""
    digest = hashlib.sha256(f"{block},{margin},{metric},{field.scale!r}".encode())
    for array in (ids, field.world, field.light):
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


@dataclass
class _Progress:
    """Blocks finished so far (restored from a checkpoint, then filled in as blocks finish)."""

    entry: np.ndarray
    position: np.ndarray
    done: np.ndarray  # (blocks,) bool

    def save(self, path: Path, fingerprint: str) -> None:
        buffer = io.BytesIO()
        np.savez(buffer, fingerprint=np.array(fingerprint), entry=self.entry, position=self.position, done=self.done)
        write_bytes_atomic(path, buffer.getvalue())

    @classmethod
    def restore(cls, path: Path | None, fingerprint: str, points: int, blocks: int) -> "_Progress":
        fresh = cls(np.full(points, np.inf), np.zeros(points, dtype=np.int64), np.zeros(blocks, dtype=bool))
        if path is None or not path.is_file():
            return fresh
        try:
            with np.load(path, allow_pickle=False) as stored:
                if str(stored["fingerprint"]) != fingerprint:
                    return fresh  # other inputs: started afresh
                restored = cls(stored["entry"], stored["position"], stored["done"])
        except (OSError, ValueError, KeyError, EOFError):  # unreadable (e.g. cut short by hand): started afresh
            return fresh
        shapes = (restored.entry.shape, restored.position.shape, restored.done.shape)
        return restored if shapes == ((points,), (points,), (blocks,)) else fresh


def blockwise_reference(field: ReferenceField, ids: np.ndarray, block: int = BLOCK_CELLS, margin: int = MARGIN_CELLS,
                        metric: str = PRIMARY_METRIC, progress: Callable[[int, int], None] | None = None,
                        workers: int = 1, checkpoint: str | os.PathLike | None = None) -> BlockwiseReference:
    """One fast reference per block with its margin (module text); `ids` (N, 3) the points' lattice ids; `workers`
    local worker processes decimate blocks side by side (core/engine.py; the same answer: blocks are independent);
    `checkpoint` a file that keeps finished blocks and resumes a run cut short (module text)."""
    if block < 1 or margin < 0:
        raise ValueError(f"block {block} must be >= 1 cell and margin {margin} >= 0 cells")
    start = time.perf_counter()
    offset = np.asarray(ids, dtype=np.int64) - np.asarray(ids, dtype=np.int64).min(axis=0)
    n = offset.shape[0]
    cell = offset // block
    keys, owner = np.unique(cell, axis=0, return_inverse=True)
    owner = owner.reshape(-1)
    cores = [np.flatnonzero(owner == b) for b in range(keys.shape[0])]
    path = None if checkpoint is None else Path(checkpoint)
    fingerprint = "" if path is None else _fingerprint(field, np.asarray(ids), block, margin, metric)
    state = _Progress.restore(path, fingerprint, n, keys.shape[0])
    pending = np.flatnonzero(~state.done)

    def tasks():  # built as they are consumed: a level's blocks with margins would not fit in memory at once
        for b in pending:
            key = keys[b]
            low, high = key * block - margin, (key + 1) * block - 1 + margin
            members = np.flatnonzero(np.all((offset >= low) & (offset <= high), axis=1))
            if members.shape[0] <= MINIMUM_PROBES or flatness(field.local[members]) is not None:
                yield None  # kept whole
            else:
                yield _sub_field(field, members), members, np.searchsorted(members, cores[b]), metric

    def results():
        from ....core.engine import Engine

        with Engine(workers if keys.shape[0] > 1 else 1) as engine:
            yield from engine.ordered(_block_entries, tasks())

    finished = keys.shape[0] - pending.shape[0]
    if progress is not None and finished:
        progress(finished, keys.shape[0])
    saved = time.perf_counter()
    for b, result in zip(pending, results()):
        if result is not None:
            state.entry[cores[b]], state.position[cores[b]] = result
        state.done[b] = True
        finished += 1
        if path is not None and time.perf_counter() - saved >= CHECKPOINT_SECONDS:
            state.save(path, fingerprint)
            saved = time.perf_counter()
        if progress is not None:
            progress(finished, keys.shape[0])
    if path is not None and pending.shape[0]:
        state.save(path, fingerprint)
    ranking = np.lexsort((np.arange(n), state.position, -state.entry)).astype(np.int64)
    return BlockwiseReference(entry=state.entry, ranking=ranking, blocks=int(keys.shape[0]),
                              seconds=time.perf_counter() - start)
