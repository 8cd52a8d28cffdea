"""Light leaking through walls (Documentation~/leaks.md): an evaluation point leaks when a probe that weighs in its
interpolation is not visible from it, so the stencil blends lighting from the other side of a wall.

    leak_report(field, probes, raycaster, near_surface=..., counted=mask)   # the figures every report shows

The raycaster is the features' protocol (lpnn.core.features.Raycaster); the C# core's Quality.LeakCheck decides
exactly alike (Tests/Data/leaks_golden.json).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...core.capture import Capture
from ...core.features import Raycaster
from ...scenes.capture_geometry import capture_raycaster
from .metric import ReferenceField, probe_stencil, stencil_leaking, stencil_point_errors

# The `nearest_surface` feature is (nearest hit of the 26 rays) / (4 cells): at most 1/4 means within one cell.
NEAR_SURFACE_FEATURE = "nearest_surface"
NEAR_SURFACE_LIMIT = 0.25


@dataclass(frozen=True)
class LeakReport:
    points: int  # points counted (the report's points: in use, or all)
    leaking: int  # of those, points that leak
    leaking_error: float  # mean error at the leaking points (0 when none leaks)
    near_surface_points: int  # counted points within one cell of geometry (0 when the capture cannot say)
    near_surface_error: float  # mean error at them (nan when there are none)

    @property
    def leaking_share(self) -> float:
        return self.leaking / self.points if self.points else 0.0


def leaking_points(field: ReferenceField, probes: np.ndarray, raycaster: Raycaster) -> tuple[np.ndarray, np.ndarray]:
    """(N,) bool leaking and (N,) float64 irradiance error per point of the placement `probes` (one
    tetrahedralisation serves both); probes never leak."""
    indices, others, stencil = probe_stencil(field, probes, coherent=True)
    return stencil_leaking(field, indices, others, stencil, raycaster), stencil_point_errors(field, indices, others,
                                                                                             stencil)


def leak_report(field: ReferenceField, probes: np.ndarray, raycaster: Raycaster,
                near_surface: np.ndarray | None = None, counted: np.ndarray | None = None) -> LeakReport:
    """The leaks.md figures over the `counted` points ((N,) bool; None: all). `near_surface` ((N,) bool, None when the
    capture has no `nearest_surface` feature) marks the points within one cell of geometry."""
    leaking, errors = leaking_points(field, probes, raycaster)
    mask = np.ones(field.point_count, dtype=bool) if counted is None else np.asarray(counted, dtype=bool)
    leaks = leaking & mask
    near = np.zeros_like(mask) if near_surface is None else (np.asarray(near_surface, dtype=bool) & mask)
    return LeakReport(points=int(mask.sum()), leaking=int(leaks.sum()),
                      leaking_error=float(errors[leaks].mean()) if leaks.any() else 0.0,
                      near_surface_points=int(near.sum()),
                      near_surface_error=float(errors[near].mean()) if near.any() else float("nan"))


def near_surface_mask(feature_names: list[str], features: np.ndarray) -> np.ndarray | None:
    """(N,) bool points within one cell of geometry by the capture's `nearest_surface` feature; None without it."""
    if NEAR_SURFACE_FEATURE not in feature_names:
        return None
    return np.asarray(features[:, feature_names.index(NEAR_SURFACE_FEATURE)], dtype=np.float64) <= NEAR_SURFACE_LIMIT


def field_with_geometry(capture: Capture) -> ReferenceField:
    """The capture's reference field with its scene's surfaces when the tools can load them (an OpenArena import:
    scenes.capture_geometry), so every placement evaluated on it reports its leaking share; otherwise without."""
    return replace(ReferenceField.from_capture(capture), geometry=capture_raycaster(capture)[0])
