"""`lpnn place`'s progress bars name what they count: insertion counts rounds (one per callback, in rounds per second
or seconds per round, with the points ranked beside it), the references and batched refinement count probes."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from lpnn.cli.main import main


@pytest.mark.parametrize("method", ["insertion", "insertion-refined"])
def test_insertion_counts_rounds(capture_files: list[Path], tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                 method: str) -> None:
    assert main(["place", str(capture_files[1]), "--method", method, "--tolerance", "0.05",
                 "--out", str(tmp_path / "p.probes.json")]) == 0
    states = re.findall(r"insertion: (\d+)round \[[^\]]*?(round/s|s/round), ([\d,]+) of ([\d,]+) points ranked\]",
                        capsys.readouterr().err.replace("\r", "\n"))
    assert len(states) >= 2, "no rounds shown"
    rounds = [int(s[0]) for s in states]
    assert rounds == list(range(1, len(rounds) + 1))  # one per round, counted as rounds
    assert all(int(s[2].replace(",", "")) <= int(s[3].replace(",", "")) for s in states)


def test_the_fast_reference_counts_probes(capture_files: list[Path], tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["place", str(capture_files[1]), "--method", "fast-reference", "--budget", "0.2",
                 "--out", str(tmp_path / "p.probes.json")]) == 0
    assert re.search(r"fast reference: .*probe/s", capsys.readouterr().err)
