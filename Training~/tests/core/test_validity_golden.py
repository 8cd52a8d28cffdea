"""Probe validity against the shared golden file (built by construction, Tools~/golden/make_validity_golden.py)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lpnn.core.validity import BACK_FACE_THRESHOLD, CAPTURE_SECTION, RAY_LENGTH, back_face_fraction, invalid

GOLDEN = Path(__file__).resolve().parents[3] / "Tests" / "Data" / "validity_golden.json"


def test_threshold_ray_length_and_section_match_the_golden() -> None:
    golden = json.loads(GOLDEN.read_text(encoding="utf-8"))
    assert golden["threshold"] == BACK_FACE_THRESHOLD
    assert golden["ray_length"] == RAY_LENGTH
    assert golden["capture_section"] == CAPTURE_SECTION


def test_every_golden_case() -> None:
    cases = json.loads(GOLDEN.read_text(encoding="utf-8"))["cases"]
    assert len(cases) >= 7
    for case in cases:
        fraction = back_face_fraction(np.array(case["directions"])[None], np.array([case["hits"]]), np.array(case["normals"])[None])
        assert fraction[0] == pytest.approx(case["back_face_fraction"], abs=1e-12), case["name"]
        assert bool(invalid(fraction)[0]) == case["invalid"], case["name"]


def test_shared_directions_and_bad_shapes() -> None:
    d = np.eye(3)
    fraction = back_face_fraction(d, np.array([[True, True, False]]), np.array([[[1, 0, 0], [0, -1, 0], [0, 0, 0]]]))
    assert fraction.tolist() == [pytest.approx(1 / 3)]
    with pytest.raises(ValueError, match="at least one ray"):
        back_face_fraction(np.zeros((0, 3)), np.zeros((1, 0), dtype=bool), np.zeros((1, 0, 3)))
    with pytest.raises(ValueError, match="do not match"):
        back_face_fraction(d, np.ones((1, 3), dtype=bool), np.zeros((1, 2, 3)))
