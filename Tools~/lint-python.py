"""Lints the trainer package with ruff (step of `make test`): ordinary checks, then the layer rules.

    python Tools~/lint-python.py [--root DIR]   (the venv's python: ruff is pinned in Training~/requirements.lock;
                                                 DIR holds `lpnn/` and `tests/`, default Training~)

Ordinary checks: the `[tool.ruff]` rules of Training~/pyproject.toml on the package and its tests.
Layers (Documentation~/training.md "Package layout"): each subpackage of `lpnn` may import only the
layers listed before it, never one after it, and TensorFlow (with keras and tf2onnx) only inside
`lpnn.train`. Ruff's banned-api rule (TID251) enforces both, relative imports included: this script
runs it once per layer with that layer's banned modules, so the order below is the one place the
rule is written.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

TRAINING = Path(__file__).resolve().parent.parent / "Training~"

# Lowest first. `lpnn/errors.py` sits below them all (a leaf: it imports nothing of the package).
LAYERS = ("core", "scenes", "quality", "lights", "train", "recipe", "demo", "cli")
TENSORFLOW = ("tensorflow", "keras", "tf2onnx")
TENSORFLOW_LAYER = "train"


def banned_modules(layer: str | None) -> dict[str, str]:
    """Module -> reason, for the files of `layer` (None: the package's top-level modules such as errors.py)."""
    above = LAYERS if layer is None else LAYERS[LAYERS.index(layer) + 1:]
    where = "lpnn's top-level modules" if layer is None else f"lpnn.{layer}"
    banned = {f"lpnn.{upper}": f"{where} must not import lpnn.{upper}, a layer above it "
                               f"(layers, lowest first: {', '.join(LAYERS)}; Tools~/lint-python.py)"
              for upper in above}
    if layer != TENSORFLOW_LAYER:
        banned.update({module: f"TensorFlow is imported only inside lpnn.{TENSORFLOW_LAYER}; call its functions instead"
                       for module in TENSORFLOW})
    return banned


def ruff(root: Path, paths: list[Path], *options: str) -> int:
    command = [sys.executable, "-m", "ruff", "check", "--no-cache", "--output-format", "concise", *options,
               *(str(p) for p in paths if p.exists())]
    return subprocess.run(command, cwd=root).returncode


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=TRAINING, help="folder holding lpnn/ and tests/ (default Training~)")
    root = parser.parse_args(argv).root.resolve()
    package = root / "lpnn"
    if not package.is_dir():
        print(f"lint-python: {package} is not a folder; pass --root the folder that holds lpnn/")
        return 2
    # The rules of Training~/pyproject.toml whichever tree is linted (the tests lint small trees of their own).
    failed = ruff(root, [package, root / "tests"], "--config", str(TRAINING / "pyproject.toml")) != 0
    top_level = sorted(package.glob("*.py"))
    for layer, paths in [(None, top_level)] + [(name, [package / name]) for name in LAYERS]:
        table = ", ".join(f"{json.dumps(module)}.msg = {json.dumps(reason)}"
                          for module, reason in banned_modules(layer).items())
        if not any(p.exists() for p in paths):
            continue
        failed |= ruff(root, paths, "--quiet", "--select", "TID251", "--config",
                       f"lint.flake8-tidy-imports.banned-api = {{{table}}}") != 0
    present = sorted(p.name for p in package.iterdir() if p.is_dir() and (p / "__init__.py").exists())
    unlisted = sorted(set(present) - set(LAYERS))
    if unlisted:
        print(f"lint-python: subpackages {unlisted} have no layer: add them to LAYERS in Tools~/lint-python.py")
        failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
