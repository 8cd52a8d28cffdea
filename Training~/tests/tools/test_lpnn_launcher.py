"""Tools~/bin/lpnn runs the code of the checkout it belongs to, whichever checkout set up the shared Python environment
last: a second checkout (its own `lpnn` package, the same requirements.lock, so the same environment) is set up after
this one, and each launcher, called directly or through a symlink on the PATH, still runs its own checkout's code."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

from tools_support import REPO

STUB = "import sys\n\ndef main():\n    print('checkout B', __file__)\n    return 0\n\nif __name__ == '__main__':\n" \
       "    sys.exit(main())\n"


def _other_checkout(root: Path) -> Path:
    """A checkout with this one's tools and requirements.lock and an `lpnn` of its own that says where it is."""
    for tool in ("bin/lpnn", "lib.sh", "setup-python.sh"):
        (root / "Tools~" / tool).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / "Tools~" / tool, root / "Tools~" / tool)
    package = root / "Training~" / "lpnn" / "cli"
    package.mkdir(parents=True)
    shutil.copy2(REPO / "Training~" / "requirements.lock", root / "Training~" / "requirements.lock")
    (package.parent / "__init__.py").write_text("")
    (package / "__init__.py").write_text("")
    (package / "main.py").write_text(STUB)
    return root


def _run(command: list[str], path: Path | None = None) -> str:
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}  # as in a user's shell
    if path is not None:
        env["PATH"] = f"{path}:{env['PATH']}"
    done = subprocess.run(command, env=env, cwd="/", capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_each_checkouts_lpnn_runs_its_own_code(tmp_path: Path) -> None:
    other = _other_checkout(tmp_path / "clone")
    mine = REPO / "Tools~" / "bin" / "lpnn"
    assert "LPNN Probes:" in _run([str(mine), "--help"])
    python = _run(["bash", str(other / "Tools~" / "setup-python.sh")]).strip()  # the other checkout sets up last
    assert python == _run(["bash", str(REPO / "Tools~" / "setup-python.sh")]).strip()  # one shared environment
    assert _run([str(other / "Tools~" / "bin" / "lpnn")]).strip() == \
        f"checkout B {other / 'Training~' / 'lpnn' / 'cli' / 'main.py'}"
    mine_help = _run([str(mine), "--help"])
    assert "LPNN Probes:" in mine_help and "checkout B" not in mine_help
    # Through symlinks on the PATH (e.g. ~/.local/bin/lpnn): each still finds its own checkout.
    for name, target in (("mine", mine), ("other", other / "Tools~" / "bin" / "lpnn")):
        (tmp_path / name).mkdir()
        (tmp_path / name / "lpnn").symlink_to(target)
    assert "LPNN Probes:" in _run(["lpnn", "--help"], path=tmp_path / "mine")
    assert _run(["lpnn"], path=tmp_path / "other").startswith("checkout B ")


def test_the_shared_environment_holds_nothing_of_the_project() -> None:
    """What makes the launcher's choice the only one: no `lpnn` package or command installed in the environment."""
    python = Path(_run(["bash", str(REPO / "Tools~" / "setup-python.sh")]).strip())
    assert not (python.parent / "lpnn").exists()
    found = _run([str(python), "-c", "import importlib.util; print(importlib.util.find_spec('lpnn'))"])
    assert found.strip() == "None"
