"""The recipe's parts without game data: level split, stored reference, summary, card report."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.quality.bench.results import BenchRow
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.placement.decimation.reference_fast import fast_decimation
from lpnn.recipe.config import RecipeConfig
from lpnn.recipe.evaluation import geometric_mean, goal_checks, summarize
from lpnn.recipe.labelling import labelled, stored_reference
from lpnn.recipe.levels import split_levels
from lpnn.recipe.publish import TABLE_BEGIN, TABLE_END, card_with_recipe, documented_table, report_markdown
from lpnn.train.modelcard import ModelCard


def test_split_is_by_rule_disjoint_and_covers_every_level() -> None:
    names = [f"level{i:02d}" for i in range(49)]
    split = split_levels(list(reversed(names)), RecipeConfig())  # input order does not matter
    assert split.held_out == tuple(names[2::5])
    assert len(split.held_out) == 10
    parts = [set(split.train), set(split.validation), set(split.held_out)]
    assert set().union(*parts) == set(names)
    assert sum(len(p) for p in parts) == len(names)
    assert all(split.role(n) == "held_out" for n in split.held_out)


def test_split_refuses_to_leave_a_part_empty() -> None:
    with pytest.raises(ValueError, match="empty part"):
        split_levels(["a", "b"], RecipeConfig())


def test_stored_reference_rebuilds_the_decimation_exactly() -> None:
    capture = AnalyticScene.random(4, cell_size=0.5, room_size=(2.5, 2.0, 1.5)).capture(name="room")
    result, seconds = labelled(capture, 0.2)
    assert seconds > 0
    fresh = fast_decimation(ReferenceField.from_capture(capture), workers=1)
    rebuilt = stored_reference(result)
    assert np.array_equal(rebuilt.ordering, fresh.ordering)
    n = capture.point_count
    for count in (4, n // 5, n // 2, n):
        assert np.array_equal(rebuilt.prefix(count), fresh.prefix(count))
        assert rebuilt.error_curve[count] == pytest.approx(fresh.error_curve[count], rel=1e-6, abs=1e-7)
    assert int(result.labels.sum()) == int(math.floor(0.2 * n + 0.5))
    assert np.array_equal(np.flatnonzero(result.labels), np.sort(fresh.ordering[:int(result.labels.sum())]))


def test_stored_reference_needs_the_sections() -> None:
    capture = AnalyticScene.random(4, cell_size=0.5, room_size=(1.5, 1.5, 1.5)).capture(name="room")
    with pytest.raises(ValueError, match="reference_rank"):
        stored_reference(capture)


def test_geometric_mean_leaves_out_unusable_ratios() -> None:
    assert geometric_mean([2.0, 8.0]) == (pytest.approx(4.0), 0)
    assert geometric_mean([2.0, math.inf, 0.0, math.nan, 8.0]) == (pytest.approx(4.0), 3)
    value, left_out = geometric_mean([])
    assert math.isnan(value) and left_out == 0


def _row(crop: str, method: str, policy: str, parameter: float, error: float, probes: int = 10) -> dict:
    return dataclasses.asdict(BenchRow(
        capture=crop, points=100, method=method, policy=policy, parameter=parameter, probes=probes, seconds=0.01,
        feature_seconds=0.02, inference_seconds=0.001, selection_seconds=0.003, refine_seconds=None,
        mean_error=error, p95_error=2 * error, smape_mean=error, smape_p95=error, reference_error=0.0,
        error_ratio=0.0, reference_probes=8 if policy == "tolerance" else None,
        probes_ratio=probes / 8 if policy == "tolerance" else None))


def _crops() -> list[dict]:
    """Two crops where LPNN's error is 1.2x / 1.5x the reference's and half the uniform one's."""
    crops = []
    for name, factor in (("a", 1.2), ("b", 1.5)):
        rows = []
        for budget in (0.1, 0.2, 0.3):
            reference = 0.1 * (1 - budget)
            rows += [_row(name, "fast-reference", "budget", budget, reference),
                     _row(name, "network", "budget", budget, reference * factor),
                     _row(name, "guided-exact-refined", "budget", budget, reference * 1.05),
                     _row(name, "uniform", "budget", budget, reference * factor * 2),
                     _row(name, "heuristic", "budget", budget, reference * factor * 1.25),
                     _row(name, "insertion", "budget", budget, reference * factor / 1.1)]
        rows += [_row(name, "fast-reference", "tolerance", 0.05, 0.049, 8),
                 _row(name, "network", "tolerance", 0.05, 0.048, 12)]
        crops.append({"name": name, "points": 100, "roc_auc": 0.8, "pr_auc": 0.5 if name == "a" else math.nan,
                      "rows": rows})
    return crops


def test_summary_ratios_are_per_crop_geometric_means() -> None:
    summary = summarize(_crops())
    lpnn = next(m for m in summary["methods"] if (m["method"], m["policy"], m["parameter"]) == ("network", "budget", 0.2))
    assert lpnn["error_vs_reference"] == pytest.approx(math.sqrt(1.2 * 1.5))
    assert lpnn["error_vs_uniform"] == pytest.approx(0.5)
    assert lpnn["error_vs_heuristic"] == pytest.approx(0.8)
    tolerance = next(m for m in summary["methods"] if (m["method"], m["policy"]) == ("network", "tolerance"))
    assert tolerance["probes_vs_reference"] == pytest.approx(1.5) and tolerance["probes_vs_reference_left_out"] == 0
    assert lpnn["error_vs_reference_left_out"] == 0  # counted beside every mean, also when none is left out
    assert tolerance["within_tolerance"] == 2
    assert summary["pr_auc"] == pytest.approx(0.5)  # the crop without a defined PR-AUC is left out
    goals = goal_checks(summary)
    assert goals["network: error <= 1.15x reference"] is False
    assert goals["guided-exact-refined: error <= 1.15x reference"] is True
    assert goals["network: error <= 0.85x uniform"] is True
    assert lpnn["error_vs_insertion"] == pytest.approx(1.1)  # the bar: LPNN must be <= 0.8x it
    assert goals["network: error <= 0.8x insertion (best non-learned)"] is False
    assert summary["failures"] == []
    crops = _crops()
    crops[0]["failures"] = [{"capture": "a", "method": "apv", "reason": "ValueError: flat"}]
    assert summarize(crops)["failures"] == crops[0]["failures"]


def test_summary_of_nothing_is_an_error() -> None:
    with pytest.raises(ValueError, match="no held-out crops"):
        summarize([])


def _card() -> ModelCard:
    return ModelCard(format="lpnn.modelcard", version=1, model_file="lpnn_default.onnx", schema="s",
                     feature_names=["f"], feature_count=1, input={}, output={}, opset=15, ops=[], normalisation={},
                     architecture={}, training={}, metrics={}, versions={}, parity={})


def test_report_renders_the_card_and_the_document_check_finds_it() -> None:
    summary = summarize(_crops())
    summary["goals"] = goal_checks(summary)
    recipe = {"levels": {"train": ["t"], "validation": ["v"], "held_out": ["h1", "h2"], "skipped": {}},
              "label_source": "reference:fast-greedy budget=0.2", "seconds": {"labels": 120.0}}
    card = card_with_recipe(_card(), recipe, summary, {"10000": 4.5})
    table = report_markdown(card)
    assert table.startswith(TABLE_BEGIN) and table.rstrip().endswith(TABLE_END)
    assert "h1, h2" in table and "| Network | 20% | 10 | 1.34 | 0.50 | 0.80 | 20 | 1 | 3 | – | 10 |" in table
    assert "10,000 points 4.5 ms" in table and "**missed**" in table and "labels 2.0 min" in table
    document = "# Benchmarks\n\ntext\n" + table + "more text\n"
    assert documented_table(document) == table
    assert documented_table("# no table\n") is None


def test_report_refuses_a_card_without_recipe_figures() -> None:
    with pytest.raises(ValueError, match="no recipe figures"):
        report_markdown(_card())


def test_a_card_without_the_recipe_levels_does_not_say_whether_a_level_is_held_out() -> None:
    from types import SimpleNamespace

    from lpnn.demo.run import held_out_in_card

    assert held_out_in_card(SimpleNamespace(training={"recipe": {}}), "oa_dm1") is None
    assert held_out_in_card(SimpleNamespace(training={"recipe": {"levels": {"held_out": None}}}), "oa_dm1") is None
    assert held_out_in_card(SimpleNamespace(training={"recipe": {"levels": {"held_out": ["oa_dm1"]}}}), "oa_dm1")


@pytest.mark.parametrize("damaged", ['{"pak": "x", ', "\xff\xfe", "[]"])
def test_a_damaged_work_file_is_named_with_what_to_do(tmp_path, damaged: str) -> None:
    from pathlib import Path

    from lpnn.cli.errors import UserError
    from lpnn.core.engine import Engine
    from lpnn.recipe.run import RecipePaths, StepTimes, check_manifest, evaluate_held_out

    paths = RecipePaths(tmp_path)
    for file in (paths.manifest, paths.evaluation, tmp_path / "times.json"):
        file.write_bytes(damaged.encode("latin-1"))
    config = RecipeConfig()
    if damaged != "[]":  # valid JSON that differs from the options is the other error ("made with other options")
        with pytest.raises(UserError, match=r"recipe\.json is damaged .*delete it to redo that step"):
            check_manifest(paths, config, Path("pak.pk3"))
    with pytest.raises(UserError, match=r"evaluation\.json is damaged"):
        evaluate_held_out(paths, [], print, Engine())
    with pytest.raises(UserError, match=r"times\.json is damaged"):
        StepTimes.load(tmp_path / "times.json")
