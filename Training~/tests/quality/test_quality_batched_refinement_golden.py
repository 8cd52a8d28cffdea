"""Tests/Data/batched_refinement_golden.json (written by Tools~/golden/make_batched_refinement_golden.py; contract
quality.md §5.3): the Python batched refinement still keeps the golden's points, with the same rounds, stop reason and
per-round candidates and commits. The C# port (BatchedRefinementTests) reads the same file."""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import pytest

from lpnn.core.grid import EvaluationGrid
from lpnn.quality.placement.batched_refinement import (COUNT_COMMIT_FRACTION, TOLERANCE_COMMIT_FRACTION,
                                                       batched_refinement)
from lpnn.quality.metric.metric import ReferenceField

GOLDEN_NAME = "batched_refinement_golden.json"


@pytest.fixture(scope="module")
def cases(golden: Callable[[str], Any]) -> list[dict[str, Any]]:
    document = golden(GOLDEN_NAME)
    assert document["tolerance"].startswith("exact")
    assert [c["name"] for c in document["cases"]] == ["count", "tolerance"]
    return document["cases"]


@pytest.mark.parametrize("index", [0, 1])
def test_the_refinement_keeps_the_golden_points_round_by_round(cases: list[dict[str, Any]], index: int) -> None:
    case = cases[index]
    grid = EvaluationGrid(cell_size=case["cell_size"], ids=np.asarray(case["ids"], dtype=np.int32))
    np.testing.assert_array_equal(grid.positions, np.asarray(case["positions"], dtype=np.float32))
    field = ReferenceField.from_sh(grid.positions, np.asarray(case["sh"], dtype=np.float32), case["lighting_scale"])
    assert case["commit_fraction"] == (COUNT_COMMIT_FRACTION if "count" in case else TOLERANCE_COMMIT_FRACTION)
    rounds: list[dict[str, Any]] = []
    result = batched_refinement(field, np.asarray(case["seed_points"]), count=case.get("count"),
                                tolerance=case.get("tolerance"), keep=np.asarray(case["keep"]), trace=rounds.append)
    decisions = [{"probes": r["probes"].tolist(), "candidates": r["candidates"].tolist(), "commit": r["commit"].tolist()}
                 for r in rounds if "candidates" in r]
    assert decisions == case["trace"]
    assert result.indices.tolist() == case["indices"]
    assert (result.rounds, result.stop_reason) == (case["rounds"], case["stop_reason"])
    assert result.mean_error == pytest.approx(case["mean_error"], rel=1e-9)
    assert set(case["keep"]) <= set(case["indices"])
    if "tolerance" in case:
        assert result.mean_error <= case["tolerance"]
        # The last rounds commit nothing: stale costs are measured again before the refinement gives up.
        assert case["trace"][-1]["commit"] == [] and case["stop_reason"] == "tolerance"
    else:
        assert len(case["indices"]) == case["count"]
