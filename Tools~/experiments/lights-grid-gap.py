#!/usr/bin/env python3
"""Where the real rig's re-lit light grid differs from the stored one (lights.md §6-7, benchmarks.md "The light rig").

  PYTHONPATH=Training~ python Tools~/experiments/lights-grid-gap.py LEVEL [LEVEL ...]

The level's own lights, spotlights, surface lights, suns and ambient re-light the stored grid's valid nodes as
evaluate.py's "real rig" row does (compare.relight_stored_grid: the same contributions and sum); each node's error
is quality.md's relative irradiance error over D14 (its mean over nodes is the row's grid error). Per level it prints:

1. the grid error, then one line per node group: the group's share of the nodes, its mean error and its share of the
   summed error. Groups: where the node is sampled (open; moved out of solid by TraceGrid's nudge; still in solid),
   whether the stored ambient A or directed D is clamped (a channel at 255), how far the nearest light source is,
   how high the sample is above the first surface below it, and whether the re-lit node is brighter or darker than
   the stored one (the sign of the summed difference of the 42 shaded values);
2. the parts: the error with only one of the re-lit A, D or direction l put into the stored node (the others
   stored), the mean luminance of A and D, stored and re-lit, and the median angle between the directions;
3. q3map2's trace rules that the grid rule leaves out (light_trace.c TraceLine_r: a shadow ray through a BSP leaf of
   cluster -1, structural solid or the void, is blocked whatever the inhibit radius; light.c
   LightContributionToPoint: a light outside the node's PVS is skipped): the grid error with each, and both;
4. the grid error with the ambient summed otherwise: with and without the worldspawn ambient (q3map2's grid holds
   none, compare.py), and 0, 0.125 (q3map2 since 2003-07-05) or 0.25 (id's q3map, q3map2 before) of D added to A.

Every number is deterministic (no random numbers). Needs the shader scripts (Tools~/install-openarena-textures.sh).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from lpnn.core.features import scene_scale
from lpnn.core.sh import ambient_plus_directed
from lpnn.lights.compare import (GRID_AMBIENT_FUDGE, NODES_PER_CHUNK, GridNodes, combine_grid, compare_grid,
                                 grid_contributions, grid_inhibit, grid_sample_points, q3map2_grid, shade, stored_grid)
from lpnn.lights.pipeline import level_emitters, point_lights_of
from lpnn.lights.rig import Rig, entity_lights
from lpnn.lights.shadows import shadow_raycaster
from lpnn.quality.metric.metric import irradiance_error
from lpnn.scenes.levels import load_level
from lpnn.scenes.solid import SolidTester

BYTE_MAX = 255.0
LUMINANCE = np.array([0.299, 0.587, 0.114])
NEAR_LIGHT, FAR_LIGHT = 96.0, 256.0  # Quake units to the nearest light source (2.4 m, 6.5 m)
LOW, HIGH = 64.0, 160.0  # Quake units above the first surface below the sample
FLOOR_SEARCH = 4096.0
TRACE_ON_EPSILON = 0.1  # light_trace.c: a segment end this close to a split plane counts on both sides
VISIBILITY_LUMP = 16


class LeafWalk:
    """The world BSP's leaves: a point's cluster (light_ydnar.c ClusterForPoint) and whether a segment crosses a leaf of
    cluster -1 (light_trace.c TraceLine_r, TRACE_LEAF_SOLID), vectorised over points and segments."""

    def __init__(self, solid: SolidTester) -> None:
        self.solid = solid

    def clusters(self, points: np.ndarray) -> np.ndarray:
        """(N,) the cluster of each point's leaf; on a split plane the leaf with a cluster wins (PointInLeafNum_r)."""
        pair_point, pair_leaf = self.solid.leaves_near(points)
        cluster = self.solid.leaf_clusters[pair_leaf]
        out = np.full(len(points), -1, dtype=np.int64)
        np.maximum.at(out, pair_point, cluster)
        return out

    def crosses_solid(self, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
        """(S,) bool: the segment from each start to its end passes through a leaf of cluster -1."""
        s = self.solid
        blocked = np.zeros(len(starts), bool)
        segment = np.arange(len(starts))
        node = np.zeros(len(starts), dtype=np.int64)
        a, b = np.asarray(starts, dtype=np.float64), np.asarray(ends, dtype=np.float64)
        for _ in range(len(s.node_planes) + 1):
            leaf = node < 0
            blocked[segment[leaf][s.leaf_clusters[-node[leaf] - 1] < 0]] = True
            keep = ~leaf & ~blocked[segment]
            segment, node, a, b = segment[keep], node[keep], a[keep], b[keep]
            if len(segment) == 0:
                return blocked
            plane = s.node_planes[node]
            normal, dist = s.plane_normals[plane], s.plane_dists[plane]
            front = np.einsum("ij,ij->i", a, normal) - dist
            back = np.einsum("ij,ij->i", b, normal) - dist
            in_front = (front >= -TRACE_ON_EPSILON) & (back >= -TRACE_ON_EPSILON)
            behind = ~in_front & (front < TRACE_ON_EPSILON) & (back < TRACE_ON_EPSILON)
            split = ~in_front & ~behind
            side = (front[split] < 0).astype(np.int64)
            fraction = front[split] / (front[split] - back[split])
            middle = a[split] + (b[split] - a[split]) * fraction[:, None]
            children = s.node_children[node]
            segment = np.concatenate([segment[in_front], segment[behind], segment[split], segment[split]])
            node = np.concatenate([children[in_front, 0], children[behind, 1],
                                   children[split, side], children[split, 1 - side]])
            a = np.concatenate([a[in_front], a[behind], a[split], middle])
            b = np.concatenate([b[in_front], b[behind], middle, b[split]])
        raise ValueError("the BSP tree has a cycle")


def visibility(data: bytes) -> tuple[int, np.ndarray] | None:
    """(bytes per cluster, the PVS bits (clusters, bytes) uint8) of lump 16, None when the level is not vised."""
    offset, length = (int(v) for v in np.frombuffer(data, dtype="<i4", count=2, offset=8 + 8 * VISIBILITY_LUMP))
    if length <= 8:
        return None
    clusters, per_cluster = (int(v) for v in np.frombuffer(data, dtype="<i4", count=2, offset=offset))
    bits = np.frombuffer(data, dtype=np.uint8, count=clusters * per_cluster, offset=offset + 8)
    return per_cluster, bits.reshape(clusters, per_cluster)


def trace_culls(walk: LeafWalk, pvs: np.ndarray | None, nodes: np.ndarray, sources: np.ndarray,
                lit: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((C, K) the lit pairs q3map2 drops by a cluster -1 leaf on the segment from the node to the source, (C, K) those
    whose source's cluster is outside the node's PVS); suns (NaN sources) are never dropped."""
    positioned = np.isfinite(sources).all(axis=1)
    outside_pvs = np.zeros(lit.shape, bool)
    if pvs is not None:
        node_cluster = walk.clusters(nodes)
        source_cluster = np.full(len(sources), -1, dtype=np.int64)
        source_cluster[positioned] = walk.clusters(sources[positioned])
        a = np.maximum(node_cluster, 0)[:, None]
        b = np.maximum(source_cluster, 0)[None, :]
        visible = (((pvs[a, b >> 3] >> (b & 7)) & 1) > 0) | (node_cluster[:, None] == source_cluster[None, :])
        visible &= (node_cluster[:, None] >= 0) & (source_cluster[None, :] >= 0)
        outside_pvs = lit & ~visible & positioned[None, :]
    through_solid = np.zeros(lit.shape, bool)
    node, light = np.nonzero(lit & positioned[None, :])
    through_solid[node, light] = walk.crosses_solid(nodes[node], sources[light])
    return through_solid, outside_pvs


def per_node_errors(stored: GridNodes, relit: GridNodes, scale: float) -> np.ndarray:
    return irradiance_error(shade(relit), shade(stored), scale)


def group_line(label: str, member: np.ndarray, errors: np.ndarray) -> str:
    count = int(member.sum())
    if count == 0:
        return f"  {label}: no node"
    return (f"  {label}: {count / len(errors):.1%} of nodes, mean error {errors[member].mean():.3f}, "
            f"{errors[member].sum() / errors.sum():.1%} of the summed error")


def scale_fit(stored: GridNodes, relit: GridNodes, ambient: np.ndarray, excluded: np.ndarray) -> str:
    """Least squares, in luminance over the nodes neither clamped nor dark: the stored D against the re-lit D
    (D_stored = b D), and the stored A less the worldspawn `ambient` against the re-lit rule's two parts (A_stored -
    ambient = x sum 0.25 (1 - dir.l) c + y D, the rule's x = 1, y = GRID_AMBIENT_FUDGE); a negative y says the stored
    grid holds less than the worldspawn ambient."""
    used = ~excluded
    if used.sum() < 3:
        return "  scale fit: fewer than 3 unclamped lit nodes"
    d_stored, d_relit = stored.directed[used] @ LUMINANCE, relit.directed[used] @ LUMINANCE
    a_stored = stored.ambient[used] @ LUMINANCE - ambient @ LUMINANCE
    spread = relit.ambient[used] @ LUMINANCE - GRID_AMBIENT_FUDGE * d_relit  # the re-lit grid holds no ambient
    b = float(d_stored @ d_relit / (d_relit @ d_relit))
    (x, y), *_ = np.linalg.lstsq(np.stack([spread, d_relit], axis=1), a_stored, rcond=None)
    return (f"  scale fit over {used.sum():,} unclamped lit nodes ({used.mean():.0%}): D stored = {b:.2f} x D re-lit; "
            f"A stored - ambient = {x:.2f} x (the off-direction quarter) + {y:.3f} x D re-lit (the rule: 1 and "
            f"{GRID_AMBIENT_FUDGE}); A / D stored {(stored.ambient[used] @ LUMINANCE).sum() / d_stored.sum():.2f}, "
            f"re-lit {(relit.ambient[used] @ LUMINANCE).sum() / d_relit.sum():.2f}")


def level_report(name: str) -> list[str]:
    level = load_level(name)
    bsp = level.bsp
    real = entity_lights(bsp.entities, level.name)
    if real.rig.count == 0:
        return [f"{level.name}: no light entity: no real rig to re-light the grid with"]
    emitters = level_emitters(level, real)
    lights = point_lights_of(real)
    rig = Rig.from_quake(lights.positions, lights.colours, lights.intensities, ambient=lights.ambient)
    raycaster = shadow_raycaster(bsp)
    solid = SolidTester(bsp)

    def is_open(points: np.ndarray) -> np.ndarray:
        return ~solid.solid_or_outside(points)

    stored = stored_grid(bsp)
    samples = grid_sample_points(stored.positions, is_open)
    inhibit = grid_inhibit(bsp)

    walk = LeafWalk(solid)
    vis = visibility(level.data)
    pvs = vis[1] if vis is not None else None
    rules = ("as modelled", "rays blocked by cluster -1 leaves", "lights outside the PVS skipped", "both")
    sums = tuple(f"{label}, {share} D" for label in ("with the worldspawn ambient", "without it")
                 for share in (0.0, GRID_AMBIENT_FUDGE, 0.25))
    parts = {rule: [] for rule in rules + sums}
    for start in range(0, len(samples), NODES_PER_CHUNK):
        nodes = samples[start:start + NODES_PER_CHUNK]
        colour, unit, sources = grid_contributions(nodes, rig, raycaster, emitters, inhibit)
        through_solid, outside_pvs = trace_culls(walk, pvs, nodes, sources, colour.max(axis=2) > 0)
        for rule, dropped in zip(rules, (None, through_solid, outside_pvs, through_solid | outside_pvs)):
            kept = colour if dropped is None else np.where(dropped[..., None], 0.0, colour)
            parts[rule].append(q3map2_grid(kept, unit))
        for rule in sums:
            ambient = rig.ambient if rule.startswith("with the") else np.zeros(3)
            parts[rule].append(combine_grid(colour, unit, ambient, float(rule.split(", ")[1].split()[0])))

    def relit_with(rule: str) -> GridNodes:
        ambient, directed, direction = (np.concatenate([chunk[k] for chunk in parts[rule]]) for k in range(3))
        return GridNodes(stored.positions, ambient, directed, direction)

    relit = relit_with("as modelled")
    scale = scene_scale(ambient_plus_directed(stored.ambient, stored.directed, stored.direction).reshape(-1, 27))
    errors = per_node_errors(stored, relit, scale)
    lines = [f"{level.name}: {len(errors):,} valid nodes, grid error {errors.mean():.3f} "
             f"(compare_grid: {compare_grid(stored, relit).mean_error:.3f}), p95 {np.percentile(errors, 95):.3f}"]

    moved = ~is_open(stored.positions)
    unresolved = ~is_open(samples)
    lines += [group_line("sampled where it is (open)", ~moved, errors),
              group_line("moved out of solid", moved & ~unresolved, errors),
              group_line("still in solid after the nudge", unresolved, errors)]
    stored_clamped = (stored.ambient.max(axis=1) >= BYTE_MAX) | (stored.directed.max(axis=1) >= BYTE_MAX)
    relit_clamped = (relit.ambient.max(axis=1) >= BYTE_MAX - 1e-6) | (relit.directed.max(axis=1) >= BYTE_MAX - 1e-6)
    lines += [group_line("stored A or D clamped at 255", stored_clamped, errors),
              group_line("re-lit A or D clamped at 255", relit_clamped, errors),
              group_line("neither clamped", ~stored_clamped & ~relit_clamped, errors)]
    sources = np.concatenate([rig.quake_positions(), emitters.spots.positions, emitters.splash_positions,
                              emitters.areas.origins]).reshape(-1, 3)
    nearest = np.full(len(samples), np.inf)
    for start in range(0, len(samples), 2048):
        chunk = samples[start:start + 2048]
        nearest[start:start + 2048] = np.linalg.norm(chunk[:, None] - sources[None], axis=2).min(axis=1, initial=np.inf)
    lines += [group_line(f"nearest light < {NEAR_LIGHT:.0f} units", nearest < NEAR_LIGHT, errors),
              group_line(f"nearest light {NEAR_LIGHT:.0f}-{FAR_LIGHT:.0f} units",
                         (nearest >= NEAR_LIGHT) & (nearest < FAR_LIGHT), errors),
              group_line(f"nearest light >= {FAR_LIGHT:.0f} units", nearest >= FAR_LIGHT, errors)]
    down = np.broadcast_to([0.0, 0.0, -1.0], samples.shape).copy()
    floor, _ = raycaster.cast(samples, down, FLOOR_SEARCH)
    lines += [group_line(f"< {LOW:.0f} units above the surface below", floor < LOW, errors),
              group_line(f"{LOW:.0f}-{HIGH:.0f} units above it", (floor >= LOW) & (floor < HIGH), errors),
              group_line(f">= {HIGH:.0f} units above it (or none below)", floor >= HIGH, errors)]
    difference = (shade(relit) - shade(stored)).sum(axis=1)
    lines += [group_line("over-lit (re-lit brighter)", difference > 0, errors),
              group_line("under-lit (re-lit darker or equal)", difference <= 0, errors)]
    dark = relit.directed.max(axis=1) <= 0
    lines.append(group_line("no light reaches the re-lit node (D = 0)", dark, errors))

    def swapped(ambient=stored.ambient, directed=stored.directed, direction=stored.direction) -> float:
        return float(per_node_errors(stored, GridNodes(stored.positions, ambient, directed, direction), scale).mean())

    cosine = np.clip(np.einsum("ij,ij->i", stored.direction, relit.direction), -1.0, 1.0)
    lines.append(f"  parts: only the re-lit A {swapped(ambient=relit.ambient):.3f}, only D "
                 f"{swapped(directed=relit.directed):.3f}, only l {swapped(direction=relit.direction):.3f}, "
                 f"D and l {swapped(directed=relit.directed, direction=relit.direction):.3f}, A and D "
                 f"{swapped(ambient=relit.ambient, directed=relit.directed):.3f}; mean luminance A stored "
                 f"{(stored.ambient @ LUMINANCE).mean():.1f} re-lit {(relit.ambient @ LUMINANCE).mean():.1f}, D stored "
                 f"{(stored.directed @ LUMINANCE).mean():.1f} re-lit {(relit.directed @ LUMINANCE).mean():.1f}; "
                 f"median angle between the directions {np.degrees(np.median(np.arccos(cosine[~dark]))):.0f} deg "
                 f"(nodes with light on both sides)" if (~dark).any() else "  parts: no re-lit light")

    lines.append(scale_fit(stored, relit, rig.ambient, stored_clamped | relit_clamped | dark))

    source_clusters = walk.clusters(sources) if len(sources) else np.zeros(0, dtype=np.int64)
    lines.append(f"  light sources in a leaf of cluster -1 (q3map2 nudges by 2 units or drops them): "
                 f"{int((source_clusters < 0).sum())} of {len(sources)}; PVS {'present' if pvs is not None else 'absent'}")
    for rule in rules[1:]:
        culled = relit_with(rule)
        lines.append(f"  with q3map2's trace: {rule}: grid error {per_node_errors(stored, culled, scale).mean():.3f} "
                     f"(compare_grid {compare_grid(stored, culled).mean_error:.3f})")
    lines.append("  the ambient's sum: " + "; ".join(
        f"{rule}: {per_node_errors(stored, relit_with(rule), scale).mean():.3f}" for rule in sums))
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("levels", nargs="+", metavar="LEVEL")
    args = parser.parse_args(argv)
    for name in args.levels:
        for line in level_report(name):
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
