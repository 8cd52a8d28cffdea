"""OnnxScorer: the class the benchmark imports; card checks and input checks."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.errors import UserError
from lpnn.core.schema import THESIS30
from lpnn.train.onnx_scoring import OnnxScorer
from lpnn.train.synthetic import synthetic_capture

from train_support import TrainedModel


def test_scores_one_value_per_point(trained: TrainedModel) -> None:
    scorer = OnnxScorer(trained.model)
    assert scorer.card.schema == "lpnn.features.v1" and scorer.feature_count == 19
    assert scorer.session.get_session_options().intra_op_num_threads == 2
    capture = synthetic_capture(42, shape=(5, 4, 3))
    scores = scorer.score_capture(capture)
    assert scores.shape == (60,) and scores.dtype == np.float32
    assert np.all((scores >= 0) & (scores <= 1))
    assert scorer.score(np.zeros((0, 19), np.float32)).shape == (0,)
    np.testing.assert_array_equal(scorer.score(capture.features.astype(np.float64)), scores)


def test_schema_mismatch_names_both_schemas(trained: TrainedModel) -> None:
    scorer = OnnxScorer(trained.model)
    capture = synthetic_capture(0)
    legacy = dataclasses.replace(capture, schema=THESIS30.id, feature_names=list(THESIS30.names),
                                 features=np.zeros((capture.point_count, 30), np.float32))
    with pytest.raises(UserError, match=r"old.lpnncap has schema 'lpnn.thesis30' \(30 features\) but the model 'model.onnx' has schema 'lpnn.features.v1' \(19"):
        scorer.check_capture(legacy, "old.lpnncap")
    renamed = list(capture.feature_names)
    renamed[4] = "light_var"
    with pytest.raises(UserError, match="feature 4 is 'light_var' in x.lpnncap and 'light_variance' in the model"):
        scorer.check_schema("lpnn.features.v1", renamed, "x.lpnncap")


def test_bad_feature_arrays_are_refused(trained: TrainedModel) -> None:
    scorer = OnnxScorer(trained.model)
    with pytest.raises(UserError, match=r"expected \[points, 19\]"):
        scorer.score(np.zeros((4, 18), np.float32))
    bad = np.zeros((4, 19), np.float32)
    bad[2, 0] = np.inf
    with pytest.raises(UserError, match="point 2 are not finite"):
        scorer.score(bad)


def test_a_model_without_its_card_is_refused(trained: TrainedModel, tmp_path: Path) -> None:
    lonely = shutil.copy(trained.model, tmp_path / "lonely.onnx")
    with pytest.raises(UserError, match="lonely.card.json: model card not found"):
        OnnxScorer(lonely)
