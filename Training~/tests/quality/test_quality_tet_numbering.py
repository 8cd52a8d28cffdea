"""The tie rule's numbering of tetrahedra (lpnn.quality.metric.tet_numbering; quality.md §1 "Ties") against
Tests/Data/tet_numbering_golden.json (written in plain integers by Tools~/golden/make_tet_numbering_golden.py, not by this
code; the C# TetrahedronNumberingTests read it too), splitmix64's published outputs, and its independence of the order
Qhull, the caller or a derivation lists the tetrahedra and probes in."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from lpnn.quality.metric.tet_numbering import GOLDEN_GAMMA, mix64, numbered, tet_hash
from lpnn.quality.metric.triangulation import tetrahedralize

GOLDEN = json.loads((Path(__file__).resolve().parents[3] / "Tests" / "Data" / "tet_numbering_golden.json")
                    .read_text(encoding="utf-8"))


def test_the_mixer_is_splitmix64():
    # splitmix64 seeded with 1234567 (Vigna's reference generator, prng.di.unimi.it/splitmix64.c): its first outputs.
    published = [6457827717110365317, 3203168211198807973, 9817491932198370423, 4593380528125082431, 16408922859458223821]
    with np.errstate(over="ignore"):
        states = np.uint64(1234567) + GOLDEN_GAMMA * np.arange(1, 6, dtype=np.uint64)
    assert mix64(states).tolist() == published


def test_the_golden_tetrahedra_are_numbered_as_written():
    ids = np.array(GOLDEN["ids"])
    result = numbered(np.array(GOLDEN["tetrahedra"]), ids)
    assert result.tolist() == GOLDEN["numbered"]
    assert [f"0x{h:016X}" for h in tet_hash(ids[result]).tolist()] == GOLDEN["hashes"]


def test_any_order_of_the_same_tetrahedra_gives_the_same_numbering():
    ids = np.array(GOLDEN["ids"])
    tets = np.array(GOLDEN["tetrahedra"])
    expected = numbered(tets, ids)
    rng = np.random.default_rng(3)
    for _ in range(20):
        rows = tets[rng.permutation(tets.shape[0])]
        shuffled = np.take_along_axis(rows, np.argsort(rng.random(rows.shape), axis=1), axis=1)
        assert np.array_equal(numbered(shuffled, ids), expected)


def test_a_tetrahedralisation_is_numbered_by_its_probes_point_indices_whatever_their_order():
    rng = np.random.default_rng(11)
    lattice = np.stack(np.meshgrid(np.arange(5.0), np.arange(4.0), np.arange(3.0), indexing="ij"), axis=-1).reshape(-1, 3)
    world = np.concatenate([lattice, rng.random((40, 3)) * 4.0])  # cospherical ties and general positions
    ids = rng.permutation(10_000)[:world.shape[0]]
    first = tetrahedralize(world, ids=ids)
    for _ in range(3):
        order = rng.permutation(world.shape[0])  # Qhull sees the points in another order, so lists its facets otherwise
        again = tetrahedralize(world[order], ids=ids[order])
        assert np.array_equal(ids[order][again.tets], ids[first.tets])
        assert np.array_equal(again.inverse, first.inverse)  # the same corners in the same order: the same arithmetic
    keys = tet_hash(np.sort(ids[first.tets], axis=1))
    assert np.all(keys[1:] >= keys[:-1])
