"""The validity rule applied to points by casting the 26 feature rays (lpnn.core.validity.back_face_fractions)."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.validity import CAPTURE_SECTION, RAY_LENGTH, back_face_fractions, invalid, valid_points, without_invalid


class SolidSlab:
    """The solid x in [low, high]: two faces whose normals point out of it (-x at low, +x at high)."""

    def __init__(self, low: float = 1.5, high: float = 3.5) -> None:
        self.faces = ((low, -1.0), (high, 1.0))
        self.lengths: list[float] = []

    def cast(self, origins: np.ndarray, directions: np.ndarray, max_distance: float) -> tuple[np.ndarray, np.ndarray]:
        self.lengths.append(max_distance)
        distances = np.full(len(origins), np.inf)
        normals = np.zeros((len(origins), 3))
        for face, normal in self.faces:
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (face - origins[:, 0]) / directions[:, 0]
            closer = (directions[:, 0] != 0) & (t >= 0) & (t <= max_distance) & (t < distances)
            distances[closer] = t[closer]
            normals[closer] = (normal, 0.0, 0.0)
        return distances, normals


def test_points_inside_the_solid_see_back_faces_and_outside_front_faces() -> None:
    slab = SolidSlab()
    points = np.array([[0.0, 0, 0], [2.0, 0, 0], [3.0, 5, -1], [5.0, 0, 0]])
    fractions = back_face_fractions(points, slab)
    # 18 of the 26 directions have an x component: inside, each meets a face from behind
    assert fractions == pytest.approx([0.0, 18 / 26, 18 / 26, 0.0])
    assert invalid(fractions).tolist() == [False, True, True, False]
    assert slab.lengths == [RAY_LENGTH]


def test_far_faces_count_so_deep_solid_is_found() -> None:
    # 1,000 m deep inside a thick solid: 4-cell feature rays would meet nothing, the validity rays meet its faces
    fractions = back_face_fractions(np.array([[0.0, 0, 0]]), SolidSlab(-1000.0, 1000.0))
    assert fractions[0] == pytest.approx(18 / 26)


def test_bad_positions_are_refused() -> None:
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        back_face_fractions(np.zeros((2, 2)), SolidSlab())


def test_without_invalid_keeps_every_per_point_array_aligned_and_refuses_flat_sets() -> None:
    capture = AnalyticScene.random(3, cell_size=0.5, room_size=(1.5, 1.25, 1.25)).capture(name="room")
    n = capture.point_count
    fractions = np.where(np.arange(n) % 3 == 0, 0.5, 0.0).astype(np.float32)
    marked = capture.with_labels(np.arange(n) % 2, "test")
    marked = type(marked)(**{**marked.__dict__, "extra_sections": {CAPTURE_SECTION: fractions}})
    valid = valid_points(marked)
    assert valid is not None and valid.tolist() == (np.arange(n) % 3 != 0).tolist()
    kept = without_invalid(marked, valid)
    assert kept.point_count == int(valid.sum())
    for name in ("ids", "positions", "sh", "features", "labels"):
        assert np.array_equal(getattr(kept, name), getattr(marked, name)[valid]), name
    assert np.array_equal(kept.extra_sections[CAPTURE_SECTION], fractions[valid])
    assert valid_points(capture) is None and without_invalid(capture, None) is capture
    flat = capture.ids[:, 2] == capture.ids[0, 2]
    with pytest.raises(ValueError, match="all in one plane"):
        without_invalid(capture, flat)
