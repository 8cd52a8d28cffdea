"""Tools~/summarize.py: the `N passed, N failed` line CI reads, from NUnit 2 and JUnit reports."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[3] / "Tools~" / "summarize.py"

# What NUnit 2.6 writes for 3 passed, 1 failed, 1 ignored, 1 inconclusive and 1 invalid test: its summary
# counts executed tests in `total` (inconclusive included) and ignored + invalid in `not-run`.
NUNIT2 = """<?xml version="1.0" encoding="utf-8"?>
<test-results name="x.dll" total="5" errors="0" failures="1" not-run="2" inconclusive="1" ignored="1"
              skipped="0" invalid="1">
  <test-suite type="Assembly" name="x.dll" executed="True" result="Failure" success="False"><results>
    <test-case name="A.One" executed="True" result="Success" success="True" />
    <test-case name="A.Two" executed="True" result="Success" success="True" />
    <test-case name="A.Three" executed="True" result="Success" success="True" />
    <test-case name="A.Broken" executed="True" result="Failure" success="False" />
    <test-case name="A.Later" executed="False" result="Ignored" />
    <test-case name="A.Unsure" executed="True" result="Inconclusive" />
    <test-case name="A.BadSignature" executed="False" result="NotRunnable" />
  </results></test-suite>
</test-results>
"""


def test_nunit2_counts_come_from_the_test_cases(tmp_path: Path) -> None:
    checks = tmp_path / "checks.txt"
    checks.write_text("pass build\n", encoding="utf-8")
    report = tmp_path / "nunit.xml"
    report.write_text(NUNIT2, encoding="utf-8")
    done = subprocess.run([sys.executable, str(SCRIPT), str(checks), str(report)], capture_output=True, text=True)
    assert "nunit.xml: 3 passed, 2 failed, 2 skipped" in done.stdout
    assert done.stdout.strip().splitlines()[-1] == "4 passed, 2 failed"
    assert done.returncode == 1
