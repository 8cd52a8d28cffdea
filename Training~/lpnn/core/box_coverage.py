"""Which lattice points a box covers, row by row (grid.md steps 1-3; the C# core's BoxCoverage).

A point belongs to the grid when its closed cell (cube of side h centred on it) and a closed box share a point,
decided by the separating-axis theorem row by row (fixed j, k) with the 1e-9-cell tolerance of the spec. Rows are
enumerated with numpy over all candidate rows of a box at once (in chunks), and the rows of several boxes merged
into disjoint intervals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterator

import numpy as np

from .grid import GridError, round_up_significant
from .grid_box import Box

# A built grid stays within +-2^23 cells of the origin: positions h*id are float32, whose spacing at h*2^23
# is at most h, so up to there neighbouring points keep distinct positions (beyond, they may round to one).
BUILD_ID_BOUND = 2**23
CELL_TOLERANCE = 1e-9  # "exactly touching" tolerance, relative to one cell
ROW_CHUNK = 1 << 16  # candidate rows evaluated per numpy pass (bounds temporary memory)


@dataclass(frozen=True)
class BoxRange:
    """Step 1 of grid.md: a box's lattice range per axis, as Python ints."""

    lo: tuple[int, int, int]
    hi: tuple[int, int, int]

    @property
    def empty(self) -> bool:
        return any(l > h for l, h in zip(self.lo, self.hi))

    @property
    def row_count(self) -> int:
        if self.empty:
            return 0
        return (self.hi[1] - self.lo[1] + 1) * (self.hi[2] - self.lo[2] + 1)


def box_range(box: Box, h: float, number: int) -> BoxRange:
    """Lattice range [ceil(lo/h - 1e-9), floor(hi/h + 1e-9)] per axis, guarding the +-2^23 build bound."""
    u, v, w = np.abs(box.half_edges)
    reach = u + v + w + h / 2.0  # |u_a| + |v_a| + |w_a| + h/2
    lo = box.center - reach
    hi = box.center + reach
    first = np.ceil(lo / h - CELL_TOLERANCE)
    last = np.floor(hi / h + CELL_TOLERANCE)
    for axis in range(3):
        for bound, index in ((lo[axis], first[axis]), (hi[axis], last[axis])):
            if not (math.isfinite(index) and abs(index) <= BUILD_ID_BOUND):
                raise GridError(
                    f"cell size {h:g} is too small for box {number}: its bound {'xyz'[axis]} = {bound:g} is lattice "
                    f"index {index:g}, beyond the limit of +-2^23 ({BUILD_ID_BOUND:,}) cells from the origin where "
                    "float32 positions still tell neighbouring points apart; use a cell size of at least "
                    f"{round_up_significant(abs(bound) / BUILD_ID_BOUND):.3g} or move the box closer to the origin"
                )
    return BoxRange(lo=tuple(int(v) for v in first), hi=tuple(int(v) for v in last))


def dot3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a . b summed x, y, z in that order (no BLAS, no fused multiply-add), like the C# core."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def separating_axes(box: Box) -> np.ndarray:
    """Candidate SAT axes of grid.md in its order (x, y, z; v x w, w x u, u x v; e x b with e outer, b
    inner), without the exactly-zero ones (zero half-edges, parallel edges). (A, 3)."""
    u, v, w = box.half_edges
    world = np.eye(3)
    face_normals = np.array([np.cross(v, w), np.cross(w, u), np.cross(u, v)])
    edge_products = np.array([np.cross(e, b) for e in world for b in (u, v, w)])
    axes = np.concatenate([world, face_normals, edge_products])
    return axes[np.any(axes != 0.0, axis=1)]


def box_rows(box: Box, h: float, number: int, box_range: BoxRange) -> Iterator[np.ndarray]:
    """Non-empty rows of one box as (M, 4) int64 arrays [k, j, i_first, i_last], in chunks."""
    if box_range.empty:
        return
    axes = separating_axes(box)
    u, v, w = box.half_edges
    c = box.center
    # R(a) = |a.u| + |a.v| + |a.w| + (h/2)(|a_x| + |a_y| + |a_z|);  a.c summed x, y, z in order
    absolute = np.abs(axes)
    radius = (np.abs(dot3(axes, u)) + np.abs(dot3(axes, v)) + np.abs(dot3(axes, w))
              + (h / 2.0) * (absolute[:, 0] + absolute[:, 1] + absolute[:, 2]))
    a_dot_c = dot3(axes, c)
    # rows with a_x = 0 are kept when |q| <= R + 1e-9 h (|a_y| + |a_z|)
    touching = radius + CELL_TOLERANCE * h * (absolute[:, 1] + absolute[:, 2])
    if not (np.all(np.isfinite(radius)) and np.all(np.isfinite(a_dot_c))):
        raise GridError(
            f"box {number} (centre {c.tolist()}, half-edges {box.half_edges.tolist()}) with cell size {h:g} is too "
            "large to test exactly in double precision; scale the scene down"
        )
    a_x = axes[:, 0]
    zero_x = a_x == 0.0
    safe_a_x = np.where(zero_x, 1.0, a_x)
    (i_lo, j_lo, k_lo), (i_hi, j_hi, _) = box_range.lo, box_range.hi
    row_width = j_hi - j_lo + 1
    total = box_range.row_count
    for start in range(0, total, ROW_CHUNK):
        flat = np.arange(start, min(start + ROW_CHUNK, total), dtype=np.int64)
        k = k_lo + flat // row_width
        j = j_lo + flat % row_width
        # q = a_y (h j) + a_z (h k) - (a_x c_x + a_y c_y + a_z c_z), per (row, axis)
        y = (h * j.astype(np.float64))[:, None]
        z = (h * k.astype(np.float64))[:, None]
        q = (axes[None, :, 1] * y + axes[None, :, 2] * z) - a_dot_c[None, :]
        kept = np.all(~zero_x[None, :] | (np.abs(q) <= touching[None, :]), axis=1)
        end_a = (-radius[None, :] - q) / safe_a_x[None, :]
        end_b = (radius[None, :] - q) / safe_a_x[None, :]
        x_lo = np.where(zero_x[None, :], -np.inf, np.minimum(end_a, end_b)).max(axis=1, initial=-np.inf)
        x_hi = np.where(zero_x[None, :], np.inf, np.maximum(end_a, end_b)).min(axis=1, initial=np.inf)
        # Clamped to the box's own i range (as the C# core does): an axis with a tiny a_x gives a huge
        # interval, and the float -> int conversion needs bounded values.
        first = np.clip(np.ceil(x_lo / h - CELL_TOLERANCE), i_lo, i_hi + 1)
        last = np.clip(np.floor(x_hi / h + CELL_TOLERANCE), i_lo - 1, i_hi)
        kept &= first <= last
        if np.any(kept):
            yield np.stack([k[kept], j[kept], first[kept].astype(np.int64), last[kept].astype(np.int64)], axis=1)


def merge_rows(rows: np.ndarray) -> np.ndarray:
    """Union of row intervals [k, j, first, last] -> disjoint, non-adjacent intervals in grid order.

    Sweep with +1 at `first` and -1 at `last + 1`: every row's events sum to zero, so one global
    cumulative sum is the per-row coverage count (no reset needed). Starts sort before ends at the
    same position, so touching intervals merge.
    """
    if rows.shape[0] == 0:
        return rows.reshape(0, 4)
    count = rows.shape[0]
    k = np.concatenate([rows[:, 0], rows[:, 0]])
    j = np.concatenate([rows[:, 1], rows[:, 1]])
    position = np.concatenate([rows[:, 2], rows[:, 3] + 1])
    delta = np.concatenate([np.ones(count, np.int64), -np.ones(count, np.int64)])
    order = np.lexsort((-delta, position, j, k))
    k, j, position, delta = k[order], j[order], position[order], delta[order]
    coverage = np.cumsum(delta)
    before = coverage - delta
    starts = np.flatnonzero((before == 0) & (coverage > 0))
    ends = np.flatnonzero((before > 0) & (coverage == 0))
    return np.stack([k[starts], j[starts], position[starts], position[ends] - 1], axis=1)
