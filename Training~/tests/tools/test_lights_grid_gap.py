"""Tools~/experiments/lights-grid-gap.py (lights.md §7, benchmarks.md "The light rig") on the light-rig tests' synthetic
level (two light entities, a stored grid, one vised cluster): its groups partition the nodes, its grid error is
compare_grid's, and its BSP walk tells open segments from segments that leave the map."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

from tools_support import REPO, load_tool, run_experiment

sys.path[:0] = [str(REPO / "Training~" / "tests" / "lights"), str(REPO / "Training~" / "tests" / "scenes")]
from lit_bsp import lit_level  # noqa: E402  (the light-rig tests' synthetic level)

from lpnn.lights.compare import compare_grid, grid_sample_points, relight_stored_grid, stored_grid  # noqa: E402
from lpnn.lights.pipeline import level_emitters, point_lights_of  # noqa: E402
from lpnn.lights.rig import Rig, entity_lights  # noqa: E402
from lpnn.lights.shadows import shadow_raycaster  # noqa: E402
from lpnn.scenes.levels import load_level  # noqa: E402
from lpnn.scenes.solid import SolidTester  # noqa: E402


def shares(lines: list[str], labels: list[str]) -> float:
    total = 0.0
    for label in labels:
        line = next(line for line in lines if line.strip().startswith(label))
        match = re.search(r": ([0-9.]+)% of nodes", line)
        total += float(match.group(1)) if match else 0.0  # "no node"
    return total


def test_the_groups_partition_the_nodes_and_the_error_is_the_yardsticks(tmp_path: Path) -> None:
    """With a worldspawn ambient (which q3map2's grid leaves out), the first line's error is the one the evaluation's
    yardstick computes through compare.relight_stored_grid."""
    synthetic = lit_level()
    synthetic.entities = synthetic.entities.replace('"classname" "worldspawn"', '"classname" "worldspawn"\n"ambient" "20"')
    level = tmp_path / "lit.bsp"
    level.write_bytes(synthetic.to_bytes())
    lines = run_experiment("lights-grid-gap.py", str(level)).stdout.splitlines()
    head = re.fullmatch(r"lit: (\d+) valid nodes, grid error ([0-9.]+) \(compare_grid: ([0-9.]+)\), p95 [0-9.]+", lines[0])
    assert head is not None and int(head.group(1)) > 0 and head.group(2) == head.group(3)
    assert head.group(2) == f"{yardstick_grid_error(level):.3f}"
    assert abs(shares(lines, ["sampled where", "moved out of", "still in solid"]) - 100.0) < 0.2
    assert abs(shares(lines, ["over-lit", "under-lit"]) - 100.0) < 0.2
    assert abs(shares(lines, ["nearest light <", "nearest light 96", "nearest light >="]) - 100.0) < 0.2
    assert any(line.strip().startswith("parts: only the re-lit A") for line in lines)
    assert sum("with q3map2's trace" in line for line in lines) == 3
    sums = next(line for line in lines if "the ambient's sum" in line)
    assert f"without it, 0.125 D: {head.group(2)}" in sums  # today's rule: q3map2's, no worldspawn ambient in the grid


def yardstick_grid_error(path: Path) -> float:
    """evaluate.py's real-rig grid error, through the library (lpnn.lights.compare), not the script."""
    level = load_level(str(path))
    real = entity_lights(level.bsp.entities, level.name)
    lights = point_lights_of(real)
    assert np.all(lights.ambient == 20.0)
    rig = Rig.from_quake(lights.positions, lights.colours, lights.intensities, ambient=lights.ambient)
    solid = SolidTester(level.bsp)
    stored = stored_grid(level.bsp)
    relit = relight_stored_grid(level.bsp, stored, rig, shadow_raycaster(level.bsp),
                                lambda p: ~solid.solid_or_outside(p), level_emitters(level, real))
    return compare_grid(stored, relit).mean_error


def test_the_bsp_walk_blocks_a_segment_that_leaves_the_map(tmp_path: Path) -> None:
    path = tmp_path / "lit.bsp"
    path.write_bytes(lit_level().to_bytes())
    bsp = load_level(str(path)).bsp
    solid = SolidTester(bsp)
    nodes = stored_grid(bsp).positions
    samples = grid_sample_points(nodes, lambda p: ~solid.solid_or_outside(p))
    inside = samples[~solid.solid_or_outside(samples)][:1]
    assert len(inside) == 1
    walk = load_tool("lights-grid-gap.py").LeafWalk(solid)
    assert walk.clusters(inside)[0] >= 0
    beyond = bsp.world_maxs + 1000.0  # outside the world: a leaf of cluster -1
    assert walk.clusters(beyond[None])[0] == -1
    np.testing.assert_array_equal(walk.crosses_solid(np.concatenate([inside, inside]),
                                                     np.concatenate([inside, beyond[None]])), [False, True])
