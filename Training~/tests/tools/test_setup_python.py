"""Tools~/setup-python.sh: never deletes a folder it did not create, and one setup at a time."""

from __future__ import annotations

import fcntl
import os
import signal
import subprocess
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[3] / "Tools~" / "setup-python.sh"


def _environment(tmp_path: Path, venv: Path) -> dict[str, str]:
    return {**os.environ, "LPNN_CACHE": str(tmp_path / "cache"), "LPNN_VENV": str(venv)}


def test_a_ready_environment_is_reused(tmp_path: Path) -> None:
    venv = tmp_path / "env"
    venv.mkdir()
    (venv / ".lpnn-ready").touch()
    done = subprocess.run(["bash", str(SCRIPT)], env=_environment(tmp_path, venv), capture_output=True, text=True,
                          timeout=60)
    assert (done.returncode, done.stdout.strip()) == (0, f"{venv}/bin/python")


def test_an_existing_folder_it_did_not_create_is_left_untouched(tmp_path: Path) -> None:
    venv = tmp_path / "users-own-env"
    venv.mkdir()
    (venv / "keep.txt").write_text("the user's")
    done = subprocess.run(["bash", str(SCRIPT)], env=_environment(tmp_path, venv), capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 1
    assert f"{venv} exists but was not created by this script" in done.stderr
    assert (venv / "keep.txt").read_text() == "the user's"


def test_a_second_setup_waits_for_the_first(tmp_path: Path) -> None:
    """While another setup holds the lock, a second one waits and creates nothing."""
    venv = tmp_path / "env"
    (tmp_path / "cache").mkdir()
    with open(tmp_path / "cache" / "setup-python.lock", "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        second = subprocess.Popen(["bash", str(SCRIPT)], env=_environment(tmp_path, venv), stderr=subprocess.PIPE,
                                  stdout=subprocess.DEVNULL, text=True, start_new_session=True)
        try:
            first_message = second.stderr.readline() if second.stderr else ""
            assert "waiting for another setup" in first_message
            assert not venv.exists()
        finally:
            os.killpg(second.pid, signal.SIGKILL)  # before the lock is released: it must not build a venv
            second.wait(timeout=30)
