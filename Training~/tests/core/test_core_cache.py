"""numba's compiled functions are cached in the project's cache folder, never beside the sources; the CLI
starts without importing the numerical libraries."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

TRAINING = Path(__file__).resolve().parents[2]


def _run(code: str, env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], env={**env, "PYTHONPATH": str(TRAINING)},
                          capture_output=True, text=True, timeout=300)


def test_numba_caches_in_the_project_cache_folder(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["LPNN_CACHE"] = str(tmp_path)
    done = _run("from lpnn.quality.placement.decimation.hole_wrap import _sorted3; _sorted3(3, 1, 2)", env)
    assert done.returncode == 0, done.stderr
    assert list((tmp_path / "numba").rglob("*hole_wrap._sorted3*.nbi")), "numba wrote no cache into LPNN_CACHE/numba"


def test_cli_help_imports_no_numerical_library() -> None:
    code = ("import sys\nfrom lpnn.cli.main import main\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
            "heavy = {'scipy', 'numba', 'tensorflow', 'onnxruntime', 'sklearn'} & {m.split('.')[0] for m in sys.modules}\n"
            "print('HEAVY', sorted(heavy))")
    done = _run(code, dict(os.environ))
    assert done.returncode == 0, done.stderr
    assert "HEAVY []" in done.stdout
