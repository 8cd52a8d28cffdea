#!/usr/bin/env python3
"""What a level's real rig leaves unexplained (lights.md §7, benchmarks.md "The light rig"): the level's own light entities,
spotlights, surface lights, suns and ambient through the forward model (lights.md §3), without and with its suns,
then with one bounce added.

  PYTHONPATH=Training~ python Tools~/experiments/lights-residual.py LEVEL [LEVEL ...]

The bounce is q3map2's radiosity pass at its defaults (light_bounce.c RadSubdivideDiffuseLight, the bounced branch:
every lit surface re-emits as area lights of add = RADIOSITY_VALUE 500 x the shader's bounceScale 1 x 0.375 x
formFactorValueScale 3 x bounceScale 0.25 = 140.625 bytes per unit form factor, coloured texture x luxel / 255 as
RadSample averages them), approximated by a gather: the form-factor sum over the surfaces a point sees is the mean,
over BOUNCE_DIRECTIONS cosine-weighted directions (deterministic: golden-angle spiral), of texture x luxel / 255 at
the first surface hit (the nearest target point within BOUNCE_MATCH units, facing the ray). Not part of the model:
it raised the objective on every level measured (lights.md §7).

Per level and case, one line: the objective; the modelled light over the target's (area-weighted means over RGB);
the share of the target's area that gets almost no modelled light (< 2 % of its target) and the part of the
objective it carries; the objective's under-lit and over-lit parts (squared shortfall and excess over the target's
squared norm, on the RGB means); the share of the area a sun reaches. Needs the shader scripts
(Tools~/install-openarena-textures.sh).
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import replace

import numpy as np

from lpnn.lights.emitters import Emitters, Suns, emitter_bytes
from lpnn.lights.pipeline import level_emitters, load_scene, point_lights_of
from lpnn.lights.rig import entity_lights
from lpnn.scenes.levels import load_level
from lpnn.scenes.lightgrid import LINEAR_PER_BYTE

ALMOST_UNLIT = 0.02  # of the point's target light
BOUNCE_ADD = 500.0 * 1.0 * 0.375 * 3.0 * 0.25  # bytes per unit form factor of texture x luxel / 255 (docstring)
BOUNCE_DIRECTIONS = 32
BOUNCE_MATCH = 32.0  # Quake units between a gather ray's hit and the target point that stands for it
RAY_OFFSET = 0.5
RAY_LENGTH = 65536.0


def one_bounce(model, luxels: np.ndarray) -> np.ndarray:
    """(N, 3) bytes one q3map2 bounce adds at the target points, given every point's luxel bytes (docstring)."""
    from scipy.spatial import cKDTree

    k = np.arange(BOUNCE_DIRECTIONS)
    u = (k + 0.5) / BOUNCE_DIRECTIONS
    angle = k * math.pi * (3.0 - math.sqrt(5.0))
    local = np.stack([np.sqrt(u) * np.cos(angle), np.sqrt(u) * np.sin(angle), np.sqrt(1.0 - u)], axis=1)
    normals = model.normals
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    first = np.cross(normals, helper)
    first /= np.linalg.norm(first, axis=1, keepdims=True)
    second = np.cross(normals, first)
    emitted = model.albedo * luxels / 255.0
    tree = cKDTree(model.points)
    gathered = np.zeros_like(model.points)
    origins = model.points + RAY_OFFSET * normals
    for x, y, z in local:
        direction = x * first + y * second + z * normals
        distance, _ = model.raycaster.cast(origins, direction, RAY_LENGTH)
        hit = np.flatnonzero(np.isfinite(distance))
        gap, nearest = tree.query(origins[hit] + distance[hit, None] * direction[hit])
        facing = (gap < BOUNCE_MATCH) & (np.einsum("ij,ij->i", normals[nearest], direction[hit]) < 0)
        gathered[hit[facing]] += emitted[nearest[facing]]
    return BOUNCE_ADD * gathered / BOUNCE_DIRECTIONS


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("levels", nargs="+", metavar="LEVEL")
    args = parser.parse_args(argv)
    for name in args.levels:
        level = load_level(name)
        scene = load_scene(level)
        real = entity_lights(level.bsp.entities, level.name)
        emitters = level_emitters(level, real)
        lights = point_lights_of(real)
        model = scene.model
        sun_bytes = emitter_bytes(model.points, model.normals, Emitters(suns=emitters.suns), model.raycaster)
        others = emitter_bytes(model.points, model.normals, replace(emitters, suns=Suns.empty()), model.raycaster)
        weights, target = model.weights, model.radiance.mean(axis=1)
        norm = float(np.sum(weights * target ** 2))
        cases = [("without suns", others), ("with suns", others + sun_bytes)]
        model.fixed = cases[1][1]
        luxels = model.radiance_of(lights, model.visibility(lights)) / np.maximum(model.albedo * LINEAR_PER_BYTE, 1e-12)
        cases.append(("with suns and one bounce", cases[1][1] + one_bounce(model, luxels)))
        for label, fixed in cases:
            model.fixed = fixed
            visible = model.visibility(lights)
            modelled = model.radiance_of(lights, visible).mean(axis=1)
            objective = model.objective(lights, visible, with_gradient=False).value
            dark = (modelled < ALMOST_UNLIT * target) & (target > 0)
            under = float(np.sum(weights * np.maximum(target - modelled, 0.0) ** 2)) / norm
            over = float(np.sum(weights * np.maximum(modelled - target, 0.0) ** 2)) / norm
            carried = float(np.sum(weights[dark] * (target[dark] - modelled[dark]) ** 2)) / norm
            print(f"{level.name} {label}: objective {objective:.4f}, modelled / target light "
                  f"{np.sum(weights * modelled) / np.sum(weights * target):.2f}, area almost unlit "
                  f"{weights[dark].sum():.1%} carrying {carried:.3f}; under-lit {under:.3f}, over-lit {over:.3f}; "
                  f"area a sun reaches {weights[sun_bytes.max(axis=1) > 0].sum():.1%}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
