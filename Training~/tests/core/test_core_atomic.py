"""Atomic writes on a bad day: an output path that cannot be written says which and why, and leaves nothing."""

from __future__ import annotations

import errno
from pathlib import Path

import pytest

from lpnn.cli.main import main
from lpnn.core import atomic
from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.atomic import OutputPathError, ensure_folder, write_bytes_atomic, write_new_atomic
from lpnn.core.capture_file import write_capture


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob("*.tmp"))


@pytest.fixture()
def capture_file(tmp_path: Path) -> Path:
    return write_capture(tmp_path / "room.lpnncap", AnalyticScene.random(seed=3).capture())


def test_an_existing_folder_as_output_is_refused_by_name(tmp_path: Path) -> None:
    (tmp_path / "out.json").mkdir()
    with pytest.raises(OutputPathError, match=r"out\.json is a folder: give a file path"):
        write_bytes_atomic(tmp_path / "out.json", b"{}")
    assert _leftovers(tmp_path) == []


def test_a_path_under_a_regular_file_names_the_file(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("x")
    with pytest.raises(OutputPathError, match=r"notes\.txt is a file, not a folder"):
        write_bytes_atomic(tmp_path / "notes.txt" / "deeper" / "out.json", b"{}")
    with pytest.raises(OutputPathError, match=r"notes\.txt is a file, not a folder"):
        ensure_folder(tmp_path / "notes.txt")


def test_no_permission_names_the_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Simulated: the tests may run as root, which ignores a read-only folder's mode bits.
    def refuse(*args: object, **kwargs: object) -> None:
        raise PermissionError(errno.EACCES, "Permission denied")
    monkeypatch.setattr(atomic.tempfile, "mkstemp", refuse)
    with pytest.raises(OutputPathError, match=f"no permission to write in {tmp_path}"):
        write_bytes_atomic(tmp_path / "out.json", b"{}")


def test_a_full_disk_keeps_the_old_file_and_leaves_no_temporary(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "out.json"
    target.write_bytes(b"old")

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")
    monkeypatch.setattr(atomic.os, "fsync", full)
    with pytest.raises(OutputPathError, match="No space left on device; free some space"):
        write_bytes_atomic(target, b"new")
    assert target.read_bytes() == b"old"
    assert _leftovers(tmp_path) == []


def test_a_failed_rename_leaves_no_temporary(tmp_path: Path) -> None:
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "inside").write_text("x")  # a non-empty folder: rename over it fails everywhere
    with pytest.raises(OutputPathError):
        write_bytes_atomic(tmp_path / "taken", b"new")
    assert _leftovers(tmp_path) == []


def test_write_new_without_hard_links_still_never_replaces(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def no_links(src: object, dst: object) -> None:
        raise OSError(errno.EPERM, "Operation not permitted")
    monkeypatch.setattr(atomic.os, "link", no_links)
    target = tmp_path / "a.bin"
    assert write_new_atomic(target, lambda handle: handle.write(b"first"))
    assert not write_new_atomic(target, lambda handle: handle.write(b"second"))
    assert target.read_bytes() == b"first"
    assert _leftovers(tmp_path) == []


@pytest.mark.parametrize("make_bad_output", [
    lambda root: (root / "probes.json").mkdir() or root / "probes.json",
    lambda root: (root / "file").write_text("x") and root / "file" / "probes.json",
])
def test_the_cli_says_which_path_and_exits_non_zero(tmp_path: Path, capture_file: Path, make_bad_output,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    out = make_bad_output(tmp_path)
    assert main(["place", str(capture_file), "--method", "uniform", "--budget", "0.25", "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("lpnn place: error: ") and "Traceback" not in err
    assert ("probes.json is a folder" in err) or (f"{tmp_path / 'file'} is a file" in err)
    assert _leftovers(tmp_path) == []


def test_the_cli_reports_an_unanticipated_file_system_error_without_traceback(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import argparse

    import lpnn.cli.main as cli_main

    def failing(args: argparse.Namespace) -> None:
        raise NotADirectoryError(errno.ENOTDIR, "Not a directory", str(tmp_path / "file" / "bench"))
    parser = argparse.ArgumentParser(prog="lpnn")
    parser.set_defaults(command="bench", handler=failing)
    monkeypatch.setattr(cli_main, "build_parser", lambda: parser)
    assert cli_main.main([]) == 1
    err = capsys.readouterr().err
    assert err == (f"lpnn bench: error: Not a directory ({tmp_path / 'file' / 'bench'}); "
                   "check the path and its permissions\n")
