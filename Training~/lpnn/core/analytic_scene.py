"""The analytic test scene of Tests/Data/README.md: a closed-form light field and an exact box raycaster.

`features_golden.json` stores one such scene; both languages sample and ray-cast it identically, so the
golden pins the feature extractor. The same classes make synthetic scenes for other tests:
`AnalyticScene.random(seed)` builds a deterministic room with obstacles and light blobs, and
`AnalyticScene.capture()` turns any scene into a capture (grid -> SH -> features).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from . import sh as shmath
from .capture import Capture
from .features import extract_features
from .grid import EvaluationGrid
from .grid_box import Box
from .grid_builder import DEFAULT_POINT_LIMIT, build_grid
from .schema import LPNN_V1


def _vector(values: Any, size: int, what: str) -> np.ndarray:
    array = np.array(values, dtype=np.float64).reshape(-1)
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise ValueError(f"{what} needs {size} finite numbers, got {values!r}")
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class AxisBox:
    """An axis-aligned box [min, max] whose 6 faces are surfaces for the raycaster."""

    min: np.ndarray
    max: np.ndarray

    def __post_init__(self) -> None:
        lo, hi = _vector(self.min, 3, "box min"), _vector(self.max, 3, "box max")
        if np.any(lo > hi):
            raise ValueError(f"box min {lo.tolist()} exceeds max {hi.tolist()}")
        object.__setattr__(self, "min", lo)
        object.__setattr__(self, "max", hi)

    @staticmethod
    def from_json(data: dict) -> "AxisBox":
        return AxisBox(min=data["min"], max=data["max"])

    def to_json(self) -> dict:
        return {"min": self.min.tolist(), "max": self.max.tolist()}


# ------------------------------------------------------------------------------------ light field

@dataclass(frozen=True)
class LightBlob:
    """A Gaussian bump of SH: sh * exp(-|p - center|^2 / sigma^2)."""

    center: np.ndarray
    sigma: float
    sh: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _vector(self.center, 3, "blob center"))
        object.__setattr__(self, "sh", _vector(self.sh, shmath.SH_FLOATS, "blob sh"))
        sigma = float(self.sigma)
        if not (np.isfinite(sigma) and sigma > 0.0):
            raise ValueError(f"blob sigma {self.sigma!r} must be a finite number > 0")
        object.__setattr__(self, "sigma", sigma)

    @staticmethod
    def from_json(data: dict) -> "LightBlob":
        return LightBlob(center=data["center"], sigma=data["sigma"], sh=data["sh"])

    def to_json(self) -> dict:
        return {"center": self.center.tolist(), "sigma": self.sigma, "sh": self.sh.tolist()}


@dataclass(frozen=True)
class AnalyticLightField:
    """SH(p) = base + sum_b sh_b exp(-|p - center_b|^2 / sigma_b^2), in double, rounded to float32."""

    base: np.ndarray
    blobs: tuple[LightBlob, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "base", _vector(self.base, shmath.SH_FLOATS, "light field base"))
        object.__setattr__(self, "blobs", tuple(self.blobs))

    @staticmethod
    def from_json(data: dict) -> "AnalyticLightField":
        return AnalyticLightField(base=data["base"],
                                  blobs=tuple(LightBlob.from_json(b) for b in data.get("blobs", [])))

    def to_json(self) -> dict:
        return {"base": self.base.tolist(), "blobs": [b.to_json() for b in self.blobs]}

    def sample(self, positions: np.ndarray) -> np.ndarray:
        """SH (N, 27) float32 at float32 positions (N, 3) (widened to double, as a sampler gets them)."""
        p = np.asarray(positions, dtype=np.float32).astype(np.float64)
        out = np.broadcast_to(self.base, (p.shape[0], shmath.SH_FLOATS)).copy()
        for blob in self.blobs:
            d = p - blob.center
            distance_sq = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2]
            out += blob.sh[None, :] * np.exp(-distance_sq / (blob.sigma * blob.sigma))[:, None]
        return out.astype(np.float32)


# -------------------------------------------------------------------------------------- raycaster

def _slab_hit(box: AxisBox, origins: np.ndarray, directions: np.ndarray, inverse: np.ndarray,
              parallel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Slab method for one box: hit distance (R,) (inf = miss) and hit axis (R,), per README rules."""
    t_min_plane = (box.min[None, :] - origins) * inverse
    t_max_plane = (box.max[None, :] - origins) * inverse
    entering = np.where(parallel, -np.inf, np.minimum(t_min_plane, t_max_plane))
    leaving = np.where(parallel, np.inf, np.maximum(t_min_plane, t_max_plane))
    outside_slab = np.any(parallel & ((origins < box.min[None, :]) | (origins > box.max[None, :])), axis=1)
    t_near, near_axis = entering.max(axis=1), entering.argmax(axis=1)  # argmax: lowest axis on ties
    t_far, far_axis = leaving.min(axis=1), leaving.argmin(axis=1)
    miss = outside_slab | (t_near > t_far) | (t_far < 0.0)
    inside = t_near < 0.0  # origin inside: the hit is the exit
    t = np.where(miss, np.inf, np.where(inside, t_far, t_near))
    axis = np.where(inside, far_axis, near_axis)
    return t, axis


@dataclass(frozen=True)
class AnalyticBoxRaycaster:
    """Exact rays against the faces of a room box and obstacle boxes (either facing)."""

    room: AxisBox | None = None
    obstacles: tuple[AxisBox, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "obstacles", tuple(self.obstacles))

    @staticmethod
    def from_json(data: dict) -> "AnalyticBoxRaycaster":
        room = data.get("room")
        return AnalyticBoxRaycaster(room=None if room is None else AxisBox.from_json(room),
                                    obstacles=tuple(AxisBox.from_json(o) for o in data.get("obstacles", [])))

    def to_json(self) -> dict:
        return {"room": None if self.room is None else self.room.to_json(),
                "obstacles": [o.to_json() for o in self.obstacles]}

    def cast(self, origins: np.ndarray, directions: np.ndarray, max_distance: float) -> tuple[np.ndarray, np.ndarray]:
        o = np.asarray(origins, dtype=np.float64)
        d = np.asarray(directions, dtype=np.float64)
        parallel = d == 0.0
        inverse = 1.0 / np.where(parallel, 1.0, d)
        best_t = np.full(o.shape[0], np.inf)
        best_axis = np.zeros(o.shape[0], dtype=np.int64)
        surfaces = ([self.room] if self.room is not None else []) + list(self.obstacles)
        for box in surfaces:  # strict '<': on equal t the room, then earlier obstacles, win
            t, axis = _slab_hit(box, o, d, inverse, parallel)
            closer = t < best_t
            best_t = np.where(closer, t, best_t)
            best_axis = np.where(closer, axis, best_axis)
        counted = best_t <= max_distance
        distances = np.where(counted, best_t, np.inf)
        normals = np.zeros_like(o)
        rows = np.flatnonzero(counted)
        axis = best_axis[rows]
        # The axis' unit vector, turned against the ray (dot(n, d) <= 0).
        normals[rows, axis] = np.where(d[rows, axis] > 0.0, -1.0, 1.0)
        return distances, normals


# ------------------------------------------------------------------------------------------ scene

@dataclass(frozen=True)
class AnalyticScene:
    """Boxes + cell size (the volume), a light field and box surfaces: everything a capture needs."""

    cell_size: float
    boxes: tuple[Box, ...]
    light_field: AnalyticLightField
    raycaster: AnalyticBoxRaycaster = field(default_factory=AnalyticBoxRaycaster)

    def __post_init__(self) -> None:
        object.__setattr__(self, "boxes", tuple(self.boxes))

    @staticmethod
    def from_json(data: dict) -> "AnalyticScene":
        return AnalyticScene(cell_size=float(data["cell_size"]),
                             boxes=tuple(Box.from_json(b) for b in data["boxes"]),
                             light_field=AnalyticLightField.from_json(data["light_field"]),
                             raycaster=AnalyticBoxRaycaster.from_json(data))

    def to_json(self) -> dict:
        return {"cell_size": self.cell_size, "boxes": [b.to_json() for b in self.boxes],
                **self.raycaster.to_json(), "light_field": self.light_field.to_json()}

    def grid(self, point_limit: int = DEFAULT_POINT_LIMIT) -> EvaluationGrid:
        return build_grid(self.boxes, self.cell_size, point_limit)

    def capture(self, name: str = "analytic", labels: np.ndarray | None = None, label_source: str | None = None,
                grid: EvaluationGrid | None = None) -> Capture:
        """A `lpnn.features.v1` capture of this scene (on `grid`, default: the scene's own grid)."""
        points = self.grid() if grid is None else grid
        positions = points.positions
        sh = self.light_field.sample(positions)
        features, scale = extract_features(points, sh, self.raycaster)
        return Capture(ids=points.ids, positions=positions, sh=sh, features=features, schema=LPNN_V1.id,
                       feature_names=list(LPNN_V1.names), cell_size=points.cell_size, lighting_scale=scale,
                       labels=None if labels is None else np.asarray(labels, dtype=np.uint8),
                       label_source=label_source, source={"scene": name, "backend": "analytic"})

    @staticmethod
    def random(seed: int, cell_size: float = 0.5, room_size: Sequence[float] = (6.0, 3.0, 5.0),
               obstacle_count: int = 3, blob_count: int = 4) -> "AnalyticScene":
        """A deterministic synthetic room: one volume box inside it, box obstacles, coloured light blobs."""
        rng = np.random.default_rng(seed)
        size = np.asarray(room_size, dtype=np.float64)
        # Walls off the lattice by a random fraction of a cell, so no ray distance sits on a threshold.
        room_min = -size / 2.0 + rng.uniform(0.05, 0.45, 3) * cell_size
        room = AxisBox(room_min, room_min + size)
        margin = 0.1 * cell_size
        volume = Box.axis_aligned(room.min + margin, room.max - margin)
        obstacles = []
        for _ in range(obstacle_count):
            extent = rng.uniform(0.3, 0.25 * size.min(), 3)
            low = rng.uniform(room.min, room.max - extent)
            obstacles.append(AxisBox(low, low + extent))
        base = shmath.ambient(rng.uniform(0.02, 0.1, 3))
        blobs = []
        for _ in range(blob_count):
            direction = rng.normal(size=3)
            direction /= max(float(np.linalg.norm(direction)), 1e-12)
            sh = shmath.directional(direction, rng.uniform(0.2, 1.0, 3), rng.uniform(0.5, 3.0))
            sh = sh + shmath.ambient(rng.uniform(0.0, 0.5, 3))
            blobs.append(LightBlob(rng.uniform(room.min, room.max), rng.uniform(0.5, 2.0), sh))
        return AnalyticScene(cell_size=cell_size, boxes=(volume,), light_field=AnalyticLightField(base, tuple(blobs)),
                             raycaster=AnalyticBoxRaycaster(room, tuple(obstacles)))


def load_scene(data: dict) -> tuple[list[Box], float, AnalyticLightField, AnalyticBoxRaycaster]:
    """The `"scene"` object of features_golden.json -> (boxes, cell_size, light_field, raycaster)."""
    scene = AnalyticScene.from_json(data)
    return list(scene.boxes), scene.cell_size, scene.light_field, scene.raycaster
