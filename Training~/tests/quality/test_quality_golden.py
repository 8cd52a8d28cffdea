"""Tests/Data/placement_error_golden.json (written by Tools~/golden/make_quality_golden.py) still holds:
the metric, the tetrahedra and the tolerance policy reproduce it, and its stencils alone give its
per-point errors (which is how the C# port uses it, with Unity's or its own tetrahedra)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

from lpnn.core import sh as shmath
from lpnn.core.features import D14
from lpnn.core.grid import EvaluationGrid
from lpnn.core.spread import spread_ranking
from lpnn.quality.metric.metric import POINT_ERRORS, ReferenceField, placement_error, point_errors
from lpnn.quality.placement.policies import place_tolerance, prefix_selection
from lpnn.quality.metric.triangulation import tetrahedralize

GOLDEN_NAME = "placement_error_golden.json"


@pytest.fixture(scope="module")
def golden(golden_path: Callable[[str], Path]) -> dict[str, Any]:
    return json.loads(golden_path(GOLDEN_NAME).read_text(encoding="utf-8"))


def _field(golden: dict[str, Any]) -> ReferenceField:
    return ReferenceField.from_sh(np.asarray(golden["positions"], dtype=np.float32),
                                  np.asarray(golden["sh"], dtype=np.float32), golden["lighting_scale"])


def _close(actual, expected, tolerance: dict[str, float]) -> None:
    np.testing.assert_allclose(actual, expected, rtol=tolerance["rel"], atol=tolerance["abs"])


def test_the_metric_reproduces_the_golden_errors(golden: dict[str, Any]) -> None:
    field = _field(golden)
    probes = np.asarray(golden["probes"], dtype=np.int64)
    tolerance = golden["tolerance"]
    for metric in ("irradiance", "smape"):
        expected = [p[metric] for p in golden["points"]]
        _close(point_errors(field, probes, metric), expected, tolerance)
        summary = placement_error(field, probes, metric)
        _close([summary.mean, summary.p95], [golden[metric]["mean"], golden[metric]["p95"]], tolerance)
    assert any(p.get("outside") for p in golden["points"])  # the nearest-hull-point rule is exercised


def test_the_tetrahedra_are_the_unique_delaunay_ones(golden: dict[str, Any]) -> None:
    field = _field(golden)
    probes = np.asarray(golden["probes"], dtype=np.int64)
    tri = tetrahedralize(field.world[probes], field.frame)
    assert {tuple(sorted(t)) for t in tri.tets.tolist()} == {tuple(sorted(t)) for t in golden["tetrahedra"]}
    assert {tuple(sorted(t)) for t in tri.hull_faces.tolist()} == {tuple(sorted(t)) for t in golden["hull_triangles"]}


def test_the_stencils_alone_give_the_errors(golden: dict[str, Any]) -> None:
    # What the C# port does: blend the probes' SH with the stencil, evaluate in D14, compare.
    sh = np.asarray(golden["sh"], dtype=np.float32).astype(np.float64)
    probes = np.asarray(golden["probes"], dtype=np.int64)
    light = shmath.evaluate(sh, D14).reshape(sh.shape[0], -1)
    ycocg = shmath.rgb_to_ycocg(shmath.evaluate(sh, D14)).reshape(sh.shape[0], -1)
    scale = golden["lighting_scale"]
    for point in golden["points"]:
        if "probe" in point:
            assert probes[point["probe"]] == point["index"] and point["irradiance"] == 0.0
            continue
        weights = np.asarray(point["weights"])
        assert np.all(weights >= 0.0) and weights.sum() == pytest.approx(1.0)
        stencil = probes[np.asarray(point["stencil"])]
        for metric, values in (("irradiance", light), ("smape", ycocg)):
            blended = (weights[:, None] * values[stencil]).sum(axis=0)
            error = POINT_ERRORS[metric](blended[None], values[point["index"]][None], scale)[0]
            assert error == pytest.approx(point[metric], rel=1e-9, abs=1e-12)


def test_the_tolerance_policy_replays(golden: dict[str, Any]) -> None:
    field = _field(golden)
    policy = golden["tolerance_policy"]
    positions = np.asarray(golden["positions"], dtype=np.float32)
    scores = np.asarray(policy["scores"], dtype=np.float32)
    ranking = spread_ranking(positions, scores)
    np.testing.assert_array_equal(ranking, policy["ranking"])
    ids = np.round(positions - positions.min(axis=0)).astype(np.int32)  # the jittered lattice's own ids
    placement = place_tolerance(field, prefix_selection(EvaluationGrid(cell_size=1.0, ids=ids), ranking),
                                policy["tolerance"])
    assert placement.requested == policy["count"]
    assert list(placement.checked) == [c["count"] for c in policy["checked"]]
    _close(list(placement.checked.values()), [c["mean_error"] for c in policy["checked"]], golden["tolerance"])
