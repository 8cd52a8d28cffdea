"""Tools~/golden/GoldenWriter.cs (run by Tools~/regenerate-golden.sh) still builds against the C# core and writes the
C#-side golden files exactly as committed in Tests/Data: the files its regeneration would rewrite stay reproducible
(make test builds the core before pytest; Mono and mcs are installed by Tools~/install-system.sh)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
BUILD = ROOT / "Build~"
WRITTEN = ["grid_golden.json", "features_golden.json", "capture_golden.lpnncap", "capture_golden.json"]


def test_the_golden_writer_builds_and_reproduces_the_committed_files(tmp_path: Path) -> None:
    references = [f"-r:{BUILD / name}" for name in ("Lpnn.Probes.Core.dll", "Lpnn.Probes.Core.Tests.dll",
                                                    "nunit.framework.dll")]
    exe = tmp_path / "GoldenWriter.exe"
    build = subprocess.run(["mcs", "-nologo", "-langversion:7.2", "-r:System.Numerics.dll",
                            "-r:System.Numerics.Vectors.dll", *references, f"-out:{exe}",
                            str(ROOT / "Tools~" / "golden" / "GoldenWriter.cs")], capture_output=True, text=True)
    assert build.returncode == 0, build.stdout + build.stderr
    out = tmp_path / "data"
    out.mkdir()
    run = subprocess.run(["mono", str(exe), str(out)], cwd=BUILD, capture_output=True, text=True, timeout=600,
                         env={**os.environ, "MONO_PATH": str(BUILD)})
    assert run.returncode == 0, run.stdout + run.stderr
    for name in WRITTEN:
        assert (out / name).read_bytes() == (ROOT / "Tests" / "Data" / name).read_bytes(), name
