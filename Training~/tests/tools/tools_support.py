"""Helpers of the Tools~/experiments script tests: load a script as a module, write a model card with a level split."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from types import ModuleType

EXPERIMENTS_DIR = Path(__file__).resolve().parents[3] / "Tools~" / "experiments"


def load_tool(script: str) -> ModuleType:
    """The script Tools~/experiments/<script> as a module (its file name has dashes, so it cannot be imported by name)."""
    spec = importlib.util.spec_from_file_location(script.removesuffix(".py").replace("-", "_"), EXPERIMENTS_DIR / script)
    assert spec is not None and spec.loader is not None, f"cannot load {EXPERIMENTS_DIR / script}"
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def card_with_held_out(tmp_path: Path, held_out: list[str]) -> Path:
    """A model card whose recipe holds out `held_out` (all the tools read of it)."""
    path = tmp_path / "card.json"
    path.write_text(json.dumps({"training": {"recipe": {"levels": {"held_out": held_out}}}}), encoding="utf-8")
    return path
