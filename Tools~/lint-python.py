"""Lints the trainer package with ruff (step of `make test`): ordinary checks, then the layer rules.

    python Tools~/lint-python.py [--root DIR]   (the venv's python: ruff is pinned in Training~/requirements.lock;
                                                 DIR holds `lpnn/` and `tests/`, default Training~)

Ordinary checks: the `[tool.ruff]` rules of Training~/pyproject.toml on the package and its tests.
Layers (Documentation~/training.md "Package layout"): each subpackage of `lpnn` may import only the
layers listed before it, never one after it, and TensorFlow (with keras and tf2onnx) only inside
`lpnn.train`. Ruff's banned-api rule (TID251) enforces both, relative imports included: this script
runs it once per layer with that layer's banned modules, so the order below is the one place the
rule is written. A layer may be split further (SUBLAYERS): its subpackages, lowest first, may import only the ones
before them (a nested subpackage listed before its parent may import none of the parent's other modules). Within a
layer, modules may not import each other in a cycle (imports inside functions included): the shared piece belongs in
a module both import. The cycle check reads the imports with `ast`.
"""

from __future__ import annotations

import argparse
import ast
import json
import subprocess
import sys
from pathlib import Path

TRAINING = Path(__file__).resolve().parent.parent / "Training~"

# Lowest first. `lpnn/errors.py` sits below them all (a leaf: it imports nothing of the package).
LAYERS = ("core", "scenes", "quality", "lights", "train", "recipe", "demo", "cli")
# Within a layer, lowest first (paths under lpnn/LAYER, dotted): Documentation~/training.md "The Python package".
SUBLAYERS = {"quality": ("metric", "placement.decimation", "placement", "bench")}
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


def banned_sublayer_modules(package: Path, layer: str, sublayer: str) -> dict[str, str]:
    """Module -> reason, for the files of lpnn.LAYER.SUBLAYER: the sublayers after it, and for a parent listed after
    it (`placement` after `placement.decimation`) the parent's other modules and subpackages."""
    order = SUBLAYERS[layer]
    rule = f"sublayers of lpnn.{layer}, lowest first: {', '.join(order)}; Tools~/lint-python.py"
    banned = {}
    for upper in order[order.index(sublayer) + 1:]:
        if not sublayer.startswith(upper + "."):
            banned[f"lpnn.{layer}.{upper}"] = f"lpnn.{layer}.{sublayer} must not import lpnn.{layer}.{upper} ({rule})"
            continue
        folder = package / layer / upper.replace(".", "/")
        own = sublayer[len(upper) + 1:].split(".")[0]
        for child in sorted(folder.iterdir()):
            name = child.stem if child.suffix == ".py" else child.name
            if name in ("__init__", own) or not (child.suffix == ".py" or (child / "__init__.py").exists()):
                continue
            banned[f"lpnn.{layer}.{upper}.{name}"] = (f"lpnn.{layer}.{sublayer} must not import lpnn.{layer}.{upper}'s "
                                                      f"other modules ({rule})")
    return banned


def unlisted_sublayers(package: Path) -> list[str]:
    """Subpackages (dotted, any depth) of a layer with SUBLAYERS that are neither listed nor a listed one's parent."""
    unlisted = []
    for layer, order in SUBLAYERS.items():
        folder = package / layer
        allowed = {".".join(s.split(".")[:i]) for s in order for i in range(1, s.count(".") + 2)}
        for init in sorted(folder.rglob("__init__.py")) if folder.is_dir() else []:
            name = ".".join(init.parent.relative_to(folder).parts)
            if name and name not in allowed:
                unlisted.append(f"{layer}.{name}")
    return unlisted


def module_imports(package: Path) -> dict[str, set[str]]:
    """Module -> the package's modules it imports anywhere in its file (`lpnn.a.b`; a package is its __init__)."""
    modules: dict[str, Path] = {}
    for path in package.rglob("*.py"):
        parts = path.relative_to(package.parent).with_suffix("").parts
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        here = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        imported: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            if isinstance(node, ast.Import):
                imported.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = ".".join(here[:len(here) - node.level + 1] + [node.module or ""]).strip(".") if node.level \
                    else node.module or ""
                # `from pkg import mod` imports the module pkg.mod; `from mod import name` the module mod
                imported.update(f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base
                                for alias in node.names)
        graph[name] = {m for m in imported if m in modules and m != name}
    return graph


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    cycles: list[list[str]] = []

    def visit(module: str) -> None:
        index[module] = low[module] = len(index)
        stack.append(module)
        for other in sorted(graph[module]):
            if other not in index:
                visit(other)
                low[module] = min(low[module], low[other])
            elif other in stack:
                low[module] = min(low[module], index[other])
        if low[module] == index[module]:
            component = []
            while not component or component[-1] != module:
                component.append(stack.pop())
            if len(component) > 1:
                cycles.append(sorted(component))

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return sorted(cycles)


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
    for layer, order in SUBLAYERS.items():
        for sublayer in order:
            folder = package / layer / sublayer.replace(".", "/")
            if not folder.is_dir():
                continue
            table = ", ".join(f"{json.dumps(module)}.msg = {json.dumps(reason)}"
                              for module, reason in banned_sublayer_modules(package, layer, sublayer).items())
            failed |= ruff(root, [folder], "--quiet", "--select", "TID251", "--config",
                           f"lint.flake8-tidy-imports.banned-api = {{{table}}}") != 0
    for cycle in import_cycles(module_imports(package)):
        print(f"lint-python: modules import each other in a cycle: {', '.join(cycle)} "
              "(move what they share into a module both import)")
        failed = True
    present = sorted(p.name for p in package.iterdir() if p.is_dir() and (p / "__init__.py").exists())
    unlisted = sorted(set(present) - set(LAYERS))
    if unlisted:
        print(f"lint-python: subpackages {unlisted} have no layer: add them to LAYERS in Tools~/lint-python.py")
        failed = True
    unlisted_inner = unlisted_sublayers(package)
    if unlisted_inner:
        print(f"lint-python: subpackages {unlisted_inner} have no sublayer: add them to SUBLAYERS in Tools~/lint-python.py")
        failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
