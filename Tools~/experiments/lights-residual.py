#!/usr/bin/env python3
"""What a level's real rig leaves unexplained (lights.md §7, benchmarks.md §8): the level's own light entities,
spotlights, surface lights, suns and ambient through the forward model (lights.md §3), without and with its suns.

  PYTHONPATH=Training~ python Tools~/experiments/lights-residual.py LEVEL [LEVEL ...]

Per level and case, one line: the objective; the modelled light over the target's (area-weighted means over RGB);
the share of the target's area that gets almost no modelled light (< 2 % of its target) and the part of the
objective it carries; the objective's under-lit and over-lit parts (squared shortfall and excess over the target's
squared norm, on the RGB means); the share of the area a sun reaches. Needs the shader scripts
(Tools~/install-openarena-textures.sh).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace

import numpy as np

from lpnn.lights.emitters import Emitters, Suns, emitter_bytes
from lpnn.lights.pipeline import level_emitters, load_scene, point_lights_of
from lpnn.lights.rig import entity_lights
from lpnn.scenes.levels import load_level

ALMOST_UNLIT = 0.02  # of the point's target light


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
        for label, fixed in (("without suns", others), ("with suns", others + sun_bytes)):
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
