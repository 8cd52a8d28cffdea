"""The quality package at its limits: refused with a message naming the limit, never a traceback."""

from __future__ import annotations

from pathlib import Path

import pytest

from lpnn.cli.main import main


def test_too_many_candidates_for_the_fast_reference_is_a_user_error(
        capture_files: list[Path], monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import lpnn.quality.placement.decimation.decimation_mesh as decimation_mesh

    monkeypatch.setattr(decimation_mesh, "VERTEX_KEY_BITS", 4)  # the real limit, 2^21 points, scaled down
    assert main(["label", str(capture_files[0]), "--budget", "0.2", "--method", "fast", "--in-place", "--quiet"]) == 1
    assert "handles fewer than 16 candidates" in capsys.readouterr().err
