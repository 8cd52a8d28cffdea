"""Tests/Data/insertion_golden.json (written by Tools~/golden/make_insertion_golden.py; contract quality.md §5):
the Python insertion ranking still gives its typical tetrahedra, every round's batch given the mesh, and the whole
ranking, and the golden's tetrahedra are still the (unique, certified) Delaunay ones ours produce; on the "ties" case's
lattice (tetrahedra not unique: the golden's, numbered as ours) every point's cell and weights are the tie rules' the
generator derived in exact arithmetic (quality.md §1 "Ties"). The C# port (InsertionRankingTests) reads the same
file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.insertion import (EXACT, guide_weights, insertion_batch, insertion_ranking, insertion_start,
                                              typical_tetrahedron)
from lpnn.quality.metric.metric import ReferenceField, probe_stencil
from lpnn.quality.metric.triangulation import tetrahedralize

GOLDEN_NAME = "insertion_golden.json"


@pytest.fixture(scope="module")
def golden(golden_path: Callable[[str], Path]) -> dict[str, Any]:
    return json.loads(golden_path(GOLDEN_NAME).read_text(encoding="utf-8"))


def _case(case: dict[str, Any]) -> tuple[EvaluationGrid, ReferenceField]:
    grid = EvaluationGrid(cell_size=case["cell_size"], ids=np.asarray(case["ids"], dtype=np.int32))
    np.testing.assert_array_equal(grid.positions, np.asarray(case["positions"], dtype=np.float32))
    field = ReferenceField.from_sh(grid.positions, np.asarray(case["sh"], dtype=np.float32), case["lighting_scale"])
    return grid, field


def _guide(case: dict[str, Any]) -> np.ndarray | None:
    """The case's guide weights (None: plain insertion), checked to be guide_weights of its float32 scores, exactly."""
    if "scores" not in case:
        return None
    guide = guide_weights(np.asarray(case["scores"], dtype=np.float32))
    np.testing.assert_array_equal(guide, np.asarray(case["guide"], dtype=np.float64), err_msg=case["name"])
    return guide


def _tet_keys(tets) -> list[tuple[int, ...]]:
    return sorted(tuple(sorted(int(v) for v in t)) for t in tets)


def test_the_golden_lists_the_certified_cases(golden: dict[str, Any]) -> None:
    assert golden["tolerance"].startswith("exact")
    assert golden["exact_threshold"] == EXACT
    assert [c["name"] for c in golden["cases"]] == ["enclosed", "outside", "plane", "guided", "ties"]


def test_typical_tetrahedra_are_reproduced(golden: dict[str, Any]) -> None:
    for case in golden["cases"]:
        if "typical_tetrahedron" in case:
            grid, field = _case(case)
            np.testing.assert_array_equal(typical_tetrahedron(field, grid), case["typical_tetrahedron"], err_msg=case["name"])
            np.testing.assert_array_equal(insertion_start(field, grid), case["start"], err_msg=case["name"])


def test_every_round_given_its_mesh_is_reproduced(golden: dict[str, Any]) -> None:
    rounds = 0
    for case in golden["cases"]:
        grid, field = _case(case)
        for round_ in case.get("rounds", []):
            probes = np.asarray(round_["probes"], dtype=np.int64)
            tri = tetrahedralize(field.world[probes], field.frame, probes)  # numbered by point index, as a round
            assert _tet_keys(tri.tets) == _tet_keys(round_["tetrahedra"]), case["name"]
            if case["name"] == "ties":  # the tie rules read the tetrahedra's numbering: the same, index for index
                assert tri.tets.tolist() == round_["tetrahedra"]
            np.testing.assert_array_equal(insertion_batch(field, probes, growth=case["growth"], guide=_guide(case)),
                                          round_["batch"], err_msg=case["name"])
            rounds += 1
    assert rounds > 10


@pytest.mark.parametrize("name", ["enclosed", "guided"])
def test_the_whole_ranking_is_reproduced_and_is_its_rounds_in_order(golden: dict[str, Any], name: str) -> None:
    case = next(c for c in golden["cases"] if c["name"] == name)
    grid, field = _case(case)
    ranking = insertion_ranking(field, grid, growth=case["growth"], guide=_guide(case))
    np.testing.assert_array_equal(ranking, case["ranking"])
    order = list(case["start"])
    for round_ in case["rounds"]:
        assert round_["probes"] == order
        order += round_["batch"]
    assert ranking[:len(order)].tolist() == order
    # The start is the enclosing tetrahedron's corners (the case's design): no point is ever outside the hull.
    corners = np.asarray(case["ids"])[case["typical_tetrahedron"]]
    assert sorted(map(tuple, corners.tolist())) == sorted(map(tuple, np.asarray([[0, 0, 0], [1024, 37, 91], [53, 1024, 11], [29, 71, 1024]]).tolist()))
    if name == "guided":  # the guide matters in this case: plain insertion ranks the same points otherwise
        assert insertion_ranking(field, grid, growth=case["growth"]).tolist() != case["ranking"]


def test_the_plane_case_needs_the_tetrahedron_guarantee(golden: dict[str, Any]) -> None:
    """By hand: the middle layer is the median, its 13 lowest indices are the candidates, all at k = 2, so the
    fifth point is the first point off that plane in the preference order: point 0."""
    case = next(c for c in golden["cases"] if c["name"] == "plane")
    start = case["typical_tetrahedron"]
    ids = np.asarray(case["ids"])
    assert len(start) == 5 and start[-1] == 0
    assert all(ids[p][2] == 2 for p in start[:4])
    assert all(p < 50 + 13 for p in start[:4])
    # The ranking's start then adds the cube's other 7 corners (i, j, k each 0 or 4; point 0 is listed), by direction.
    corners = [int(np.flatnonzero((ids == [4 * a, 4 * b, 4 * c]).all(axis=1))[0]) for a in (0, 1) for b in (0, 1) for c in (0, 1)]
    assert case["start"] == start + corners[1:]


def test_the_ties_case_gives_every_point_the_exact_tie_rules_cell_and_weights(golden: dict[str, Any]) -> None:
    """quality.md §1 "Ties": points on faces, edges and vertices shared by several tetrahedra take the lowest-index one,
    points outside with several nearest hull triangles take the lowest owner's, snapped onto the shared edge or vertex;
    the golden's cells and weights come from the generator's brute-force enumeration in exact rationals."""
    case = next(c for c in golden["cases"] if c["name"] == "ties")
    _, field = _case(case)
    round_ = case["rounds"][0]
    probes = np.asarray(round_["probes"], dtype=np.int64)
    indices, others, stencil = probe_stencil(field, probes)
    np.testing.assert_array_equal(indices, probes)  # stencil vertices are positions in the probes list
    np.testing.assert_array_equal(stencil.cell, np.asarray(round_["cells"])[others])
    for row, point in enumerate(others.tolist()):
        ours = np.zeros(probes.shape[0])
        np.add.at(ours, stencil.vertices[row], stencil.weights[row])
        expected = np.zeros(probes.shape[0])
        for vertex, weight in round_["stencils"][point]:
            expected[vertex] = weight
        np.testing.assert_allclose(ours, expected, rtol=0.0, atol=1e-12, err_msg=f"point {point}")
    assert np.count_nonzero(stencil.outside) > 10
