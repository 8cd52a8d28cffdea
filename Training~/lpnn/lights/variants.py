"""Relit variants of a rig: seeded perturbations that stay plausible (Documentation~/lights.md §9).

From one rig and one seed (numpy's default generator, PCG64), in this order:
  - every light is switched off with probability OFF_PROBABILITY (at least one stays on);
  - every light's intensity is multiplied by a log-uniform factor in INTENSITY_RANGE;
  - every light's colour channels are multiplied by factors uniform in COLOUR_RANGE, then the colour is
    normalised to a largest component of 1 (its scale moves into the intensity, as in every rig);
  - up to MOVED_LIGHTS lights (chosen among those still on) move by an offset uniform in a ball of
    MOVE_RADIUS metres; a move whose end is not in open space (when an open-space test is given) is
    tried again up to MOVE_ATTEMPTS times, then the light stays where it was;
  - the ambient is multiplied by a factor uniform in AMBIENT_RANGE (clamped to 255 bytes).
The same rig and seed always give the same variant.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from .model import BYTE_MAX
from .rig import Rig

OFF_PROBABILITY = 0.15
INTENSITY_RANGE = (0.5, 2.0)  # factor, log-uniform
COLOUR_RANGE = (0.6, 1.0)  # per channel, before renormalising
MOVED_LIGHTS = 3
MOVE_RADIUS = 1.5  # metres
MOVE_ATTEMPTS = 8
AMBIENT_RANGE = (0.6, 1.4)


def relit_variant(rig: Rig, seed: int, is_open: Callable[[np.ndarray], np.ndarray] | None = None) -> Rig:
    """A perturbed copy of `rig` (module docstring); `is_open` takes Unity positions (M, 3) -> (M,) bool."""
    if rig.count == 0:
        raise ValueError("a rig without lights has no relit variant")
    rng = np.random.default_rng(seed)
    on = rng.random(rig.count) >= OFF_PROBABILITY
    if not on.any():
        on[rng.integers(rig.count)] = True
    low, high = np.log(INTENSITY_RANGE[0]), np.log(INTENSITY_RANGE[1])
    intensities = rig.intensities * np.exp(rng.uniform(low, high, rig.count))
    colours = rig.colours * rng.uniform(COLOUR_RANGE[0], COLOUR_RANGE[1], (rig.count, 3))
    peak = colours.max(axis=1)
    colours = np.where(peak[:, None] > 0, colours / np.where(peak > 0, peak, 1.0)[:, None], colours)
    intensities = intensities * np.where(peak > 0, peak, 1.0)
    positions = rig.positions.copy()
    candidates = np.flatnonzero(on)
    moved = rng.choice(candidates, size=min(MOVED_LIGHTS, len(candidates)), replace=False)
    for light in np.sort(moved):
        for _ in range(MOVE_ATTEMPTS):
            direction = rng.normal(size=3)
            offset = direction / max(np.linalg.norm(direction), 1e-12) * MOVE_RADIUS * rng.random() ** (1.0 / 3.0)
            end = positions[light] + offset
            if is_open is None or bool(is_open(end[None])[0]):
                positions[light] = end
                break
    ambient = np.clip(rig.ambient * rng.uniform(AMBIENT_RANGE[0], AMBIENT_RANGE[1]), 0.0, BYTE_MAX)
    extra = {"variant_of": rig.scheme or "rig", "variant_seed": int(seed), "lights_off": int((~on).sum()),
             "lights_moved": [int(i) for i in np.sort(moved)]}
    cones = {} if len(rig.radius_by_dist) != rig.count else \
        {"spot_directions": rig.spot_directions[on], "radius_by_dist": rig.radius_by_dist[on]}
    return replace(rig, positions=positions[on], colours=colours[on], intensities=intensities[on], ambient=ambient,
                   scheme="relit variant", objective=None, extra=extra, **cones)
