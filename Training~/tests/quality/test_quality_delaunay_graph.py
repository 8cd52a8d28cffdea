"""The Delaunay graph's update after a removal (placement/delaunay_graph.py): graph_edges' array exactly, from Qhull's
tetrahedralisations of random points before and after."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.quality.metric.triangulation import HULL, INNER_BOUNDARY, tetrahedralize
from lpnn.quality.placement.batched_refinement import greedy_independent_set
from lpnn.quality.placement.delaunay_graph import edges_after_removal, graph_edges


def _global_tets(ids: np.ndarray, world: np.ndarray):
    """The tetrahedralisation of the points `ids` of `world`: (mesh, tetrahedra in global ids)."""
    mesh = tetrahedralize(world[ids])
    return mesh, ids[mesh.tets]


def _key_set(tets: np.ndarray) -> set[tuple[int, ...]]:
    return {tuple(row) for row in np.sort(tets, axis=1).tolist()}


def _removal(world: np.ndarray, ids: np.ndarray, seed: int, count: int):
    """(old edges, old global tets, old neighbours, gone mask, refills, new edges) for removing `count` probes of an
    independent set chosen by a random rank."""
    rng = np.random.default_rng(seed)
    mesh, tets = _global_tets(ids, world)
    edges = graph_edges(ids, mesh.tets)
    rank = np.full(world.shape[0], np.iinfo(np.int64).max, dtype=np.int64)
    rank[ids] = rng.permutation(ids.shape[0])
    removed = greedy_independent_set(ids, edges, rank)[:count]
    gone = np.zeros(world.shape[0], dtype=bool)
    gone[removed] = True
    remaining = ids[~gone[ids]]
    new_mesh, new_tets = _global_tets(remaining, world)
    old_keys = _key_set(tets)
    refills = np.asarray([row for row in new_tets.tolist() if tuple(sorted(row)) not in old_keys], dtype=np.int64)
    return edges, tets, mesh.neighbours, gone, refills.reshape(-1, 4), graph_edges(remaining, new_mesh.tets)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("count", [1, 5, 40])
def test_the_update_is_the_graph_made_afresh(seed: int, count: int) -> None:
    rng = np.random.default_rng(100 + seed)
    world = rng.uniform(-1.0, 1.0, (160, 3)) * [3.0, 1.0, 2.0] + 1e4  # far from the origin
    ids = np.sort(rng.choice(world.shape[0], 120, replace=False))
    edges, tets, neighbours, gone, refills, fresh = _removal(world, ids, seed, count)
    updated = edges_after_removal(edges, tets, neighbours, gone, refills)
    assert updated is not None
    np.testing.assert_array_equal(updated, fresh)


def _edge_set(tets: np.ndarray) -> list[list[int]]:
    """Every edge of the tetrahedra both ways, sorted: the definition, by Python sets."""
    pairs = {(a, b) for row in tets.tolist() for a in row for b in row if a != b}
    return sorted([a, b] for a, b in pairs)


def test_the_update_is_the_graph_of_the_kept_tetrahedra_and_the_refills_given() -> None:
    """Removing points keeps every Delaunay edge between kept points (an empty sphere stays empty), so with Qhull's
    refills no edge between kept probes is lost; but the state's tetrahedra are derived, not Qhull's, and the graph
    must be theirs: refills that leave out an edge only removed stars held lose it (here the refills without their
    tetrahedra holding such an edge)."""
    dropped = 0
    for seed in range(12):
        rng = np.random.default_rng(seed)
        world = rng.uniform(0.0, 1.0, (90, 3))
        ids = np.arange(world.shape[0])
        edges, tets, neighbours, gone, refills, _ = _removal(world, ids, seed, 30)
        kept_tets = tets[~gone[tets].any(axis=1)]
        star_tets = tets[gone[tets].any(axis=1)]
        only_in_stars = ({tuple(e) for e in _edge_set(star_tets) if not gone[e[0]] and not gone[e[1]]}
                         - {tuple(e) for e in _edge_set(kept_tets)})
        if not only_in_stars:
            continue
        a, b = min(only_in_stars)
        partial = refills[~(np.isin(refills, [a]).any(axis=1) & np.isin(refills, [b]).any(axis=1))]
        updated = edges_after_removal(edges, tets, neighbours, gone, partial)
        assert updated.tolist() == _edge_set(np.concatenate([kept_tets, partial]))
        assert [a, b] not in updated.tolist()
        dropped += 1
    assert dropped > 0


def test_a_star_next_to_a_crack_is_left_to_the_graph_made_afresh() -> None:
    rng = np.random.default_rng(7)
    world = rng.uniform(0.0, 1.0, (40, 3))
    ids = np.arange(world.shape[0])
    edges, tets, neighbours, gone, refills, _ = _removal(world, ids, 7, 3)
    cracked = neighbours.copy()
    star = np.flatnonzero(gone[tets].any(axis=1))[0]
    cracked[star, 0] = INNER_BOUNDARY
    assert edges_after_removal(edges, tets, cracked, gone, refills) is None


def test_nothing_removed_keeps_the_graph() -> None:
    rng = np.random.default_rng(3)
    world = rng.uniform(0.0, 1.0, (30, 3))
    ids = np.arange(world.shape[0])
    mesh, tets = _global_tets(ids, world)
    edges = graph_edges(ids, mesh.tets)
    kept = edges_after_removal(edges, tets, mesh.neighbours, np.zeros(world.shape[0], dtype=bool),
                               np.zeros((0, 4), dtype=np.int64))
    np.testing.assert_array_equal(kept, edges)


def test_the_update_is_the_graph_made_afresh_on_a_lattice_with_hull_vertices_removed() -> None:
    """The fields' points are a lattice (many cospherical points: the tetrahedralisation is one of many) and removals
    take hull vertices too, whose stars are fans open to the outside."""
    lattice = np.stack(np.meshgrid(*[np.arange(6.0)] * 3, indexing="ij"), axis=-1).reshape(-1, 3) * 0.25 + 1e3
    hull_removals = 0
    for seed in range(12):
        ids = np.sort(np.random.default_rng(seed).choice(lattice.shape[0], 150, replace=False))
        edges, tets, neighbours, gone, refills, fresh = _removal(lattice, ids, seed, 1 + seed)
        faces_on_hull = [np.delete(tets[t], i) for t, i in zip(*np.nonzero(neighbours == HULL))]
        hull_removals += int(gone[np.concatenate(faces_on_hull)].any())
        updated = edges_after_removal(edges, tets, neighbours, gone, refills)
        assert updated is not None
        np.testing.assert_array_equal(updated, fresh)
    assert hull_removals > 0
