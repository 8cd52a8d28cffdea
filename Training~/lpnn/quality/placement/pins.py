"""Pinned probes: the artist's probes every placement keeps (Documentation~/pins.md).

    pins = pin_probes(positions, grid_world, cell_size)     # snap, validate, block the points near them
    pins.indices          # (P,) int64 the evaluation point each pin stands for, in the pins' order
    pins.blocked          # (N,) bool points that never become a *new* probe (the pins' own points included)
    pinned_selection(grid, ranking, pins)                  # a ranking method with its pins first
    checked_pinned_count(count, pins)                      # a budget counts the pins (smaller: an error)

The rule, once (pins.md): a pin is a world position. It stands for its nearest evaluation point (ties: the lower
index), which must lie within SNAP_RADIUS_CELLS x h (half the cell diagonal: every position inside a cell of the
grid is at most that far from one of the cell's corners) — the lighting is known only at evaluation points, so that
point's lighting is the pin's and the error counts the pin there (error 0). The probe written is the artist's own
position. No new probe comes within `min_distance` (default MIN_DISTANCE_CELLS x h) of a pin. The C# core's
Quality.Pins implements the same text; Tests/Data/pins_golden.json pins both.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
from scipy.spatial import cKDTree

from ...core.grid import EvaluationGrid
from ...core.selection import ensure_tetrahedron
from ...errors import InvalidInputError
from .decimation.decimation import MINIMUM_PROBES
from .probes_file import FORMAT_NAME

# Half the cell diagonal: the farthest a position inside a fully covered cell can be from its nearest grid corner.
SNAP_RADIUS_CELLS = math.sqrt(3.0) / 2.0
# One cell: the grid samples the lighting every h, so a new probe closer than that to an artist's probe adds nothing
# the metric can tell apart from the pin (and Unity's tetrahedra between them would be slivers). pins.md "Why".
MIN_DISTANCE_CELLS = 1.0
# Distances are compared with this slack (x h), so that an on-grid pin's grid neighbours, exactly one cell away give
# or take float32 rounding of the positions, stay candidates, and a pin exactly on the snap radius still snaps.
SLACK_CELLS = 1e-3


class PinError(InvalidInputError):
    """Pinned probes a placement cannot keep; the message names the pin and what to do."""


@dataclass(frozen=True)
class Pins:
    positions: np.ndarray  # (P, 3) float64 the artist's world positions, in the file's order
    indices: np.ndarray  # (P,) int64 the evaluation point each pin stands for
    blocked: np.ndarray  # (N,) bool never a new probe: the pins' points and those within min_distance of a pin
    min_distance: float

    @property
    def count(self) -> int:
        return int(self.indices.shape[0])

    @property
    def candidates(self) -> np.ndarray:
        """(N,) bool the points that may become new probes."""
        return ~self.blocked


def _where(position: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(c):.6g}" for c in position) + ")"


def pin_probes(positions: np.ndarray, world: np.ndarray, cell_size: float, min_distance: float | None = None) -> Pins:
    """Snap `positions` (P, 3) to the evaluation points `world` (N, 3) of cell size h and block the points within
    `min_distance` (default one cell) of a pin (module text). Errors name the bad pin and what to do."""
    h = float(cell_size)
    points = np.asarray(world, dtype=np.float64).reshape(-1, 3)
    pins = np.asarray(positions, dtype=np.float64)
    if pins.ndim != 2 or pins.shape[1] != 3:
        raise PinError(f"pinned positions must be (P, 3) world positions, got shape {list(pins.shape)}")
    if pins.shape[0] == 0:
        raise PinError("no pinned positions were given: pin at least one probe, or leave the pins out")
    bad = np.flatnonzero(~np.all(np.isfinite(pins), axis=1))
    if bad.shape[0]:
        raise PinError(f"pinned probe {int(bad[0])} is at {_where(pins[bad[0]])}, not a finite position: "
                       "fix or remove it")
    distance = MIN_DISTANCE_CELLS * h if min_distance is None else float(min_distance)
    if not (math.isfinite(distance) and distance >= 0.0):
        raise PinError(f"pin minimum distance {min_distance!r} must be a distance >= 0 in the capture's units "
                       f"(default one cell, {MIN_DISTANCE_CELLS * h:g})")
    order = np.lexsort((np.arange(pins.shape[0]), pins[:, 2], pins[:, 1], pins[:, 0]))
    same = np.flatnonzero(np.all(pins[order[1:]] == pins[order[:-1]], axis=1))
    if same.shape[0]:
        first, second = sorted((int(order[same[0]]), int(order[same[0] + 1])))
        raise PinError(f"pinned probes {first} and {second} are both at {_where(pins[first])}: remove the duplicate")
    tree = cKDTree(points)
    nearest, _ = tree.query(pins, k=1)
    indices = np.empty(pins.shape[0], dtype=np.int64)
    radius = (SNAP_RADIUS_CELLS + SLACK_CELLS) * h
    for p in range(pins.shape[0]):
        if not nearest[p] <= radius:
            raise PinError(f"pinned probe {p} at {_where(pins[p])} is {nearest[p]:.4g} from the nearest evaluation point, "
                           f"more than half a cell diagonal ({SNAP_RADIUS_CELLS * h:.4g}): it is outside the volume's "
                           "points (in use); move it inside or leave it out of the pins")
        # Ties to the lower index: every point as near as the nearest (to 1e-9 of h), the lowest index among them.
        near = np.asarray(tree.query_ball_point(pins[p], nearest[p] + 1e-9 * h), dtype=np.int64)
        gaps = np.linalg.norm(points[near] - pins[p], axis=1)
        indices[p] = int(near[gaps <= nearest[p] + 1e-9 * h].min())
    taken = np.full(points.shape[0], -1, dtype=np.int64)
    for p in range(pins.shape[0]):
        if taken[indices[p]] >= 0:
            raise PinError(f"pinned probes {int(taken[indices[p]])} and {p} ({_where(pins[taken[indices[p]]])}, "
                           f"{_where(pins[p])}) both stand for evaluation point {int(indices[p])} at "
                           f"{_where(points[indices[p]])}: keep one of them, or use a smaller cell size")
        taken[indices[p]] = p
    blocked = np.zeros(points.shape[0], dtype=bool)
    blocked[indices] = True
    if distance > 0.0:
        to_pin, _ = cKDTree(pins).query(points, k=1)
        blocked |= to_pin < distance - SLACK_CELLS * h
    return Pins(positions=pins, indices=indices, blocked=blocked, min_distance=distance)


def read_pins_json(path: str | os.PathLike, units: str | None = None) -> np.ndarray:
    """(P, 3) float64 world positions from a `*.probes.json` (file-formats.md, what `lpnn place` writes and the editor
    exports). `units`: the capture's; a file in other units is an error."""
    name = Path(path).name
    try:
        document = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise PinError(f"{path}: no such pins file: give a *.probes.json of the probes to keep") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise PinError(f"{name}: not a JSON probes file ({exc}): give a *.probes.json (file-formats.md)") from None
    if not isinstance(document, dict) or document.get("format") != FORMAT_NAME:
        raise PinError(f"{name}: not a probes file (format must be \"{FORMAT_NAME}\"): give a *.probes.json "
                       "(file-formats.md)")
    if units is not None and document.get("units") != units:
        raise PinError(f"{name}: its positions are in {document.get('units')!r}, the capture's in {units!r}: "
                       "export the pins in the capture's units")
    rows = document.get("positions")
    if not isinstance(rows, list) or not rows:
        raise PinError(f"{name} holds no positions: pin at least one probe, or leave out --keep")
    for r, row in enumerate(rows):
        if not (isinstance(row, list) and len(row) == 3
                and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in row)):
            raise PinError(f"{name}: position {r} is {row!r}, not three numbers [x, y, z]: fix the file")
    return np.asarray(rows, dtype=np.float64)


def checked_pinned_count(count: int, pins: Pins | None) -> int:
    """A budget's probe count, which counts the pins: smaller than the pins is an error naming both numbers."""
    if pins is not None and int(count) < pins.count:
        raise PinError(f"the budget keeps {int(count):,} probes but {pins.count:,} are pinned: raise the budget to at "
                       f"least {pins.count:,} probes, or pin fewer")
    return int(count)


def pinned_order(ranking: np.ndarray, pins: Pins) -> tuple[np.ndarray, int]:
    """(order, available): every point once — the pins in their order, then the ranking's points that may become
    probes in its order, then the blocked ones by index (only the tetrahedron guarantee may read past `available`)."""
    ranked = np.asarray(ranking, dtype=np.int64)
    is_pin = np.zeros(pins.blocked.shape[0], dtype=bool)
    is_pin[pins.indices] = True
    free = ranked[~pins.blocked[ranked]]
    rest = np.flatnonzero(pins.blocked & ~is_pin)
    return np.concatenate([pins.indices, free, rest]), pins.count + int(free.shape[0])


def pinned_selection(grid: EvaluationGrid, ranking: np.ndarray, pins: Pins) -> Callable[[int], np.ndarray]:
    """A ranking method with pins (pins.md): count -> the pins, then the ranking's first points that are no pin and
    not near one, completed to a tetrahedron by the same order (a count above the points available gets them all)."""
    order, available = pinned_order(ranking, pins)

    def select(count: int) -> np.ndarray:
        return ensure_tetrahedron(grid, order, order[:min(checked_pinned_count(count, pins), available)])[0]

    return select


def pinned_start(grid: EvaluationGrid, pins: Pins, start: np.ndarray) -> np.ndarray:
    """Insertion's start with pins (pins.md): the pins, then the usual start's points that are not blocked, then — only
    if those lie in one plane — the first points by the same preference (free points by index) that make a tetrahedron."""
    usual = np.asarray(start, dtype=np.int64)
    begun = np.concatenate([pins.indices, usual[~pins.blocked[usual]]])
    listed = np.zeros(pins.blocked.shape[0], dtype=bool)
    listed[begun] = True
    preference = np.concatenate([begun, np.flatnonzero(~listed & ~pins.blocked), np.flatnonzero(~listed & pins.blocked)])
    chosen = ensure_tetrahedron(grid, preference, begun)[0]
    rank_of = np.empty(preference.shape[0], dtype=np.int64)
    rank_of[preference] = np.arange(preference.shape[0])
    return chosen[np.argsort(rank_of[chosen], kind="stable")]


def pinned_smallest(pins: Pins | None) -> int:
    """The tolerance search's smallest count: every pin, and at least a tetrahedron's 4 probes."""
    return max(MINIMUM_PROBES, 0 if pins is None else pins.count)
