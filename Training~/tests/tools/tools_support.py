"""Helpers of the Tools~/experiments script tests: load a script as a module, write a model card with a level split."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path
from types import ModuleType

REPO = Path(__file__).resolve().parents[3]
EXPERIMENTS_DIR = REPO / "Tools~" / "experiments"


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


def run_experiment(script: str, *arguments: str, env: dict[str, str] | None = None,
                   timeout: float = 600) -> subprocess.CompletedProcess[str]:
    """Runs Tools~/experiments/<script> as the docs do (`bash` for .sh, this Python with Training~ on the path for .py)
    from the repository root, with `env` added to the environment; fails the test on a non-zero exit code."""
    path = EXPERIMENTS_DIR / script
    command = ["bash", str(path)] if script.endswith(".sh") else [sys.executable, str(path)]
    environment = {**os.environ, "PYTHONPATH": str(REPO / "Training~"), **(env or {})}
    result = subprocess.run([*command, *arguments], cwd=REPO, env=environment, capture_output=True, text=True,
                            timeout=timeout)
    assert result.returncode == 0, f"{script} exited with {result.returncode}:\n{result.stdout}\n{result.stderr}"
    return result
