"""The placement error metric (quality.md §2).

For every evaluation point (all grid points of a capture) the lighting interpolated from the probe
set is compared with the dense reference, per direction of the fixed set D14 (features.md) and per
RGB channel: 42 numbers per point, never averaged first (averaging over a symmetric set keeps only
the DC term: LumiProbes bug B5).

- irradiance (primary): e(p) = sum|E_int - E_ref| / (sum(|E_int| + |E_ref|) + 42 eps S), in [0, 1]
  (features.md's rel(): about half the plain relative error when it is small, and bounded, so a
  black point that receives leaked light counts 1, not 1/eps)
- smape (LumiProbes-style): e(p) = mean over the 42 YCoCg values of |x - y| / (|x| + |y| + eps S)

S is the scene scale (features.md: median DC luminance of the capture; the capture header's
`lighting_scale`) and eps = 0.01, so points darker than 1 % of the typical brightness cannot blow
the relative error up, and multiplying all lighting by any a > 0 leaves both errors unchanged.
A capture's error is the mean (and the 95th percentile, linear interpolation) of e over all its
points; the probes themselves have e = 0.
"""

from __future__ import annotations

import math

from dataclasses import dataclass, replace
from functools import cached_property
from typing import Callable

import numpy as np

from ...errors import InvalidInputError
from ...core import sh as shmath
from ...core.capture import Capture
from ...core.in_use_section import in_use_points
from ...core.features import D14, Raycaster, scene_scale
from .leak_rule import SegmentVisibility, stencil_leaks
from .location import Stencil, locate_local
from .metric_kernel import IRRADIANCE, SMAPE, run_rows, stencil_errors, stencil_irradiance_errors
from .triangulation import Frame, Tetrahedralization, assembled, checked_positions, tetrahedralize

METRIC_EPSILON = 0.01
LIGHT_VALUES = D14.shape[0] * 3
METRIC_NAMES = ("irradiance", "smape")
PRIMARY_METRIC = "irradiance"
PERCENTILE = 95.0
CHUNK_POINTS = 65_536  # rows per pass: per-row arithmetic is unchanged, temporaries stay small at 10^6 points


class MetricError(InvalidInputError):
    """The metric cannot be computed from these inputs; the message names the bad value."""


@dataclass(frozen=True)
class ReferenceField:
    """The dense lighting a placement must reproduce, pre-evaluated in the metric's directions."""

    world: np.ndarray  # (N, 3) float64 evaluation points (= candidate probe positions)
    local: np.ndarray  # (N, 3) float64 in `frame`
    light: np.ndarray  # (N, 42) float64 E(p, d) over D14, direction-major RGB
    scale: float  # scene scale S
    frame: Frame
    in_use: np.ndarray | None = None  # (N,) bool points where dynamic objects go (in-use.md); None: not known
    geometry: Raycaster | None = None  # the scene's surfaces, when known: placements then report leaks (leaks.md)

    @property
    def point_count(self) -> int:
        return int(self.world.shape[0])

    @cached_property
    def ycocg(self) -> np.ndarray:
        """(N, 42) float64: `light` in YCoCg, row by row the same values; computed on first use (the SMAPE metric,
        reports), not by the tolerance search, which reads irradiance only (0.34 GB and ~1 s saved at 10^6 points)."""
        out = np.empty_like(self.light)
        for start in range(0, self.point_count, CHUNK_POINTS):
            stop = min(start + CHUNK_POINTS, self.point_count)
            rgb = self.light[start:stop].reshape(-1, D14.shape[0], 3)
            out[start:stop] = shmath.rgb_to_ycocg(rgb).reshape(-1, LIGHT_VALUES)
        return out

    def values(self, metric: str) -> np.ndarray:
        return self.ycocg if checked_metric(metric) == "smape" else self.light

    @staticmethod
    def from_sh(positions: np.ndarray, sh: np.ndarray, scale: float | None = None) -> "ReferenceField":
        world = checked_positions(positions, "evaluation point positions")
        values = np.asarray(sh)
        if values.shape != (world.shape[0], shmath.SH_FLOATS):
            raise MetricError(f"reference SH must have shape ({world.shape[0]}, 27), got {list(values.shape)}")
        bad = np.flatnonzero(~np.all(np.isfinite(values), axis=1))
        if bad.shape[0]:
            column = int(np.flatnonzero(~np.isfinite(values[bad[0]]))[0])
            raise MetricError(
                f"reference SH of point {int(bad[0])} is not finite (sh[{'rgb'[column // 9]},{column % 9}] = "
                f"{values[bad[0], column]}; {bad.shape[0]:,} points affected): re-bake or re-import the lighting")
        s = scene_scale(values) if scale is None else float(scale)
        if not (np.isfinite(s) and s > 0.0):
            raise MetricError(f"scene scale {scale!r} must be a finite number > 0")
        n = world.shape[0]
        light = np.empty((n, LIGHT_VALUES))
        for start in range(0, n, CHUNK_POINTS):  # row by row the same values; no (N, 42) temporaries
            stop = min(start + CHUNK_POINTS, n)
            light[start:stop] = shmath.evaluate(values[start:stop], D14).reshape(-1, LIGHT_VALUES)  # (M, 14, 3)
        frame = Frame.for_points(world)
        return ReferenceField(world=world, local=frame.to_local(world), light=light, scale=s, frame=frame)

    @staticmethod
    def from_capture(capture: Capture) -> "ReferenceField":
        field_ = ReferenceField.from_sh(capture.positions, capture.sh, capture.lighting_scale)
        return replace(field_, in_use=in_use_points(capture))


def checked_metric(metric: str) -> str:
    if metric not in METRIC_NAMES:
        raise MetricError(f"unknown metric {metric!r}: use one of {', '.join(METRIC_NAMES)}")
    return metric


def irradiance_error(interpolated: np.ndarray, reference: np.ndarray, scale: float) -> np.ndarray:
    """Symmetric relative irradiance error per point: rows of 42 values -> (M,), in [0, 1]."""
    floor = LIGHT_VALUES * METRIC_EPSILON * scale
    magnitude = (np.abs(interpolated) + np.abs(reference)).sum(axis=1)
    return np.abs(interpolated - reference).sum(axis=1) / (magnitude + floor)


def smape_error(interpolated: np.ndarray, reference: np.ndarray, scale: float) -> np.ndarray:
    """YCoCg SMAPE per point (values already in YCoCg): rows of 42 values -> (M,), in [0, 1]."""
    floor = METRIC_EPSILON * scale
    return np.mean(np.abs(interpolated - reference) / (np.abs(interpolated) + np.abs(reference) + floor), axis=1)


POINT_ERRORS: dict[str, Callable[[np.ndarray, np.ndarray, float], np.ndarray]] = {
    "irradiance": irradiance_error,
    "smape": smape_error,
}


@dataclass(frozen=True)
class ErrorSummary:
    mean: float
    p95: float
    per_point: np.ndarray  # (N,)


def guarded_ratio(value: float, reference: float) -> float:
    """value / reference; 0 / 0 is 1 (equal), a non-zero value over a zero reference is inf."""
    if reference > 0:
        return value / reference
    return 1.0 if value == 0 else math.inf


def _checked_errors(per_point: np.ndarray) -> np.ndarray:
    errors = np.asarray(per_point, dtype=np.float64)
    if errors.shape[0] == 0:
        raise MetricError("no evaluation points: the error of an empty capture is undefined")
    return errors


def summarize(per_point: np.ndarray) -> ErrorSummary:
    errors = _checked_errors(per_point)
    return ErrorSummary(mean=float(np.mean(errors)), p95=float(np.percentile(errors, PERCENTILE)), per_point=errors)


def checked_probes(field: ReferenceField, probes: np.ndarray) -> np.ndarray:
    indices = np.asarray(probes)
    if indices.ndim != 1 or not (np.issubdtype(indices.dtype, np.integer) or indices.shape[0] == 0):
        raise MetricError(f"probe indices must be a 1-D integer array, got {indices.dtype} {list(indices.shape)}")
    indices = indices.astype(np.int64)
    n = field.point_count
    out_of_range = np.flatnonzero((indices < 0) | (indices >= n))
    if out_of_range.shape[0]:
        raise MetricError(f"probe index {int(indices[out_of_range[0]])} is outside the {n:,} evaluation points")
    ordered = np.sort(indices)
    repeated = ordered[1:][ordered[1:] == ordered[:-1]]
    if repeated.shape[0]:
        raise MetricError(f"probe index {int(repeated[0])} is listed more than once")
    return indices


def probe_mesh(field: ReferenceField, probes: np.ndarray, coherent: bool = False, points: np.ndarray | None = None,
               tets: np.ndarray | None = None, mesh: Tetrahedralization | None = None,
               start: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, Tetrahedralization, Stencil]:
    """probe_stencil plus the probes' tetrahedralisation (its vertices are positions in the checked probe indices).
    `points` (ascending point indices, none a probe): locate only those instead of every other point (batched
    refinement re-evaluates only the points whose stencil changed). `tets` (T, 4), positions in `probes`: the
    tetrahedralisation when it is already known (derived by batched refinement), instead of tetrahedralising again;
    `mesh`: the same, already assembled (triangulation.assembled_after_removal); `start`: a tetrahedron of `mesh` near
    each of `points`, where its walk starts (location.locate_local)."""
    indices = checked_probes(field, probes)
    tri = (mesh if mesh is not None else tetrahedralize(field.world[indices], field.frame, indices) if tets is None
           else assembled(field.world[indices], field.frame, tets))
    if points is None:
        is_probe = np.zeros(field.point_count, dtype=bool)
        is_probe[indices] = True
        others = np.flatnonzero(~is_probe)
    else:
        others = np.asarray(points, dtype=np.int64)
    return indices, others, tri, locate_local(tri, field.local[others], coherent, start)


def probe_stencil(field: ReferenceField, probes: np.ndarray, coherent: bool = False
                  ) -> tuple[np.ndarray, np.ndarray, Stencil]:
    """Checked probe indices, the other points (M,) and their stencils (indices into the probes);
    coherent: location.locate_local's walk from the previous point (the errors' own path)."""
    indices, others, _, stencil = probe_mesh(field, probes, coherent)
    return indices, others, stencil


def error_floor(metric: str, scale: float) -> float:
    """The floor the compiled per-point errors add to a point's denominator (POINT_ERRORS' own): 42 eps S for the
    irradiance error (its sum over the 42 values), eps S for each SMAPE term."""
    return (LIGHT_VALUES * METRIC_EPSILON if metric == "irradiance" else METRIC_EPSILON) * scale


def stencil_point_errors(field: ReferenceField, indices: np.ndarray, others: np.ndarray, stencil: Stencil,
                         metric: str = PRIMARY_METRIC) -> np.ndarray:
    """Per-point errors (N,), 0 at the probes: metric_kernel.stencil_errors, the numbers of
    POINT_ERRORS applied to shmath.blend's interpolation, without (M, 42) temporaries."""
    floor = error_floor(metric, field.scale)
    errors = np.zeros(field.point_count)
    if metric == "irradiance" and stencil.vertices.shape[1] == 4:
        run_rows(stencil_irradiance_errors, others.shape[0], field.values(metric), indices, stencil.vertices,
                 stencil.weights, others, floor, errors)
    else:
        run_rows(stencil_errors, others.shape[0], field.values(metric), indices, stencil.vertices, stencil.weights,
                 others, floor, IRRADIANCE if metric == "irradiance" else SMAPE, errors)
    return errors


def point_errors(field: ReferenceField, probes: np.ndarray, metric: str = PRIMARY_METRIC) -> np.ndarray:
    """Per-point error (N,) of the placement `probes` (indices into the field's points)."""
    checked_metric(metric)
    return stencil_point_errors(field, *probe_stencil(field, probes, coherent=True), metric)


def placement_error(field: ReferenceField, probes: np.ndarray, metric: str = PRIMARY_METRIC) -> ErrorSummary:
    return summarize(point_errors(field, probes, metric))


def mean_placement_error(field: ReferenceField, probes: np.ndarray, metric: str = PRIMARY_METRIC) -> float:
    """placement_error(...).mean without the p95 (a partition of every point: the tolerance search reads the mean)."""
    return float(np.mean(_checked_errors(point_errors(field, probes, metric))))


@dataclass(frozen=True)
class PlacementQuality:
    probes: int
    irradiance: ErrorSummary
    smape: ErrorSummary
    in_use_error: float = math.nan  # mean irradiance error at the points in use (NaN: not known, or none)
    leaking: float = math.nan  # share of the points in use (else of all) that leak (leaks.md); NaN: no geometry


def in_use_mean(field: ReferenceField, per_point: np.ndarray) -> float:
    """Mean of per-point errors over the field's points in use (in-use.md); NaN when not known or empty."""
    if field.in_use is None or not field.in_use.any():
        return math.nan
    return float(np.mean(np.asarray(per_point)[field.in_use]))


@dataclass(frozen=True)
class Evaluated:
    """A placement located afresh (probe_stencil's checked probe indices, the other points and their stencils, the
    coherent walk's) and its per-point irradiance errors (N,): what evaluate_placement would compute first."""

    indices: np.ndarray
    others: np.ndarray
    stencil: Stencil
    errors: np.ndarray

    @property
    def mean_error(self) -> float:
        return float(np.mean(_checked_errors(self.errors)))


def evaluated(field: ReferenceField, probes: np.ndarray) -> Evaluated:
    """The placement `probes` located afresh and its irradiance errors (mean_error: mean_placement_error's number)."""
    indices, others, stencil = probe_stencil(field, probes, coherent=True)
    return Evaluated(indices, others, stencil, stencil_point_errors(field, indices, others, stencil, "irradiance"))


def evaluate_placement(field: ReferenceField, probes: np.ndarray, known: Evaluated | None = None,
                       segments: SegmentVisibility | None = None) -> PlacementQuality:
    """Both metrics for one placement (one tetrahedralisation). `known`: `probes`' own evaluated() (a placement that
    checked its answer afresh: refined_insertion), not computed again; `segments`: remembered segments of the field's
    geometry between its points (the placement's own, leak_aware.LeakWeighting.remembering): the leak share asks them
    first, the same answers with fewer rays."""
    located = evaluated(field, probes) if known is None else known
    if known is not None and not np.array_equal(known.indices, np.asarray(probes, dtype=np.int64)):
        raise MetricError("the known evaluation is of another placement: evaluate this one afresh (known=None)")
    indices, others, stencil = located.indices, located.others, located.stencil
    irradiance = summarize(located.errors)
    return PlacementQuality(probes=int(indices.shape[0]), irradiance=irradiance,
                            smape=summarize(stencil_point_errors(field, indices, others, stencil, "smape")),
                            in_use_error=in_use_mean(field, irradiance.per_point),
                            leaking=_leaking_share(field, indices, others, stencil, segments))


def stencil_leaking(field: ReferenceField, indices: np.ndarray, others: np.ndarray, stencil: Stencil,
                    raycaster: Raycaster) -> np.ndarray:
    """(N,) bool: the points among `others` that leak under their stencils (leaks.md; vertices are positions in the
    probe indices `indices`); probes and points not asked for never do."""
    leaking = np.zeros(field.point_count, dtype=bool)
    leaking[others] = stencil_leaks(field.world[others], field.world[indices], stencil.vertices, stencil.weights,
                                    raycaster)
    return leaking


def checked_segments(segments: SegmentVisibility, field: ReferenceField) -> SegmentVisibility:
    """`segments` when they remember segments between `field`'s points (MetricError otherwise)."""
    if segments.positions.shape[0] != field.point_count:
        raise MetricError(f"the remembered segments are of {segments.positions.shape[0]:,} points, the field has "
                          f"{field.point_count:,}: remember them for this field (LeakWeighting.remembering)")
    return segments


def _leaking_share(field: ReferenceField, indices: np.ndarray, others: np.ndarray, stencil: Stencil,
                   segments: SegmentVisibility | None = None) -> float:
    """The share of the points in use (all points when not known) that leak under this stencil (leaks.md); NaN
    without the scene's geometry. Probes never leak. `segments`: remembered segments of field.geometry (the answers
    of stencil_leaks, fewer rays)."""
    if field.geometry is None:
        return math.nan
    if segments is None:
        leaking = stencil_leaking(field, indices, others, stencil, field.geometry)
    else:
        if segments.raycaster is not field.geometry:
            raise MetricError("the remembered segments must come from the field's own geometry")
        leaking = np.zeros(field.point_count, dtype=bool)
        leaking[others] = checked_segments(segments, field).stencil_leaks(others, indices, stencil.vertices,
                                                                          stencil.weights)
    counted = field.in_use if field.in_use is not None and field.in_use.any() else np.ones_like(leaking)
    return float(np.count_nonzero(leaking & counted)) / float(np.count_nonzero(counted))
