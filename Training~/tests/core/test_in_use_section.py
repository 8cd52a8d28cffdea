"""Which points of a capture are in use (in-use.md "What placement does with the mask"), and the error reports read
there (quality.metric.evaluate_placement's in_use_error, lpnn bench's in_use_error column)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.in_use_section import IN_USE_SECTION, capture_rule, in_use_label, in_use_points, in_use_text
from lpnn.quality.bench.results import CSV_COLUMNS, BenchConfig, rows_csv
from lpnn.quality.bench.run import bench_capture
from lpnn.quality.metric.metric import ReferenceField, evaluate_placement, point_errors


def _room():
    return AnalyticScene.random(5, cell_size=0.5, room_size=(2.5, 1.5, 2.0)).capture(name="room")


def _all_marked(capture, in_use: int, rule: str):
    """`capture` as an `all` capture whose section marks its first `in_use` points in use by `rule`."""
    mask = np.zeros(capture.point_count, dtype=np.uint8)
    mask[:in_use] = 1
    return replace(capture, source={**capture.source, "in_use": "all", "in_use_report_rule": rule},
                   extra_sections={IN_USE_SECTION: mask})


def test_old_captures_say_nothing_filtered_ones_are_all_in_use_and_all_captures_read_their_section():
    old = _room()
    assert capture_rule(old) == "all" and in_use_points(old) is None
    band = replace(old, source={**old.source, "in_use": "band"})
    assert in_use_points(band).all()
    mask = (np.arange(old.point_count) % 3 == 0).astype(np.uint8)
    marked = replace(old, source={**old.source, "in_use": "all"}, extra_sections={IN_USE_SECTION: mask})
    assert in_use_points(marked).tolist() == (mask == 1).tolist()
    assert in_use_text(math.nan) == "n/a" and in_use_text(0.123456) == "0.1235"


def test_the_error_at_the_points_in_use_is_the_mean_over_them():
    old = _room()
    mask = (np.arange(old.point_count) % 3 == 0).astype(np.uint8)
    marked = replace(old, extra_sections={IN_USE_SECTION: mask})
    field = ReferenceField.from_capture(marked)
    probes = np.arange(0, old.point_count, 5)
    quality = evaluate_placement(field, probes)
    errors = point_errors(field, probes)
    assert math.isclose(quality.in_use_error, float(errors[mask == 1].mean()))
    assert quality.in_use_error != quality.irradiance.mean  # the air is not averaged in
    assert math.isnan(evaluate_placement(ReferenceField.from_capture(old), probes).in_use_error)


def test_every_bench_row_carries_the_error_at_the_points_in_use():
    old = _room()
    mask = (np.arange(old.point_count) % 2 == 0).astype(np.uint8)
    marked = replace(old, extra_sections={IN_USE_SECTION: mask})
    geometry = AnalyticScene.random(5, cell_size=0.5, room_size=(2.5, 1.5, 2.0)).raycaster
    result = bench_capture("room", marked, BenchConfig(budgets=(0.2,), repeats=1, faithful_limit=0), geometry=geometry)
    assert result.rows and all(0.0 <= row.in_use_error <= 1.0 and 0.0 <= row.leaking <= 1.0 for row in result.rows)
    assert "in_use_error" in CSV_COLUMNS and rows_csv(result.rows).splitlines()[0].endswith("in_use_error,leaking")
    without = bench_capture("room", marked, BenchConfig(budgets=(0.2,), repeats=1, faithful_limit=0))
    assert all(math.isnan(row.leaking) for row in without.rows)  # no geometry: leaks not known


def test_dataset_info_names_the_rule_and_its_counts():
    from lpnn.cli.dataset_cmd import in_use_summary

    old = _room()
    assert "not recorded" in in_use_summary(old)
    reachable = replace(old, source={**old.source, "in_use": "reachable", "points_before_in_use": 5000})
    assert in_use_summary(reachable) == f"reachable: all {old.point_count:,} (of 5,000 valid points)"
    marked = _all_marked(old, 7, "band")
    assert in_use_summary(marked) == "all points kept; 7 in use by the band rule (section in_use)"


def test_reports_name_the_points_their_in_use_figures_are_over():
    # An `all` capture places every point; its "in use" error is over the section's points only, and the label says
    # how many and by which rule, so it is not read as the error over all of them (lpnn place's report).
    old = _room()
    assert in_use_label(old) == "not recorded"
    assert in_use_label(replace(old, source={**old.source, "in_use": "reachable"})) == "reachable"
    marked = _all_marked(old, 34, "band")
    assert in_use_label(marked) == "34 points by the band rule"


def test_the_demo_names_the_points_in_use_of_a_capture_that_placed_every_point():
    from types import SimpleNamespace

    from lpnn.demo.report import in_use_line

    old = _room()
    marked = _all_marked(old, 34, "reachable")
    assert in_use_line(SimpleNamespace(capture=marked)) == (
        "points in use: 34 points by the reachable rule (every point of the volume placed)")
    assert in_use_line(SimpleNamespace(capture=old)) == "points in use: not recorded (every point of the volume placed)"
