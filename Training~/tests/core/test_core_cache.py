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


def test_numba_worker_threads_sleep_between_loops_unless_the_user_chose_a_policy() -> None:
    """parallel_wait.py: the kernels' import sets OMP_WAIT_POLICY before numba's thread pool (OpenMP) starts, and a
    parallel kernel then runs under it; a policy already in the environment is left as it is."""
    code = ("import os\nfrom lpnn.quality.metric import metric_kernel\nimport numba\n"
            "print('POLICY', os.environ.get('OMP_WAIT_POLICY'))\n"
            "import numpy as np\nhit = np.empty(3, dtype=bool)\nwhich = np.empty(3, dtype=np.int64)\n"
            "metric_kernel.run_rows(__import__('lpnn.quality.placement.refinement_kernel', fromlist=['_holding'])._holding,"
            " 3, np.full((3, 4), -1), np.array([True, False, False]), hit, which)\nprint('HIT', hit.tolist())\n")
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    done = _run(code, env)
    assert done.returncode == 0, done.stderr
    assert "POLICY PASSIVE" in done.stdout and "HIT [True, False, False]" in done.stdout
    done = _run(code, {**env, "OMP_WAIT_POLICY": "ACTIVE"})
    assert done.returncode == 0, done.stderr
    assert "POLICY ACTIVE" in done.stdout
