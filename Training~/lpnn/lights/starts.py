"""Where a fit's lights start: at the peaks of the baked light, the grid's cells as fallback (lights.md §4).

The lightmaps say where the lights are. A point light at height h over a flat surface gives it, at tangential
distance rho from the foot of the light, q3map2's
    E(rho) = 7500 I cos / d^2 = (7500 I / h^2) (h^2 / (h^2 + rho^2))^(3/2)  bytes
(light_ydnar.c, LightContributionToSample: inverse square and Lambert cosine), a bump whose top is under the
light and whose width grows with h (half the peak at rho = 0.766 h). So:

1. the baked light of every target point, in bytes: its radiance over its albedo (target.py), where the albedo
   is bright enough to divide by (LIGHT_MIN_ALBEDO), and whether its largest channel is saturated;
2. peaks: points at least as bright as every other point within PEAK_RADIUS (ties to the lower index, so a
   saturated plateau gives one peak per PEAK_RADIUS);
3. per peak, the bump above fitted to the light of the points within FIT_RADIUS on its plane (normals within
   FIT_COSINE, off the plane by at most FIT_PLANE_OFFSET): E = alpha s(|t - c|; h) + beta + g.t (a plane of the
   other lights' light, smooth over the window) by least squares for each height of HEIGHTS and each foot c among
   the plane's points within PEAK_RADIUS of the peak (the top of a bright light is a saturated plateau whose first
   point is not its centre), keeping the pair of least residual; saturated points (largest channel >= SATURATED
   bytes) are left out of the fit (ColorToBytes clamps them); a peak with too few points gets DEFAULT_HEIGHT; one
   whose bump is lower than MIN_BUMP bytes is no light's (ambient, or a plateau);
4. the start: the foot pushed out along the peak's normal by its height (halved down to MIN_HEIGHT until it is in
   open space, dropped if never), with the estimated intensity alpha h^2 / 7500 (the fitted height's);
5. merged: highest bump (alpha) first, ties to the lower index — the surface nearest a light sees its sharpest,
   best-determined bump, while a far wall's broad one says little of the height —, a start within
   MERGE_DISTANCE of one kept is dropped; at most MAX_STARTS are kept;
6. the grid as fallback: the open cell centres of the --grid (optimise.initial_grid) farther than
   FALLBACK_DISTANCE from every start above (where nothing peaks: dim regions, or light from surfaces the fit
   recovers otherwise).

With spotlights (fit_scene(spots=True)), spotlights also start where q3map2 spotlights hang over the floor they light
(ceiling_starts): a spotlight pointing down lights a disc of the floor, brightest at its centre under the light,
where the point light's bump of step 3 puts the light at the bump's height, not at the fixture's. So:

7. every peak (within SPOT_PEAK_RADIUS: spotlights hang closer together than the point lights' PEAK_RADIUS) on a
   surface facing up (normal within FLOOR_COSINE of +z) and at least MIN_BUMP bytes bright starts a spotlight
   CLEARANCE below the nearest surface above it or above any of CEILING_STEPS around it (a tilted spotlight's disc
   peaks beside its small fixture), if that surface is at most SPOT_REACH above (moved sideways by the
   first open one of SIDE_STEPS when that is in solid: a peak at the foot of a wall), with the estimated intensity
   light h^2 / 7500 (a light at height h on its axis); merged as in step 5, brightest first. These and the copies of
   the point starts (pipeline.spotlight_starts) are kept only where something other than the sky is above within
   SPOT_REACH, straight up or up from one of the CEILING_STEPS (under_a_ceiling): a spotlight hangs from something.

With spotlights, they also start under the fixtures they hang from (fixture_starts): a mapper hangs a spotlight just
under the panel drawn with a light texture, which its disc on the floor does not show when the discs of neighbours
overlap (no floor peak under it) or the floor peak's column misses the panel. So:

9. every face facing down (normal within FLOOR_COSINE of -z) of a shader whose name says "light" (the surface-light
   candidates' word, pipeline.names_a_light) starts a spotlight CLEARANCE below its centre, if that is open and a
   surface lies below it within SPOT_REACH, with the estimated intensity light h^2 / 7500 (the baked light of the
   target point nearest the surface below, h the height above it; a point too dark to read gives none, and the fit
   its starts' median); merged as in step 5, the brightest floor first. These come first: the ceiling starts of step 7
   within the merge distance of one of them are dropped.

Whether a level's fit starts spotlights at all (fit_scene(spots=None), pipeline.fits_spots) is read from the same
floor peaks:

8. at each floor peak of step 7, the plane window of step 3 (feet within SPOT_PEAK_RADIUS) is fitted twice: by the
   point light's bump (every height of HEIGHTS) and by a downward spotlight's disc hanging at step 7's height (the
   bump cut by q3map2's cone, emitters.cone_factor, of every radiusByDist of DISC_CONES); the disc gain is 1 - the
   disc's residual / the bump's. The level is lit by spotlights when the median gain over its floor peaks is at least
   SPOT_LEVEL_GAIN.

Deterministic: no random numbers; every tie is broken by index.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.spatial import cKDTree

from ..scenes.lightgrid import LINEAR_PER_BYTE
from .emitters import cone_factor
from .model import BYTE_MAX, POINT_SCALE
from .optimise import CLEARANCE

LIGHT_MIN_ALBEDO = 0.05  # mean albedo below which a point's light (radiance / albedo) is not read
PEAK_RADIUS = 96.0  # Quake units: a peak is the brightest point within this distance
PEAK_NEIGHBOURS = 64  # the nearest points compared with a candidate peak (bounded by PEAK_RADIUS)
FIT_RADIUS = 320.0  # Quake units around a peak whose light the bump is fitted to
FIT_COSINE = 0.95  # normals within ~18 degrees of the peak's are on its plane
FIT_PLANE_OFFSET = 8.0  # Quake units off the peak's plane
FIT_MIN_POINTS = 6
SATURATED = BYTE_MAX - 2.0  # bytes: clamped points say nothing of the bump's shape
HEIGHTS = (24.0, 32.0, 48.0, 64.0, 96.0, 128.0, 192.0, 256.0)  # Quake units tried per peak
DEFAULT_HEIGHT = 64.0
MIN_HEIGHT = CLEARANCE  # closer to a surface, the fit's clearance penalty pushes the light away
MIN_BUMP = 8.0  # bytes of bump (alpha) below which a peak is not a light's
MERGE_DISTANCE = 64.0  # Quake units
MAX_STARTS = 160
FALLBACK_DISTANCE = 512.0  # Quake units (13 m)
# step 7 (spotlights): chosen on aggressor (training), whose 47 spotlights hang 3.3 m apart, 12 units under the
# ceiling (benchmarks.md "The light rig")
SPOT_PEAK_RADIUS = 64.0  # Quake units
FLOOR_COSINE = 0.9
SPOT_REACH = 512.0  # Quake units above the floor peak
# a spotlight start in solid moves sideways by the first of these that is open (x, y; the 8 directions at 16 units)
SIDE_STEPS = tuple(np.array([16.0 * dx, 16.0 * dy, 0.0]) for dx, dy in
                   ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, 1), (1, -1), (-1, -1)))
# the ceiling above a floor peak: the nearest surface above the peak or above any of these (the 8 directions at 16
# units): aggressor's spotlights hang 12 units under 16-unit panels, tilted so that their discs' centres are 12 units
# off the panel's centre, outside it
CEILING_STEPS = SIDE_STEPS

# step 8, chosen on the training levels aggressor, kaos and oa_bases3 only (benchmarks.md "The light rig",
# 2026-11-27): the median gain was 0.0127 on aggressor (47 downward spotlights), 0.0017 on kaos (0.0004 with CEILING_STEPS) and 0.0000 on
# oa_bases3 (none); the held-out q3dm6ish (no spotlight) scores 0.040, reported only: the gain says a disc fits the
# floor's peaks, not that the level was lit by spotlights
DISC_CONES = (0.3, 0.45, 0.6, 0.75, 0.9, 1.2, 1.6)  # radiusByDist tried (half-angles 17-58 degrees)
SPOT_LEVEL_GAIN = 0.0075  # median disc gain from which a level's fit starts spotlights
OpenTest = Callable[[np.ndarray], np.ndarray]
DistanceUp = Callable[[np.ndarray], np.ndarray]  # (N, 3) Quake points -> (N,) units to the first surface above (inf)
# (or below: fixture_starts' distance_down)
UP = np.array([0.0, 0.0, 1.0])  # Quake's up: a downward spotlight hangs above its floor peak along it
CEILING_PROBE_LIFT = 1.0  # units above a floor peak the ray up to the ceiling starts, so its own floor is not the hit


@dataclass(frozen=True)
class PeakSettings:
    peak_radius: float = PEAK_RADIUS
    fit_radius: float = FIT_RADIUS
    min_bump: float = MIN_BUMP
    merge_distance: float = MERGE_DISTANCE
    max_starts: int = MAX_STARTS
    fallback_distance: float = FALLBACK_DISTANCE


DEFAULT_PEAKS = PeakSettings()


@dataclass(frozen=True)
class Starts:
    positions: np.ndarray  # (J, 3) Quake units
    intensities: np.ndarray  # (J,) estimated q3map2 intensity (peaks), 0 for grid cells (no estimate)
    from_peaks: int  # the first from_peaks positions come from peaks, the rest from the grid


def baked_light(radiance: np.ndarray, albedo: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((N,) the baked light of each point in bytes, the mean over RGB of radiance / albedo, NaN where the albedo is
    too dark to divide by; (N,) bool its largest channel is saturated, at SATURATED bytes or more: ColorToBytes
    scales the colour down there, keeping its hue)."""
    mean_albedo = albedo.mean(axis=1)
    readable = mean_albedo >= LIGHT_MIN_ALBEDO
    light = np.full(len(radiance), np.nan)
    saturated = np.zeros(len(radiance), bool)
    channels = radiance[readable] / (np.maximum(albedo[readable], LIGHT_MIN_ALBEDO) * LINEAR_PER_BYTE)
    light[readable] = channels.mean(axis=1)
    saturated[readable] = channels.max(axis=1) >= SATURATED
    return light, saturated


def light_peaks(points: np.ndarray, light: np.ndarray, radius: float = PEAK_RADIUS) -> np.ndarray:
    """Indices (ascending) of the points at least as bright as every readable point within `radius`; an equal
    neighbour of lower index wins the tie."""
    readable = np.flatnonzero(np.isfinite(light))
    if len(readable) == 0:
        return readable
    tree = cKDTree(points[readable])
    k = min(PEAK_NEIGHBOURS, len(readable))
    distance, neighbour = tree.query(points[readable], k=k, distance_upper_bound=radius)
    distance, neighbour = distance.reshape(len(readable), k), neighbour.reshape(len(readable), k)
    present = np.isfinite(distance)
    other = readable[np.where(present, neighbour, 0)]
    own = readable[:, None]
    own_light, other_light = light[own], light[other]
    beaten = present & (other != own) & ((other_light > own_light) | ((other_light == own_light) & (other < own)))
    return readable[~beaten.any(axis=1)]


def bump_profile(rho: np.ndarray, height: float | np.ndarray) -> np.ndarray:
    """A point light's light on a plane at tangential distance rho, relative to its foot (module docstring)."""
    return (height * height / (height * height + rho * rho)) ** 1.5


@dataclass(frozen=True)
class Bump:
    foot: int  # index (into the centres given to fit_bump) of the light's foot
    height: float  # Quake units
    alpha: float  # bytes at the foot


def spot_disc_profile(rho: np.ndarray, height: float | np.ndarray, cone: float | np.ndarray) -> np.ndarray:
    """A downward q3map2 spotlight's light on the floor at tangential distance rho from its foot, relative to its foot:
    the point light's bump times q3map2's cone (emitters.cone_factor) of radiusByDist `cone` at `height` down the axis
    and rho off it (light_ydnar.c LightContributionToSample)."""
    return bump_profile(rho, height) * cone_factor(height, rho, np.asarray(cone))


def _foot_distances(tangential: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """(C, M) the distance of every plane point (M, 3) from every candidate foot (C, 3)."""
    return np.linalg.norm(tangential[None, :, :] - centres[:, None, :], axis=2)


def _bump_fits(tangential: np.ndarray, light: np.ndarray, rho: np.ndarray,
               normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """_profile_fits of the point light's bump at every height of HEIGHTS and foot (rho: _foot_distances): (alpha,
    residual), each (H, C)."""
    return _profile_fits(tangential, light, bump_profile(rho[None], np.asarray(HEIGHTS)[:, None, None]), normal)


def _profile_fits(tangential: np.ndarray, light: np.ndarray, profiles: np.ndarray,
                  normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each profile (..., M) alpha p + beta + g.t fitted to `light` (M,) at plane points `tangential` (M, 3, in the
    plane of `normal`) by least squares, alpha >= 0: (alpha (...), residual sum of squares (...))."""
    count = len(light)
    u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    background = np.stack([np.ones(count), tangential @ u, tangential @ v], axis=1)  # (M, 3)
    projector = np.linalg.pinv(background)  # (3, M): least-squares coefficients of the background

    def without_background(values: np.ndarray) -> np.ndarray:
        return values - (values @ projector.T) @ background.T

    profile = without_background(profiles)
    residual_light = without_background(light)
    variance = np.einsum("...m,...m->...", profile, profile)
    covariance = np.einsum("...m,m->...", profile, residual_light)
    alpha = np.where((variance > 0) & (covariance > 0), covariance / np.maximum(variance, 1e-300), 0.0)
    return alpha, float(residual_light @ residual_light) - alpha * covariance


def fit_bump(tangential: np.ndarray, light: np.ndarray, centres: np.ndarray, normal: np.ndarray) -> Bump:
    """The bump alpha s(|t - c|; h) + beta + g.t (a plane of other light: the other lights' light is smooth over
    the window) that fits `light` at plane points `tangential` (M, 3, in the plane of `normal`) best by least
    squares (alpha >= 0), over every foot c of `centres` (C, 3) and height h of HEIGHTS (ties: the lower index,
    the lower height); Bump(0, DEFAULT_HEIGHT, 0) with fewer than FIT_MIN_POINTS points."""
    if len(light) < FIT_MIN_POINTS or len(centres) == 0:
        return Bump(0, DEFAULT_HEIGHT, 0.0)
    alpha, residual = _bump_fits(tangential, light, _foot_distances(tangential, centres), normal)  # (H, C)
    best = int(np.argmin(residual.T.ravel()))  # centre-major: the first minimum is the lowest centre, then height
    centre, height = divmod(best, len(HEIGHTS))
    return Bump(centre, float(HEIGHTS[height]), float(alpha[height, centre]))


def disc_gain(tangential: np.ndarray, light: np.ndarray, centres: np.ndarray, normal: np.ndarray,
              height: float) -> float:
    """Step 8: 1 - the residual of the best spotlight disc hanging at `height` (cones DISC_CONES, feet `centres`) / the
    residual of the best point bump (fit_bump's heights and feet); > 0 where the disc fits the light better, 0 when
    neither leaves any residual or there are fewer than FIT_MIN_POINTS points."""
    if len(light) < FIT_MIN_POINTS or len(centres) == 0:
        return 0.0
    rho = _foot_distances(tangential, centres)
    bump = _bump_fits(tangential, light, rho, normal)[1].min()
    cones = np.asarray(DISC_CONES)[:, None, None]
    disc = _profile_fits(tangential, light, spot_disc_profile(rho[None], height, cones), normal)[1].min()
    return float(1.0 - disc / bump) if bump > 0 else 0.0


def _plane_window(tree: cKDTree, points: np.ndarray, normals: np.ndarray, light: np.ndarray, peak: int,
                  settings: PeakSettings, foot_radius: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step 3's window of a peak: (indices of the readable points on its plane within settings.fit_radius, their
    tangential offsets (M, 3) from the peak, the candidate feet: those offsets within foot_radius)."""
    normal = normals[peak]
    near = np.asarray(tree.query_ball_point(points[peak], settings.fit_radius), dtype=np.int64)
    offset = points[near] - points[peak]
    along = offset @ normal
    on_plane = (normals[near] @ normal >= FIT_COSINE) & (np.abs(along) <= FIT_PLANE_OFFSET) & np.isfinite(light[near])
    near, offset, along = near[on_plane], offset[on_plane], along[on_plane]
    tangential = offset - along[:, None] * normal
    centres = tangential[np.linalg.norm(tangential, axis=1) <= foot_radius]  # a saturated top: any foot
    return near, tangential, centres


def peak_starts(points: np.ndarray, normals: np.ndarray, radiance: np.ndarray, albedo: np.ndarray,
                is_open: OpenTest, settings: PeakSettings = DEFAULT_PEAKS) -> Starts:
    """Starts 1-5 of the module docstring: light positions and estimated intensities from the baked light."""
    light, saturated = baked_light(radiance, albedo)
    peaks = light_peaks(points, light, settings.peak_radius)
    tree = cKDTree(points)
    positions, intensities, bumps = [], [], []
    for peak in peaks:
        normal = normals[peak]
        near, tangential, centres = _plane_window(tree, points, normals, light, peak, settings, settings.peak_radius)
        unsaturated = ~saturated[near]
        bump = fit_bump(tangential[unsaturated], light[near][unsaturated], centres, normal)
        if bump.alpha < settings.min_bump and unsaturated.sum() >= FIT_MIN_POINTS:
            continue
        alpha = max(bump.alpha, settings.min_bump)
        foot = points[peak] + (centres[bump.foot] if len(centres) else 0.0)
        height = bump.height
        while height >= MIN_HEIGHT:
            position = foot + height * normal
            if is_open(position[None])[0]:
                positions.append(position)
                intensities.append(alpha * bump.height * bump.height / POINT_SCALE)
                bumps.append(alpha)
                break
            height /= 2.0
    if not positions:
        return Starts(np.zeros((0, 3)), np.zeros(0), 0)
    positions_array, intensity_array = np.array(positions), np.array(intensities)
    kept = merged(positions_array, np.array(bumps), settings)  # highest bump first
    return Starts(positions_array[kept], intensity_array[kept], len(kept))


def merged(positions: np.ndarray, strength: np.ndarray, settings: PeakSettings) -> list[int]:
    """Step 5: the indices kept, strongest first (ties to the lower index), each at least settings.merge_distance
    from every one kept before it, at most settings.max_starts."""
    kept: list[int] = []
    for index in np.lexsort((np.arange(len(strength)), -strength)):
        if len(kept) == settings.max_starts:
            break
        if kept and np.min(np.linalg.norm(positions[kept] - positions[index], axis=1)) < settings.merge_distance:
            continue
        kept.append(int(index))
    return kept


def _ceiling_peaks(points: np.ndarray, normals: np.ndarray, light: np.ndarray, distance_up: DistanceUp,
                   settings: PeakSettings) -> tuple[np.ndarray, np.ndarray]:
    """Step 7's floor peaks with a ceiling in reach: (their indices, the start's height above each)."""
    peaks = light_peaks(points, light, SPOT_PEAK_RADIUS)
    peaks = peaks[(normals[peaks, 2] >= FLOOR_COSINE) & (light[peaks] >= settings.min_bump)]
    if len(peaks) == 0:
        return peaks, np.zeros(0)
    # from CEILING_PROBE_LIFT above the floor (its own surface is not the ceiling), at the peak and CEILING_STEPS around
    # it: the nearest surface above any of them, as a fixture smaller than a tilted spotlight's offset still hangs there
    above = np.min([distance_up(points[peaks] + CEILING_PROBE_LIFT * UP + offset)
                    for offset in (np.zeros(3),) + CEILING_STEPS], axis=0)
    reach = np.isfinite(above) & (above <= SPOT_REACH) & (above > CLEARANCE)
    return peaks[reach], above[reach] + CEILING_PROBE_LIFT - CLEARANCE


def ceiling_starts(points: np.ndarray, normals: np.ndarray, radiance: np.ndarray, albedo: np.ndarray,
                   is_open: OpenTest, distance_up: DistanceUp, settings: PeakSettings = DEFAULT_PEAKS) -> Starts:
    """Step 7 of the module docstring: spotlight starts under the ceiling above the floor's peaks of baked light."""
    light, _ = baked_light(radiance, albedo)
    peaks, height = _ceiling_peaks(points, normals, light, distance_up, settings)
    if len(peaks) == 0:
        return Starts(np.zeros((0, 3)), np.zeros(0), 0)
    positions = points[peaks] + height[:, None] * UP
    inside = is_open(positions) if len(positions) else np.zeros(0, bool)
    for offset in SIDE_STEPS:  # a peak at the foot of a wall: its column is on the wall's plane
        if inside.all():
            break
        moved = positions[~inside] + offset
        now_open = is_open(moved)
        index = np.flatnonzero(~inside)[now_open]
        positions[index], inside[index] = moved[now_open], True
    peaks, height, positions = peaks[inside], height[inside], positions[inside]
    kept = merged(positions, light[peaks], settings)  # brightest first
    intensities = light[peaks[kept]] * height[kept] ** 2 / POINT_SCALE
    return Starts(positions[kept], intensities, len(kept))


def fixture_starts(corners: np.ndarray, vertex_normals: np.ndarray, face: np.ndarray, points: np.ndarray,
                   radiance: np.ndarray, albedo: np.ndarray, is_open: OpenTest, distance_down: DistanceUp,
                   settings: PeakSettings = DEFAULT_PEAKS) -> Starts:
    """Step 9 of the module docstring: spotlight starts under the down-facing faces among the triangles `corners` (T, 3,
    3) Quake units with vertex normals (T, 3, 3) of faces `face` (T,) — the faces of light-named shaders
    (pipeline.light_fixtures) — over the target's `points` with their `radiance` and `albedo`; `distance_down`: units
    to the first surface straight below (inf beyond SPOT_REACH). Intensities 0 where the floor below is too dark to
    read (baked_light)."""
    if len(corners) == 0:
        return Starts(np.zeros((0, 3)), np.zeros(0), 0)
    normal = vertex_normals.mean(axis=1)
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), np.finfo(float).tiny)
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    down = (normal[:, 2] <= -FLOOR_COSINE) & (area > 0)
    faces = np.unique(face[down])
    if len(faces) == 0:
        return Starts(np.zeros((0, 3)), np.zeros(0), 0)
    weight = np.where(down, area, 0.0)
    # area-weighted centre of each face's down-facing triangles (a face's triangles share its plane)
    index = np.searchsorted(faces, face[down])
    total = np.bincount(index, weight[down], minlength=len(faces))
    centres = np.stack([np.bincount(index, weight[down] * corners[down].mean(axis=1)[:, k], minlength=len(faces))
                        for k in range(3)], axis=1) / total[:, None]
    positions = centres - CLEARANCE * UP
    height = distance_down(positions) if len(positions) else np.zeros(0)
    keep = np.isfinite(height) & (height <= SPOT_REACH) & is_open(positions)
    positions, height = positions[keep], height[keep]
    if len(positions) == 0:
        return Starts(np.zeros((0, 3)), np.zeros(0), 0)
    light, _ = baked_light(radiance, albedo)
    _, nearest = cKDTree(points).query(positions - height[:, None] * UP)
    below = np.nan_to_num(light[nearest], nan=0.0)
    kept = merged(positions, below, settings)  # brightest floor first
    return Starts(positions[kept], below[kept] * height[kept] ** 2 / POINT_SCALE, len(kept))


def under_a_ceiling(positions: np.ndarray, distance_up: DistanceUp, sky_up: DistanceUp | None) -> np.ndarray:
    """(N,) bool: something other than the sky is above each position (N, 3) within SPOT_REACH, straight up or straight
    up from any of CEILING_STEPS around it — the columns in which ceiling_starts found the ceiling the start hangs from
    — where a spotlight start may hang (pipeline.spotlight_starts). A column counts when its first surface is in reach
    and no nearer than the sky in it. `sky_up`: units to the level's sky straight above (inf if none), None on a level
    without sky. On aggressor the spotlights started under its sky became suns: 20 of the fit's spotlights had the sky
    straight above, the 17 of them farther than 1 m from every real light carrying 2,030 of its 15,323 power, and its
    sun came out 61 degrees off (benchmarks.md "The light rig"). The side columns because a ceiling start under a
    fixture found from a side step has, straight up, the gap beside the fixture (on aggressor the start 0.38 m from the
    real spotlight 46, under its 16-unit panel, was dropped so)."""
    hangs = np.zeros(len(positions), bool)
    for offset in (np.zeros(3),) + CEILING_STEPS:
        column = positions + offset
        above = distance_up(column)
        found = np.isfinite(above) & (above <= SPOT_REACH)
        if sky_up is not None:
            found &= ~(sky_up(column) < above)
        hangs |= found
    return hangs


def disc_gains(points: np.ndarray, normals: np.ndarray, radiance: np.ndarray, albedo: np.ndarray,
               distance_up: DistanceUp, settings: PeakSettings = DEFAULT_PEAKS) -> np.ndarray:
    """Step 8: the disc gain (disc_gain) at each of step 7's floor peaks with a ceiling in reach."""
    light, saturated = baked_light(radiance, albedo)
    peaks, height = _ceiling_peaks(points, normals, light, distance_up, settings)
    tree = cKDTree(points)
    gains = []
    for peak, above in zip(peaks, height):
        # feet within step 7's SPOT_PEAK_RADIUS: the peak is the brightest point that close
        near, tangential, centres = _plane_window(tree, points, normals, light, peak, settings, SPOT_PEAK_RADIUS)
        unsaturated = ~saturated[near]
        gains.append(disc_gain(tangential[unsaturated], light[near][unsaturated], centres, normals[peak], float(above)))
    return np.array(gains)


def lit_by_spotlights(gains: np.ndarray) -> bool:
    """Step 8's rule: the median disc gain over a level's floor peaks is at least SPOT_LEVEL_GAIN (False without any)."""
    return bool(len(gains)) and float(np.median(gains)) >= SPOT_LEVEL_GAIN


def with_grid_fallback(peaks: Starts, grid: np.ndarray, distance: float = FALLBACK_DISTANCE) -> Starts:
    """Step 6: the peaks' starts, then the grid cells (optimise.initial_grid) farther than `distance` from all of
    them; the whole grid when nothing peaks."""
    if peaks.from_peaks == 0:
        return Starts(grid, np.zeros(len(grid)), 0)
    if len(grid):
        far, _ = cKDTree(peaks.positions).query(grid)
        grid = grid[np.asarray(far) > distance]
    return Starts(np.concatenate([peaks.positions, grid]), np.concatenate([peaks.intensities, np.zeros(len(grid))]),
                  peaks.from_peaks)
