"""Leaks on a real level (openarena-081-maps; installed by Tools~/install-openarena.sh, never committed)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.quality.metric.leaks import leak_report, near_surface_mask
from lpnn.quality.metric.metric import ReferenceField
from lpnn.scenes.capture_geometry import capture_raycaster
from lpnn.scenes.importer import import_level
from lpnn.scenes.levels import load_pak_member

pytestmark = pytest.mark.openarena


def test_sparse_probes_leak_through_the_walls_of_a_real_level(openarena_pak: Path) -> None:
    capture = import_level(load_pak_member(openarena_pak, "maps/oa_dm1.bsp"), timings_in_source=False).capture
    raycaster, why = capture_raycaster(capture, openarena_pak)
    assert raycaster is not None, why
    field = ReferenceField.from_capture(capture)
    near = near_surface_mask(capture.feature_names, capture.features)
    sparse = np.linspace(0, capture.point_count - 1, 24).astype(np.int64)  # 24 probes over an indoor level of rooms
    report = leak_report(field, sparse, raycaster, near_surface=near)
    assert report.points == capture.point_count
    assert 0.2 < report.leaking_share < 1.0  # tetrahedra spanning rooms: most points see a hidden probe
    assert report.leaking_error > 0 and 0 < report.near_surface_points < report.points
    every = leak_report(field, np.arange(capture.point_count), raycaster)
    assert every.leaking == 0  # every point a probe: nothing is interpolated


def test_captures_without_a_level_have_no_geometry(openarena_pak: Path) -> None:
    synthetic = AnalyticScene.random(3).capture()
    assert capture_raycaster(synthetic)[0] is None
    capture = import_level(load_pak_member(openarena_pak, "maps/oa_dm1.bsp"), timings_in_source=False).capture
    changed = replace(capture, source={**capture.source, "bsp_sha256": "0" * 64})
    raycaster, why = capture_raycaster(changed, openarena_pak)
    assert raycaster is None and "SHA-256 differs" in why
