"""The merge after a spotlight fit (Documentation~/lights.md §4): a fitted spotlight's disc is often shared with weaker
spotlights beside it, each carrying part of one real light's power and none of them enough to count (lights.md §6's
significance floor). Every spotlight, strongest first, takes in the weaker spotlights within the merge radius: their
power (intensity x largest colour component) is added to its intensity and they are dropped. Point lights are left
alone: folded into a spotlight, the walls they lit outside its cone went dark (on aggressor, within 48 units and fitted
again, the objective rose 0.0252 -> 0.0378 and the re-lit grid 0.476 -> 0.515; benchmarks.md "The light rig"). The fit
then runs a short second pass from the merged rig (pipeline.fit_scene). Deterministic: strongest first, ties to the
lower index.

Before that pass the merged spotlights also settle on the light fixtures they hang from (settle_on_fixtures): the fit
pulls a spotlight off its fixture towards a neighbour's disc, or one spotlight between two fixtures carries both their
discs (aggressor's real spotlights 59 and 60, 128 units apart, under one recovered spotlight between them), and the
second pass does not move it back: between two overlapping discs the objective is nearly flat."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .model import Lights


def merge_spotlights(lights: Lights, radius: float) -> Lights:
    """`lights` with every spotlight's weaker spotlights within `radius` Quake units folded into it (module docstring);
    point lights, the ambient, surface values and suns as they are. Without spotlights, `lights` itself."""
    if not radius >= 0:
        raise ValueError(f"merge radius {radius!r} must be a number of Quake units >= 0")
    _, cones = lights.cones()
    spot = cones > 0
    if not spot.any():
        return lights
    peak = lights.colours.max(axis=1)
    power = lights.intensities * peak
    alive = np.ones(lights.count, bool)
    intensities = lights.intensities.astype(np.float64, copy=True)
    for index in np.lexsort((np.arange(lights.count), -power)):  # strongest first, ties to the lower index
        if not (alive[index] and spot[index]) or peak[index] <= 0:  # a black spotlight has no colour to carry power
            continue
        near = np.linalg.norm(lights.positions - lights.positions[index], axis=1) <= radius
        taken = alive & spot & near & (power <= power[index])
        taken[index] = False
        if taken.any():
            intensities[index] = (power[index] + power[taken].sum()) / peak[index]
            alive[taken] = False
    if alive.all():
        return lights
    return replace(lights, positions=lights.positions[alive], colours=lights.colours[alive],
                   intensities=intensities[alive], spot_directions=lights.spot_directions[alive],
                   radius_by_dist=lights.radius_by_dist[alive])


def settle_on_fixtures(lights: Lights, fixtures: np.ndarray, reach: float) -> Lights:
    """`lights` with every spotlight, strongest first (ties to the lower index), moved to the nearest fixture start
    (`fixtures` (F, 3) Quake units: starts.fixture_starts, under the down-facing faces of light-named shaders) within
    `reach` units that no stronger spotlight took, its axis, cone, colour and intensity kept; then every fixture start
    still free gets a copy of the nearest moved spotlight within `reach` (one spotlight that carried two fixtures'
    discs), that spotlight's power shared equally between it and its copies. Point lights, the ambient, surface values
    and suns as they are. Without a spotlight within reach of a fixture, `lights` itself (module docstring)."""
    if not reach >= 0:
        raise ValueError(f"fixture reach {reach!r} must be a number of Quake units >= 0")
    fixtures = np.asarray(fixtures, dtype=np.float64).reshape(-1, 3)
    axes, cones = lights.cones()
    spot = cones > 0
    positions = lights.positions.astype(np.float64, copy=True)
    power = lights.intensities * lights.colours.max(axis=1)
    free = np.ones(len(fixtures), bool)
    settled = []
    for index in np.lexsort((np.arange(lights.count), -power)):  # strongest first, ties to the lower index
        if not spot[index] or not free.any():
            continue
        gap = np.where(free, np.linalg.norm(fixtures - positions[index], axis=1), np.inf)
        nearest = int(np.argmin(gap))  # ties to the lower fixture
        if gap[nearest] <= reach:
            positions[index] = fixtures[nearest]
            free[nearest] = False
            settled.append(index)
    if not settled:
        return lights
    movers = np.array(sorted(settled), dtype=int)
    copies = []  # (spotlight, fixture), fixtures in order
    for fixture in np.flatnonzero(free):
        gap = np.linalg.norm(positions[movers] - fixtures[fixture], axis=1)
        if gap.min() <= reach:
            copies.append((int(movers[np.argmin(gap)]), int(fixture)))
    intensities = lights.intensities.astype(np.float64, copy=True)
    source = np.array([spotlight for spotlight, _ in copies], dtype=int)
    intensities /= 1 + np.bincount(source, minlength=lights.count)
    return replace(lights, positions=np.concatenate([positions, fixtures[[fixture for _, fixture in copies]]]),
                   colours=np.concatenate([lights.colours, lights.colours[source]]),
                   intensities=np.concatenate([intensities, intensities[source]]),
                   spot_directions=np.concatenate([axes, axes[source]]),
                   radius_by_dist=np.concatenate([cones, cones[source]]))
