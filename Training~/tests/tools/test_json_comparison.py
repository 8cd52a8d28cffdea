"""Tools~/experiments/json-comparison/run.sh (file-formats.md "JSON in C#") builds and prints its three findings: the
golden numbers read alike, what Json.NET accepts that the contracts forbid, and the capture header byte for byte.
Mono and Json.NET are installed by Tools~/install-system.sh for make test."""

from __future__ import annotations

import re

from tools_support import run_experiment


def test_the_three_findings() -> None:
    out = run_experiment("json-comparison/run.sh").stdout
    numbers = re.findall(r"^(en-US|de-DE) \S+\.json: (\d+) numbers \((\d+) Json.NET\), read differently (\d+)", out, re.M)
    assert {culture for culture, *_ in numbers} == {"en-US", "de-DE"}
    assert all(ours == theirs and different == "0" for _, ours, theirs, different in numbers)
    assert re.search(r"^\{\"a\": NaN\} +ours: refused +Json.NET: ACCEPTED", out, re.M), out
    assert "our writer reproduces it: True" in out
