"""The layer and import-cycle rules of Tools~/lint-python.py catch what they forbid (the real tree is linted by
`make test`)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

LINT = Path(__file__).resolve().parents[3] / "Tools~" / "lint-python.py"
LAYERS = ("core", "scenes", "quality", "lights", "train", "recipe", "demo", "cli")


def lint(tmp_path: Path, files: dict[str, str]) -> subprocess.CompletedProcess[str]:
    """Lints a tree with every layer present and `files` (path under lpnn/ -> source) added."""
    (tmp_path / "lpnn").mkdir()
    (tmp_path / "lpnn" / "__init__.py").write_text("")
    for layer in LAYERS:
        (tmp_path / "lpnn" / layer).mkdir()
        (tmp_path / "lpnn" / layer / "__init__.py").write_text("")
    for name, source in files.items():
        path = tmp_path / "lpnn" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        (path.parent / "__init__.py").touch()
        path.write_text(source)
    return subprocess.run([sys.executable, str(LINT), "--root", str(tmp_path)], capture_output=True, text=True)


def test_downward_imports_and_tensorflow_inside_train_pass(tmp_path: Path) -> None:
    result = lint(tmp_path, {
        "errors.py": "class LpnnError(Exception):\n    pass\n",
        "quality/a.py": "from ..core import grid\nfrom ..errors import LpnnError\nimport lpnn.scenes\n"
                        "print(grid, LpnnError, lpnn)\n",
        "train/b.py": "import tensorflow as tf\nfrom ..quality import a\nprint(tf, a)\n",
        "cli/c.py": "from ..train import b\nfrom .. import recipe\nprint(b, recipe)\n",
    })
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize("name, source, banned", [
    ("core/a.py", "from ..cli.errors import UserError\nprint(UserError)\n", "lpnn.cli"),
    ("quality/a.py", "import lpnn.train.metrics\nprint(lpnn)\n", "lpnn.train"),
    ("scenes/deep/a.py", "from ...quality import metric\nprint(metric)\n", "lpnn.quality"),
    ("errors.py", "from .core import grid\nprint(grid)\n", "lpnn.core"),
    ("recipe/a.py", "import tensorflow\nprint(tensorflow)\n", "tensorflow"),
    ("cli/a.py", "from tf2onnx import convert\nprint(convert)\n", "tf2onnx"),
])
def test_an_upward_import_or_tensorflow_outside_train_fails(tmp_path: Path, name: str, source: str,
                                                            banned: str) -> None:
    result = lint(tmp_path, {name: source})
    assert result.returncode == 1
    assert f"`{banned}` is banned" in result.stdout


def test_a_subpackage_without_a_layer_fails(tmp_path: Path) -> None:
    result = lint(tmp_path, {"plugins/a.py": "x = 1\n"})
    assert result.returncode == 1
    assert "['plugins'] have no layer" in result.stdout


def test_modules_importing_each_other_fail_even_inside_functions(tmp_path: Path) -> None:
    result = lint(tmp_path, {
        "cli/scene_cmd.py": "LEVEL_HELP = 'a level'\n\ndef register():\n    from .lights_cmd import run\n    run()\n",
        "cli/lights_cmd.py": "from .scene_cmd import LEVEL_HELP\n\ndef run():\n    print(LEVEL_HELP)\n",
        "cli/other.py": "from . import scene_cmd\nprint(scene_cmd)\n",  # importing one of them is no cycle
    })
    assert result.returncode == 1
    assert "modules import each other in a cycle: lpnn.cli.lights_cmd, lpnn.cli.scene_cmd (" in result.stdout


def test_a_longer_cycle_across_packages_fails(tmp_path: Path) -> None:
    result = lint(tmp_path, {
        "core/a.py": "from . import b\nprint(b)\n",
        "core/b.py": "import lpnn.core.sub.c\nprint(lpnn)\n",
        "core/sub/c.py": "from ..a import x\nprint(x)\n",
    })
    assert result.returncode == 1
    assert "cycle: lpnn.core.a, lpnn.core.b, lpnn.core.sub.c (" in result.stdout


@pytest.mark.parametrize("name, source, banned", [
    ("quality/metric/a.py", "from ..placement.insertion import x\nprint(x)\n", "lpnn.quality.placement"),
    ("quality/metric/a.py", "import lpnn.quality.bench.run\nprint(lpnn)\n", "lpnn.quality.bench"),
    ("quality/placement/a.py", "from ..bench import run\nprint(run)\n", "lpnn.quality.bench"),
    ("quality/placement/decimation/a.py", "from ..insertion import x\nprint(x)\n", "lpnn.quality.placement.insertion"),
])
def test_an_upward_import_between_sublayers_fails(tmp_path: Path, name: str, source: str, banned: str) -> None:
    result = lint(tmp_path, {name: source, "quality/placement/insertion.py": "x = 1\n", "quality/bench/run.py": "y = 2\n"})
    assert result.returncode == 1
    assert f"`{banned}` is banned" in result.stdout


def test_downward_imports_between_sublayers_pass(tmp_path: Path) -> None:
    result = lint(tmp_path, {
        "quality/metric/metric.py": "E = 1\n",
        "quality/placement/decimation/fast.py": "from ...metric.metric import E\nprint(E)\n",
        "quality/placement/insertion.py": "from ..metric import metric\nfrom .decimation.fast import E\nprint(metric, E)\n",
        "quality/bench/run.py": "from ..placement import insertion\nfrom ..metric.metric import E\nprint(insertion, E)\n",
    })
    assert result.returncode == 0, result.stdout + result.stderr


def test_a_quality_subpackage_without_a_sublayer_fails(tmp_path: Path) -> None:
    result = lint(tmp_path, {"quality/extras/a.py": "x = 1\n"})
    assert result.returncode == 1
    assert "['quality.extras'] have no sublayer" in result.stdout
