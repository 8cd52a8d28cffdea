"""Fit point lights to the radiance target: initial grid in open space, penalties, Adam / L-BFGS phases.

Schemes follow the seed's Table 5.1 (Documentation~/lights.md §4). Parameters are optimised in
scaled units so one step size fits all: position / POSITION_UNIT, colour as is (in [0, 1]),
intensity / INTENSITY_UNIT, the level's ambient / AMBIENT_UNIT (with the intensities). Bounds:
colour in [0, 1], intensity >= 0, ambient in [0, 255] bytes, position inside the world
box; Adam projects onto them after each step, L-BFGS-B (scipy) enforces them itself.

Visibility is recomputed every `refresh` iterations (and at each phase start) and held fixed in
between: Adam keeps its moments across refreshes; L-BFGS runs in rounds of `refresh` iterations
with fixed visibility (its curvature memory restarts each round), and stops when a round ends
before its limit (converged) or the phase's iteration limit is reached.

Penalties (the seed's future work), added to the objective with their gradients:
  - clearance: mu * sum_j max(0, 1 - d_j / CLEARANCE)^2, d_j = distance from light j to the nearest
    target point: keeps lights off the surfaces, where the 1/r^2 peak fits single bright spots;
  - in walls / outside: at every refresh, a light whose position is in solid or outside the map
    (the importer's solid test) goes back to where it was at the previous refresh (open space);
  - inside the level: the position bounds above.
The result is the best point met at a visibility refresh or at the end, each scored with its own visibility:
a refresh can make the fit worse (a light on a shadow edge flips the pairs it sees), and the last point need
not be the best one.
Deterministic: no random numbers; the same level and settings give the same rig.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np
from scipy.optimize import minimize, nnls
from scipy.spatial import cKDTree

from ..scenes.lightgrid import LINEAR_PER_BYTE
from .emitters import Suns
from .model import BYTE_MAX, ForwardModel, Gradient, Lights
from .settings import COLOUR, DEFAULT_REFRESH, INTENSITY, POSITION, Phase

POSITION_UNIT = 64.0  # Quake units per scaled position unit (one light grid cell)
INTENSITY_UNIT = 1000.0
AMBIENT_UNIT = 64.0  # bytes
SURFACE_UNIT = 1000.0  # q3map_surfacelight value per scaled unit
MAX_SURFACE_VALUE = 1e5
CLEARANCE = 24.0  # Quake units (0.61 m)
CLEARANCE_WEIGHT = 1e-3
MAX_INTENSITY = 1e6
ADAM_BETAS = (0.9, 0.999)
ADAM_EPSILON = 1e-8
# spotlights (fit_scene(spots=True), lights.md §4): a light started as a q3map2 spotlight stays one, its axis
# N = u / |u| with u in [-1, 1]^3 (renormalised at every visibility refresh), its radiusByDist in [SPOT_MIN_CONE,
# SPOT_MAX_CONE] (half-angles 3-76 degrees), started pointing down with SPOT_START_CONE; a point light stays one
SPOT_MIN_CONE = 0.05
SPOT_MAX_CONE = 4.0
SPOT_START_CONE = 1.0
SPOT_START_AXIS = (0.0, 0.0, -1.0)
# a sun (fit_scene(suns=True), lights.md §4): the direction toward the sun d = u / |u|, u in [-1, 1]^3 (renormalised
# at every refresh), optimised with the positions; white at the start, intensity in photons. Its start is the best of
# SUN_START_ELEVATIONS x SUN_START_AZIMUTHS by the closed-form fit: straight overhead alone is a saddle (every floor's
# gradient is along the direction itself, every wall is edge-on): a first version's sun started there never moved.
SUN_UNIT = 100.0  # photons per scaled unit
MAX_SUN_INTENSITY = 1e4
SUN_START_ELEVATIONS = (90.0, 70.0, 50.0, 30.0)  # degrees; 90 is overhead (one direction)
SUN_START_AZIMUTHS = 8  # every 45 degrees



@dataclass
class CurvePoint:
    phase: int
    algorithm: str
    iteration: int  # iterations so far over all phases (one Adam step / one L-BFGS iteration)
    evaluations: int  # objective evaluations so far
    objective: float  # fit term only (penalties excluded)
    penalty: float
    seconds: float
    rays: int


@dataclass
class FitResult:
    lights: Lights
    objective: float
    curve: list[CurvePoint] = field(default_factory=list)
    seconds: float = 0.0
    rays: int = 0
    ray_seconds: float = 0.0
    iterations: int = 0
    # lights the fit started from; a merge then a second pass (pipeline.fit_scene) ends with fewer, and its result
    # carries the first pass's count
    initial_lights: int = 0


Progress = Callable[[int, int], None]  # (iterations done, iteration budget)
OpenTest = Callable[[np.ndarray], np.ndarray]  # (J, 3) Quake positions -> (J,) bool open


def initial_grid(mins: np.ndarray, maxs: np.ndarray, dims: tuple[int, int, int], is_open: OpenTest) -> np.ndarray:
    """Cell centres of an nx x ny x nz grid over the box, kept where they are in open space."""
    axes = [mins[k] + (np.arange(n) + 0.5) * (maxs[k] - mins[k]) / n for k, n in enumerate(dims)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return grid[is_open(grid)]


def initial_intensity(model: ForwardModel, positions: np.ndarray, spots: np.ndarray | None = None,
                      relative: np.ndarray | None = None, sun: bool = False, ambient: np.ndarray | None = None,
                      held_values: np.ndarray | None = None, held_suns: Suns | None = None) -> Lights:
    """White lights of one common intensity and a grey ambient: the least-squares fit of the two
    scales to the target (closed form, without the byte clamp); the ambient is dropped if negative.
    With `ambient` (3,) bytes, the ambient is that (a fit holding it, Fitter(fit_ambient=False)) and the other
    scales are fitted to what it leaves of the target.
    With `relative` (J,) > 0, the lights' intensities are one common scale times these (starts.py's estimates).
    With surface lights (model.surface_basis), their values too: the non-negative least-squares fit of
    all the scales (scipy's nnls). `spots` (J,) bool: those lights are spotlights along SPOT_START_AXIS with
    SPOT_START_CONE, the others point lights. With `sun`, one white sun too, its intensity in the same
    non-negative fit, along the start direction (sun_start_directions) whose fit leaves the least residual.
    `held_values` (S,): the surface lights' values a fit holds (Fitter(held_values=...)), NaN where a value is fitted;
    `held_suns`: the suns a fit holds (Fitter(hold_suns=True)), instead of `sun`'s fitted one. Like a held ambient,
    their radiance leaves the target and their columns the fit."""
    surfaces = np.zeros(model.surface_count)
    if held_values is not None:
        held_values = np.asarray(held_values, dtype=np.float64)
        if held_values.shape != surfaces.shape:
            raise ValueError(f"{held_values.size} held surface light values for the model's {model.surface_count} "
                             f"surface lights")
        surfaces = np.where(np.isnan(held_values), 0.0, np.clip(held_values, 0.0, MAX_SURFACE_VALUE))
    count = len(positions)
    spot = np.zeros(count, bool) if spots is None else np.asarray(spots, dtype=bool)
    if spot.shape != (count,):
        raise ValueError(f"{spot.size} spotlight flags for {count} lights")
    axes = np.where(spot[:, None], SPOT_START_AXIS, 0.0) if spot.any() else np.zeros((0, 3))
    cones = np.where(spot, SPOT_START_CONE, 0.0) if spot.any() else np.zeros(0)
    shape = np.ones(count) if relative is None else np.asarray(relative, dtype=np.float64) / np.mean(relative)
    if shape.shape != (count,) or not np.all(shape > 0):
        raise ValueError(f"relative intensities must be {count} positive numbers")
    unit = Lights(positions=positions, colours=np.ones((count, 3)), intensities=shape.copy(),
                  surface_values=np.zeros(model.surface_count), spot_directions=axes, radius_by_dist=cones)
    visible = model.visibility(Lights(positions, unit.colours, np.full(count, 1000.0)))
    lit = model.radiance_of(unit, visible).ravel()  # per unit of the common scale (the point lights' alone)
    unit.surface_values = surfaces  # the held values (zeros where fitted): _initial_with_surfaces takes them out
    flat = (model.albedo * LINEAR_PER_BYTE).ravel()  # per byte of ambient
    weights = np.repeat(model.weights, 3)
    target = model.radiance.ravel()
    if ambient is not None:  # held: its radiance leaves the target, and its column the fits
        unit.ambient = np.clip(np.asarray(ambient, dtype=np.float64), 0.0, BYTE_MAX)
        target = target - (model.albedo * LINEAR_PER_BYTE * unit.ambient).ravel()
        flat = None
    held = None if held_values is None else ~np.isnan(held_values)
    if held_suns is not None:
        unit = replace(unit, sun_directions=held_suns.directions.copy(), sun_colours=held_suns.colours.copy(),
                       sun_intensities=held_suns.photons.copy())
        return _initial_with_surfaces(model, unit, lit, flat, weights, target, held, held_sun=True)[0]
    if sun:
        best: tuple[Lights, float] | None = None
        for direction in sun_start_directions():  # the first of equal residuals: deterministic
            trial = replace(unit, sun_directions=direction[None], sun_colours=np.ones((1, 3)), sun_intensities=np.zeros(1))
            found = _initial_with_surfaces(model, trial, lit, flat, weights, target, held)
            if best is None or found[1] < best[1]:
                best = found
        assert best is not None
        return best[0]
    if model.surface_count or flat is None:
        return _initial_with_surfaces(model, unit, lit, flat, weights, target, held)[0]
    basis = np.stack([lit, flat], axis=1)
    gram = basis.T @ (weights[:, None] * basis)
    rhs = basis.T @ (weights * target)
    scale, ambient = np.linalg.lstsq(gram, rhs, rcond=None)[0] if np.all(np.isfinite(gram)) else (1.0, 0.0)
    if ambient < 0:  # a negative ambient is not a light: fit the scale alone
        scale, ambient = (rhs[0] / gram[0, 0] if gram[0, 0] > 0 else 1.0), 0.0
    unit.intensities = np.clip(float(scale) * shape, 1.0, MAX_INTENSITY)
    unit.ambient = np.full(3, float(np.clip(ambient, 0.0, BYTE_MAX)))
    return unit


def sun_start_directions() -> np.ndarray:
    """(D, 3) unit directions toward the sun a fitted sun may start from: overhead, then SUN_START_AZIMUTHS azimuths
    at each lower elevation of SUN_START_ELEVATIONS (Quake axes: z up)."""
    out = []
    for elevation in SUN_START_ELEVATIONS:
        e = np.radians(elevation)
        for azimuth in np.radians(np.arange(SUN_START_AZIMUTHS) * 360.0 / SUN_START_AZIMUTHS)[:1 if elevation == 90 else None]:
            out.append([np.cos(azimuth) * np.cos(e), np.sin(azimuth) * np.cos(e), np.sin(e)])
    directions = np.array(out)
    return directions / np.linalg.norm(directions, axis=1, keepdims=True)


def _initial_with_surfaces(model: ForwardModel, unit: Lights, lit: np.ndarray, flat: np.ndarray | None,
                           weights: np.ndarray, target: np.ndarray, held: np.ndarray | None = None,
                           held_sun: bool = False) -> tuple[Lights, float]:
    """The nnls fit of the lights' common scale, the ambient (`flat`, per byte; None: held at unit.ambient, already
    taken from `target`), every surface light's value and every sun's intensity (a white sun's radiance per photon:
    albedo x 4/255 x lit x cos), and its residual norm. The surface lights where `held` (S,) is True keep
    unit.surface_values, and with `held_sun` the suns keep their colours and intensities: their radiance is taken
    from the target and their columns from the fit."""
    per_value = (model.albedo[None] * LINEAR_PER_BYTE * model.surface_basis).reshape(model.surface_count,
                                                                                     3 * model.point_count)
    sun_lit = model.sun_visibility(unit)
    weight = model.sun_weights(unit, sun_lit)  # (N, K)
    per_photon = (model.albedo[:, None, :] * LINEAR_PER_BYTE * weight[:, :, None])
    per_photon = per_photon.transpose(1, 0, 2).reshape(unit.sun_count, 3 * model.point_count)
    held = np.zeros(model.surface_count, bool) if held is None else held
    target = target - unit.surface_values[held] @ per_value[held]
    if held_sun and unit.sun_count:
        target = target - (model.albedo * LINEAR_PER_BYTE * (weight @ (unit.sun_colours *
                                                                        unit.sun_intensities[:, None]))).ravel()
        per_photon = per_photon[:0]
    root = np.sqrt(weights)
    scalars = [lit] if flat is None else [lit, flat]
    basis = np.concatenate([np.stack(scalars, axis=1), per_value[~held].T, per_photon.T], axis=1) * root[:, None]
    scales, residual = nnls(basis, target * root, maxiter=50 * basis.shape[1])
    unit.intensities = np.clip(scales[0] * unit.intensities, 1.0, MAX_INTENSITY)
    if flat is not None:
        unit.ambient = np.full(3, float(np.clip(scales[1], 0.0, BYTE_MAX)))
    first = len(scalars)
    free = int((~held).sum())
    values = unit.surface_values.copy()
    values[~held] = np.clip(scales[first:first + free], 0.0, MAX_SURFACE_VALUE)
    unit.surface_values = values
    if not held_sun:
        unit.sun_intensities = np.clip(scales[first + free:], 0.0, MAX_SUN_INTENSITY)
    return unit, float(residual)


class Fitter:
    """Parameters are one flat vector: the lights' (J, 7) rows (position, colour, intensity, scaled), with
    spotlights their (J, 4) rows (axis u, radiusByDist; optimised with the positions), the suns' (K, 7) rows
    (direction u, optimised with the positions; colour; intensity / SUN_UNIT), the surface lights' values
    (S, scaled), then the ambient (3, scaled); the ambient (unless `fit_ambient` is False: held where the start
    put it) and the surface values are optimised with the intensities. The lights whose start has a cone (Lights.radius_by_dist > 0) are spotlights; when any is, every
    light has spot rows, held at 0 (a point light) for the others."""

    def __init__(self, model: ForwardModel, bounds: tuple[np.ndarray, np.ndarray], is_open: OpenTest,
                 surface_points: np.ndarray, refresh: int = DEFAULT_REFRESH,
                 progress: Progress | None = None, fit_ambient: bool = True, held_values: np.ndarray | None = None,
                 hold_suns: bool = False) -> None:
        if refresh < 1:
            raise ValueError(f"refresh {refresh} must be at least 1 iteration")
        self.model = model
        self.lower, self.upper = bounds
        self.is_open = is_open
        self.surfaces = cKDTree(surface_points)
        self.refresh = refresh
        self.progress = progress
        self.fit_ambient = fit_ambient
        # (S,) True where a surface light's value is held where the start put it (its script's, lights.md §4)
        self.held_values = np.zeros(model.surface_count, bool) if held_values is None else \
            np.asarray(held_values, dtype=bool)
        if self.held_values.shape != (model.surface_count,):
            raise ValueError(f"{self.held_values.size} held flags for the model's {model.surface_count} surface lights")
        self.hold_suns = hold_suns  # the suns' directions, colours and intensities held where the start put them
        self.curve: list[CurvePoint] = []
        self.iterations = 0
        self.evaluations = 0
        self.started = time.perf_counter()
        self.budget = 0
        self._best: tuple[float, float, np.ndarray] | None = None  # objective, penalty, parameters
        self.count = 0  # lights (set by fit)
        self.spots = False  # some lights are spotlights: the vector has spot rows (set by fit)
        self.spot_mask = np.zeros(0, bool)  # (J,) which lights are spotlights (set by fit)
        self.sun_count = 0  # suns (set by fit)

    # ------------------------------------------------------------------------ packing

    def _pack(self, lights: Lights) -> np.ndarray:
        rows = np.concatenate([lights.positions / POSITION_UNIT, lights.colours,
                               lights.intensities[:, None] / INTENSITY_UNIT], axis=1)
        values = np.asarray(lights.surface_values, dtype=np.float64)
        if values.shape != (self.surfaces_count,):
            raise ValueError(f"{values.size} surface light values for the model's {self.surfaces_count} surface lights")
        spots = np.zeros((0, 4))
        if self.spots:
            axes, cones = lights.cones()
            spots = np.where(self.spot_mask[:, None], np.concatenate([_unit_rows(axes), cones[:, None]], axis=1), 0.0)
        suns = np.concatenate([lights.sun_directions, lights.sun_colours,
                               lights.sun_intensities[:, None] / SUN_UNIT], axis=1) if self.sun_count else np.zeros((0, 7))
        return np.concatenate([rows.ravel(), spots.ravel(), suns.ravel(), values / SURFACE_UNIT,
                               lights.ambient / AMBIENT_UNIT])

    @property
    def _spot_size(self) -> int:
        return 4 * self.count if self.spots else 0

    def _spot_rows(self, x: np.ndarray) -> np.ndarray:
        """The spotlights' (J, 4) rows (axis u, radiusByDist) of a parameter vector (a view; (0, 4) without)."""
        return x[7 * self.count:7 * self.count + self._spot_size].reshape(-1, 4)

    def _sun_rows(self, x: np.ndarray) -> np.ndarray:
        """The suns' (K, 7) rows (direction u, colour, intensity / SUN_UNIT) of a parameter vector (a view)."""
        start = 7 * self.count + self._spot_size
        return x[start:start + 7 * self.sun_count].reshape(-1, 7)

    @property
    def surfaces_count(self) -> int:
        return self.model.surface_count

    def _rows(self, x: np.ndarray) -> np.ndarray:
        """The lights' (J, 7) rows of a parameter vector (a view)."""
        return x[:7 * self.count].reshape(-1, 7)

    def _unpack(self, x: np.ndarray) -> Lights:
        rows = self._rows(x)
        spots = self._spot_rows(x)
        suns = self._sun_rows(x)
        return Lights(positions=rows[:, 0:3] * POSITION_UNIT, colours=rows[:, 3:6].copy(),
                      intensities=rows[:, 6] * INTENSITY_UNIT, ambient=x[-3:] * AMBIENT_UNIT,
                      surface_values=x[len(x) - 3 - self.surfaces_count:-3] * SURFACE_UNIT,
                      spot_directions=_unit_rows(spots[:, 0:3]), radius_by_dist=spots[:, 3].copy(),
                      sun_directions=_unit_rows(suns[:, 0:3]), sun_colours=suns[:, 3:6].copy(),
                      sun_intensities=suns[:, 6] * SUN_UNIT)

    def _mask(self, parameters: tuple[str, ...], count: int) -> np.ndarray:
        columns = np.zeros(7, dtype=bool)
        columns[0:3] = POSITION in parameters
        columns[3:6] = COLOUR in parameters
        columns[6] = INTENSITY in parameters
        spots = np.repeat(self.spot_mask & (POSITION in parameters), 4) if self.spots else np.zeros(0, bool)
        suns = np.tile(columns & (not self.hold_suns), self.sun_count)  # direction with the positions, colour, intensity
        return np.concatenate([np.tile(columns, count), spots, suns,
                               (INTENSITY in parameters) & ~self.held_values,
                               np.full(3, INTENSITY in parameters and self.fit_ambient)])

    def _box(self, count: int) -> tuple[np.ndarray, np.ndarray]:
        low = np.concatenate([self.lower / POSITION_UNIT, np.zeros(3), [0.0]])
        high = np.concatenate([self.upper / POSITION_UNIT, np.ones(3), [MAX_INTENSITY / INTENSITY_UNIT]])
        surfaces = self.surfaces_count
        spot = self.spot_mask[:, None] if self.spots else np.zeros((0, 1), bool)
        spot_low = np.where(spot, [-1.0, -1.0, -1.0, SPOT_MIN_CONE], 0.0).ravel()  # point lights: held at 0
        spot_high = np.where(spot, [1.0, 1.0, 1.0, SPOT_MAX_CONE], 0.0).ravel()
        sun_low = np.tile([-1.0, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0], self.sun_count)
        sun_high = np.tile([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, MAX_SUN_INTENSITY / SUN_UNIT], self.sun_count)
        return (np.concatenate([np.tile(low, count), spot_low, sun_low, np.zeros(surfaces), np.zeros(3)]),
                np.concatenate([np.tile(high, count), spot_high, sun_high,
                                np.full(surfaces, MAX_SURFACE_VALUE / SURFACE_UNIT), np.full(3, BYTE_MAX / AMBIENT_UNIT)]))

    # ---------------------------------------------------------------------- objective

    def _evaluate(self, x: np.ndarray, visible: np.ndarray) -> tuple[float, float, np.ndarray]:
        lights = self._unpack(x)
        fit: Gradient = self.model.objective(lights, visible)
        rows = np.concatenate([fit.positions * POSITION_UNIT, fit.colours,
                               fit.intensities[:, None] * INTENSITY_UNIT], axis=1)
        distance, nearest = self.surfaces.query(lights.positions)
        distance = np.asarray(distance, dtype=np.float64)
        short = np.maximum(0.0, 1.0 - distance / CLEARANCE)
        penalty = CLEARANCE_WEIGHT * float(np.sum(short ** 2))
        away = lights.positions - self.surfaces.data[nearest]
        safe = np.where(distance > 0, distance, 1.0)[:, None]
        rows[:, 0:3] += (-2.0 * CLEARANCE_WEIGHT * short / CLEARANCE)[:, None] * away / safe * POSITION_UNIT
        self.evaluations += 1
        spots = np.zeros((0, 4))
        if self.spots:
            spots = np.concatenate([_through_unit(self._spot_rows(x)[:, 0:3], fit.spot_directions),
                                    fit.radius_by_dist[:, None]], axis=1)
        suns = np.concatenate([_through_unit(self._sun_rows(x)[:, 0:3], fit.sun_directions), fit.sun_colours,
                               fit.sun_intensities[:, None] * SUN_UNIT], axis=1)
        return fit.value, penalty, np.concatenate([rows.ravel(), spots.ravel(), suns.ravel(),
                                                   fit.surface_values * SURFACE_UNIT, fit.ambient * AMBIENT_UNIT])

    def _record(self, phase: int, algorithm: str, value: float, penalty: float) -> None:
        self.curve.append(CurvePoint(phase=phase, algorithm=algorithm, iteration=self.iterations,
                                     evaluations=self.evaluations, objective=value, penalty=penalty,
                                     seconds=time.perf_counter() - self.started, rays=self.model.rays))
        if self.progress is not None:
            self.progress(self.iterations, self.budget)

    def _refresh(self, x: np.ndarray, anchor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lights in solid / outside go back to their anchor; new visibility. The point is scored with its own
        visibility (the true objective, not one of fixed visibility) and kept when it is the best so far."""
        blocked = ~self.is_open(self._unpack(x).positions)
        if blocked.any():
            x = x.copy()
            self._rows(x)[blocked, 0:3] = anchor[blocked]
        if self.spots or self.sun_count:  # axes and sun directions back to unit length, so u stays inside its box
            x = x.copy()
            self._spot_rows(x)[:, 0:3] = _unit_rows(self._spot_rows(x)[:, 0:3])
            self._sun_rows(x)[:, 0:3] = _unit_rows(self._sun_rows(x)[:, 0:3])
        visible = self.model.visibility(self._unpack(x))
        self._keep_best(x, visible)
        return x, visible

    def _keep_best(self, x: np.ndarray, visible: np.ndarray) -> tuple[float, float]:
        value, penalty, _ = self._evaluate(x, visible)
        if self._best is None or value + penalty < self._best[0] + self._best[1]:
            self._best = (value, penalty, x.copy())
        return value, penalty

    # ------------------------------------------------------------------------ phases

    def fit(self, lights: Lights, phases: tuple[Phase, ...]) -> FitResult:
        """The best point of `phases` from `lights`. Called again on the same fitter (a second pass, pipeline.py), it
        continues its clock, iteration count and curve, and the best point is the new pass's."""
        self.budget = self.iterations + sum(p.iterations for p in phases)
        self.count = lights.count
        self.spot_mask = lights.cones()[1] > 0
        self.spots = bool(self.spot_mask.any())
        self.sun_count = lights.sun_count
        x = self._pack(lights)
        self._best = None
        value, penalty = self._keep_best(x, self.model.visibility(lights))
        self._record(0, "start", value, penalty)
        for number, phase in enumerate(phases, start=1):
            run = self._adam if phase.algorithm == "adam" else self._lbfgs
            x = run(number, phase, x)
        # the end point, scored with its own visibility; a visibility refresh can make the last point worse
        # than one met earlier (a light on a shadow edge), so the best point scored that way is the result
        self._keep_best(x, self.model.visibility(self._unpack(x)))
        assert self._best is not None
        value, penalty, x = self._best
        final = self._unpack(x)
        self._record(len(phases), "final", value, penalty)
        return FitResult(lights=final, objective=value, curve=list(self.curve),  # a copy: a second pass appends to ours
                         seconds=time.perf_counter() - self.started, rays=self.model.rays,
                         iterations=self.iterations, initial_lights=lights.count)

    def _adam(self, number: int, phase: Phase, x: np.ndarray) -> np.ndarray:
        count = len(self._rows(x))
        mask = self._mask(phase.parameters, count)
        low, high = self._box(count)
        first = np.zeros_like(x)
        second = np.zeros_like(x)
        anchor = self._rows(x)[:, 0:3].copy()
        visible = None
        for step in range(1, phase.iterations + 1):
            if visible is None or (step - 1) % self.refresh == 0:
                x, visible = self._refresh(x, anchor)
                anchor = self._rows(x)[:, 0:3].copy()
            value, penalty, grad = self._evaluate(x, visible)
            grad = np.where(mask, grad, 0.0)
            first = ADAM_BETAS[0] * first + (1 - ADAM_BETAS[0]) * grad
            second = ADAM_BETAS[1] * second + (1 - ADAM_BETAS[1]) * grad * grad
            corrected = (first / (1 - ADAM_BETAS[0] ** step)) / (np.sqrt(second / (1 - ADAM_BETAS[1] ** step)) + ADAM_EPSILON)
            x = np.clip(x - phase.step * corrected, low, high)
            self.iterations += 1
            self._record(number, "adam", value, penalty)
        return x

    def _lbfgs(self, number: int, phase: Phase, x: np.ndarray) -> np.ndarray:
        count = len(self._rows(x))
        free = self._mask(phase.parameters, count)
        low, high = self._box(count)
        bounds = list(zip(low[free], high[free]))
        anchor = self._rows(x)[:, 0:3].copy()
        done = 0
        while done < phase.iterations:
            x, visible = self._refresh(x, anchor)
            anchor = self._rows(x)[:, 0:3].copy()
            last: dict[str, float] = {}

            def objective(y: np.ndarray, visible: np.ndarray = visible, fixed: np.ndarray = x,
                          last: dict[str, float] = last) -> tuple[float, np.ndarray]:
                full = fixed.copy()
                full[free] = y
                value, penalty, grad = self._evaluate(full, visible)
                last.update(value=value, penalty=penalty)
                return value + penalty, grad[free]

            def on_iteration(_: np.ndarray, last: dict[str, float] = last) -> None:
                # L-BFGS-B reports the point its line search accepted, the last one evaluated
                self.iterations += 1
                self._record(number, "lbfgs", last["value"], last["penalty"])

            limit = min(self.refresh, phase.iterations - done)
            result = minimize(objective, x[free], jac=True, method="L-BFGS-B", bounds=bounds,
                              callback=on_iteration, options={"maxiter": limit})
            x = x.copy()
            x[free] = result.x
            done += max(int(result.nit), 1)
            if result.nit < limit:  # converged for this visibility: the phase is done
                break
        return x


def _through_unit(u: np.ndarray, d_unit: np.ndarray) -> np.ndarray:
    """dL/du from dL/dN for N = u / |u| (rows): (dL/dN - N (N . dL/dN)) / |u|."""
    length = np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-12)
    unit = u / length
    return (d_unit - unit * np.einsum("jk,jk->j", unit, d_unit)[:, None]) / length


def _unit_rows(u: np.ndarray) -> np.ndarray:
    """Rows scaled to unit length (a zero row stays zero)."""
    length = np.linalg.norm(u, axis=1, keepdims=True)
    return np.divide(u, length, out=np.zeros_like(u), where=length > 0)
