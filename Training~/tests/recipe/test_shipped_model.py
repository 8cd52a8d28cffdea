"""The model the package ships: its card, its honesty (held-out levels never trained on) and its
agreement with Documentation~/benchmarks.md."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.main import main
from lpnn.core.schema import LPNN_V1
from lpnn.recipe.config import RecipeConfig
from lpnn.recipe.levels import split_levels
from lpnn.train.modelcard import ModelCard, card_path
from lpnn.train.onnx_scoring import OnnxScorer

REPO = Path(__file__).resolve().parents[3]
SHIPPED = REPO / "Packages" / "com.lpnn.probes" / "Models" / "lpnn_default.onnx"
BENCHMARKS = REPO / "Documentation~" / "benchmarks.md"


@pytest.fixture(scope="module")
def card() -> ModelCard:
    return ModelCard.read(card_path(SHIPPED))


def test_shipped_card_matches_the_feature_schema_and_the_file(card: ModelCard) -> None:
    assert card.model_file == SHIPPED.name
    assert card.schema == LPNN_V1.id and card.feature_names == list(LPNN_V1.names)


def test_held_out_levels_follow_the_rule_and_were_never_trained_on(card: ModelCard) -> None:
    levels = card.training["recipe"]["levels"]
    every = sorted(levels["train"] + levels["validation"] + levels["held_out"])
    split = split_levels(every, RecipeConfig())
    assert list(split.held_out) == levels["held_out"] and list(split.validation) == levels["validation"]
    assert len(levels["held_out"]) >= 0.2 * len(every)
    trained_on = {name.split("@")[0] for name in card.training["captures"]}
    assert trained_on <= set(levels["train"])


def test_benchmarks_page_shows_the_cards_figures(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["recipe", "report", str(SHIPPED), "--check", str(BENCHMARKS)]) == 0, capsys.readouterr().err


def test_shipped_model_scores_in_range_and_deterministically() -> None:
    scorer = OnnxScorer(SHIPPED)
    features = np.random.default_rng(0).normal(size=(500, scorer.feature_count)).astype(np.float32)
    first, second = scorer.score(features), scorer.score(features)
    assert first.shape == (500,) and np.all((first >= 0) & (first <= 1))
    assert np.array_equal(first, second)
    assert float(first.std()) > 1e-3  # not a constant (the thesis model scored everything 0.46-0.48)
