"""`lpnn dataset` info / validate / convert-legacy, and capture validation messages."""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from lpnn.cli.main import main
from lpnn.core.analytic_scene import AnalyticScene
from lpnn.core.capture import CaptureError
from lpnn.core.capture_encoder import encode_capture
from lpnn.core.capture_file import read_capture, validate_capture, write_capture


def thesis_files(folder: Path, points: int = 3) -> tuple[Path, Path]:
    block = "\n".join(" ".join(f"{0.25 * (n + 10 * line)}".replace(".", ",") for n in range(10)) for line in range(3))
    features = folder / "features.txt"
    features.write_text("30\n\n" + "\n\n".join(block for _ in range(points)) + "\n", encoding="utf-8")
    labels = folder / "comparisons.txt"
    labels.write_text("\n".join("True" if n % 2 else "False" for n in range(points)) + "\n", encoding="utf-8")
    return features, labels


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.glob("*.lpnncap"))}


def test_convert_info_validate_append_round_trip(tmp_path, capsys):
    features, labels = thesis_files(tmp_path)
    out = tmp_path / "dataset"
    assert main(["dataset", "convert-legacy", str(features), str(labels), "--out", str(out), "--scene", "office"]) == 0
    first = snapshot(out)
    assert list(first) == ["office.lpnncap"]
    capture = read_capture(out / "office.lpnncap")
    assert capture.point_count == 3 and capture.labels.tolist() == [0, 1, 0]

    # the same name again without --append: refused, nothing touched
    assert main(["dataset", "convert-legacy", str(features), str(labels), "--out", str(out), "--scene", "office"]) == 1
    assert "already exists" in capsys.readouterr().err
    assert snapshot(out) == first

    # --append adds office-2 beside it; the existing bytes are unchanged
    assert main(["dataset", "convert-legacy", str(features), "--out", str(out / "office.lpnncap"), "--append"]) == 0
    after = snapshot(out)
    assert list(after) == ["office-2.lpnncap", "office.lpnncap"] and after["office.lpnncap"] == first["office.lpnncap"]

    capsys.readouterr()
    assert main(["dataset", "info", str(out)]) == 0
    text = capsys.readouterr().out
    assert "points: 3   features: 30 (lpnn.thesis30)" in text and "labels: 1 positive of 3 (33.33 %)" in text
    assert "labels: none" in text and "legacy=True" in text
    assert "total: 2 captures, 6 points, 3 labelled, 1 positive (33.33 %)" in text

    assert main(["dataset", "validate", str(out)]) == 0
    assert "2 captures checked, 0 with problems" in capsys.readouterr().out
    assert snapshot(out) == after  # info and validate only read


def test_scene_names_become_safe_file_names(tmp_path, capsys):
    features, _ = thesis_files(tmp_path)
    out = tmp_path / "dataset"
    assert main(["dataset", "convert-legacy", str(features), "--out", str(out), "--scene", "Office/Day 1"]) == 0
    assert [p.name for p in out.iterdir()] == ["Office_Day_1.lpnncap"]
    assert read_capture(out / "Office_Day_1.lpnncap").source["scene"] == "Office/Day 1"


def test_convert_legacy_reports_format_errors(tmp_path, capsys):
    features, _ = thesis_files(tmp_path, points=2)
    labels = tmp_path / "three.txt"
    labels.write_text("True\nTrue\nFalse\n", encoding="utf-8")
    assert main(["dataset", "convert-legacy", str(features), str(labels), "--out", str(tmp_path / "x")]) == 1
    assert "3 labels, but" in capsys.readouterr().err and not (tmp_path / "x").exists()


def corrupt(path: Path, offset: int, payload: bytes) -> None:
    """Overwrite bytes and re-seal the CRC, so the content check (not the CRC) finds the problem."""
    data = bytearray(path.read_bytes())
    data[offset:offset + len(payload)] = payload
    struct.pack_into("<I", data, len(data) - 16, zlib.crc32(bytes(data[:-16])) & 0xFFFFFFFF)
    path.write_bytes(bytes(data))


def test_validate_names_file_record_and_field(tmp_path, capsys):
    capture = AnalyticScene.random(seed=3).capture()
    good = write_capture(tmp_path / "good.lpnncap", capture)
    data = good.read_bytes()
    (tmp_path / "truncated.lpnncap").write_bytes(data[:-100])
    (tmp_path / "zip.lpnncap").write_bytes(b"PK\x03\x04" + data[4:])
    nan_file = tmp_path / "nan.lpnncap"
    nan_file.write_bytes(data)
    header_length = struct.unpack_from("<I", data, 12)[0]
    n = capture.point_count
    sh_offset = 16 + header_length + (n * 12 + (-n * 12) % 8) * 2  # after ids and positions sections
    corrupt(nan_file, sh_offset + (17 * 27 + 11) * 4, struct.pack("<f", float("nan")))

    i, j, k = capture.ids[17]
    assert validate_capture(nan_file) == [f"{nan_file}: record 17 (id {i},{j},{k}): field 'sh[g,2]': NaN is not finite"]
    with pytest.raises(CaptureError, match=r"truncated.lpnncap: file is .* bytes but the header describes .* \(truncated\?\)"):
        read_capture(tmp_path / "truncated.lpnncap")
    with pytest.raises(CaptureError, match=r"zip.lpnncap: byte 0: not a capture"):
        read_capture(tmp_path / "zip.lpnncap")

    assert main(["dataset", "validate", str(tmp_path)]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert f"{good}: ok" in lines
    assert any(line.startswith(f"{nan_file}: record 17") for line in lines)
    assert any(line.startswith(f"{tmp_path / 'truncated.lpnncap'}: file is") for line in lines)
    assert any(line.startswith(f"{tmp_path / 'zip.lpnncap'}: byte 0") for line in lines)
    assert lines[-1] == "4 captures checked, 3 with problems"
    assert good.read_bytes() == data

    assert main(["dataset", "info", str(good), str(tmp_path / "zip.lpnncap")]) == 1
    assert "unreadable" in capsys.readouterr().out


def test_writing_is_deterministic(tmp_path):
    capture = AnalyticScene.random(seed=6).capture()
    assert encode_capture(capture) == encode_capture(AnalyticScene.random(seed=6).capture())
    assert np.array_equal(read_capture(write_capture(tmp_path / "a.lpnncap", capture)).sh, capture.sh)


def test_missing_paths_are_user_errors(tmp_path, capsys):
    assert main(["dataset", "info", str(tmp_path / "nothing")]) == 1
    assert "no such capture file or dataset folder" in capsys.readouterr().err
    assert main(["dataset", "validate", str(tmp_path)]) == 1
    assert "no .lpnncap files found" in capsys.readouterr().err


def test_atomic_writes_get_normal_file_permissions(tmp_path):
    import os
    import stat

    from lpnn.core.atomic import write_bytes_atomic

    old = os.umask(0o022)
    try:
        path = write_bytes_atomic(tmp_path / "model.card.json", b"{}")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
