"""A box of the evaluation grid (grid.md "Boxes"; the C# core's GridBox): a parallelepiped of centre and half-edges."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np

from .grid import GridError


@dataclass(frozen=True)
class Box:
    """A parallelepiped: centre c and half-edge vectors u, v, w (rows of `half_edges`).

    Half-edges may be zero (a flat box, a line, a point); every component must be finite.
    """

    center: np.ndarray  # (3,) float64
    half_edges: np.ndarray  # (3, 3) float64, rows u, v, w

    def __post_init__(self) -> None:
        center = np.array(self.center, dtype=np.float64).reshape(-1)
        half_edges = np.array(self.half_edges, dtype=np.float64)
        if center.shape != (3,):
            raise GridError(f"box centre needs 3 values, got shape {np.shape(self.center)}")
        if half_edges.shape != (3, 3):
            raise GridError(f"box half_edges needs 3 vectors of 3 values (u, v, w), got shape {np.shape(self.half_edges)}")
        if not np.all(np.isfinite(center)):
            raise GridError(f"box centre {center.tolist()} is not finite: every coordinate must be a finite number")
        if not np.all(np.isfinite(half_edges)):
            raise GridError(f"box half_edges {half_edges.tolist()} are not finite: every component must be a finite number")
        center.setflags(write=False)
        half_edges.setflags(write=False)
        object.__setattr__(self, "center", center)
        object.__setattr__(self, "half_edges", half_edges)

    @staticmethod
    def axis_aligned(min_corner: Sequence[float] | np.ndarray, max_corner: Sequence[float] | np.ndarray) -> "Box":
        lo = np.asarray(min_corner, dtype=np.float64).reshape(-1)
        hi = np.asarray(max_corner, dtype=np.float64).reshape(-1)
        if lo.shape != (3,) or hi.shape != (3,):
            raise GridError(f"box corners need 3 values each, got {lo.tolist()} and {hi.tolist()}")
        if np.any(lo > hi):
            raise GridError(f"box min corner {lo.tolist()} exceeds max corner {hi.tolist()}: swap them")
        return Box(center=(lo + hi) / 2.0, half_edges=np.diag((hi - lo) / 2.0))

    @staticmethod
    def from_json(data: dict) -> "Box":
        """{"center": [x, y, z], "half_edges": [[ux, uy, uz], [vx, vy, vz], [wx, wy, wz]]}."""
        try:
            return Box(center=np.asarray(data["center"], dtype=np.float64),
                       half_edges=np.asarray(data["half_edges"], dtype=np.float64))
        except (KeyError, TypeError) as exc:
            raise GridError(f"box {data!r} needs 'center' (3 numbers) and 'half_edges' (3x3 numbers)") from exc

    def to_json(self) -> dict:
        return {"center": self.center.tolist(), "half_edges": self.half_edges.tolist()}

    def corners(self) -> np.ndarray:
        """The 8 corners c +- u +- v +- w, (8, 3) float64."""
        signs = np.array([[sx, sy, sz] for sx in (-1.0, 1.0) for sy in (-1.0, 1.0) for sz in (-1.0, 1.0)])
        return self.center + signs @ self.half_edges


def validate_boxes(boxes: Iterable[Box]) -> list[Box]:
    box_list = list(boxes)
    if not box_list:
        raise GridError("no boxes: add at least one box to the volume")
    for number, box in enumerate(box_list):
        if not isinstance(box, Box):
            raise GridError(f"box {number} is a {type(box).__name__}, expected lpnn.core.grid_box.Box")
    return box_list
