"""Tools~/experiments/recipe-crops.py: crops of the training or validation split only; held-out levels are refused."""

from __future__ import annotations

import pytest

from tools_support import load_tool

CARD = {"training": {"recipe": {"levels": {"train": ["b", "a"], "validation": ["v"], "held_out": ["h"]}}}}


def test_the_split_of_the_card_is_used_and_held_out_levels_are_refused() -> None:
    tool = load_tool("recipe-crops.py")
    assert tool.levels_for_role(CARD, "validation") == ["v"]
    assert tool.levels_for_role(CARD, "train") == ["a", "b"]
    with pytest.raises(SystemExit, match="held-out levels are never used"):
        tool.levels_for_role(CARD, "held_out")
    with pytest.raises(SystemExit, match="no training.recipe.levels"):
        tool.levels_for_role({"training": {}}, "train")


def test_the_shipped_card_has_a_split_whose_validation_levels_are_not_held_out() -> None:
    import json

    card = json.loads(load_tool("recipe-crops.py").DEFAULT_CARD.read_text(encoding="utf-8"))
    validation = set(load_tool("recipe-crops.py").levels_for_role(card, "validation"))
    assert validation and not validation & set(card["training"]["recipe"]["levels"]["held_out"])
