"""Prints one line per test suite and, last, the `N passed, N failed` line CI reads.

Usage: summarize.py CHECKS_FILE [nunit.xml|junit.xml ...]
CHECKS_FILE holds lines `pass|fail <name>` for steps that are not test runners (builds, compile checks).
Standard library only: runs with the system python3 before any venv exists.
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from pathlib import Path


NUNIT2_FAILED = {"Failure", "Error", "NotRunnable", "Cancelled"}


def nunit2(root: ET.Element) -> tuple[int, int, int]:
    """Counted from the test cases themselves: the summary's `total` counts only executed tests (inconclusive
    ones among them) while `not-run` counts ignored and invalid ones too, so no sum of its attributes is right."""
    cases = list(root.iter("test-case"))
    passed = sum(1 for c in cases if c.get("executed") == "True" and c.get("result") == "Success")
    failed = sum(1 for c in cases if c.get("result") in NUNIT2_FAILED)
    return passed, failed, len(cases) - passed - failed  # skipped: ignored, skipped, inconclusive


def junit(root: ET.Element) -> tuple[int, int, int]:
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    tests = sum(int(s.get("tests", 0)) for s in suites)
    failed = sum(int(s.get("failures", 0)) + int(s.get("errors", 0)) for s in suites)
    skipped = sum(int(s.get("skipped", 0)) for s in suites)
    return tests - failed - skipped, failed, skipped


def main(argv: list[str]) -> int:
    passed = failed = skipped = 0
    for line in Path(argv[1]).read_text(encoding="utf-8").splitlines():
        if not line.strip():
            continue
        status, _, name = line.partition(" ")
        ok = status == "pass"
        passed += ok
        failed += not ok
        print(f"  {'ok  ' if ok else 'FAIL'} {name}")
    for report in argv[2:]:
        path = Path(report)
        if not path.is_file():
            print(f"  FAIL {path.name}: no report (the runner did not finish)")
            failed += 1
            continue
        root = ET.parse(path).getroot()
        p, f, s = nunit2(root) if root.tag == "test-results" else junit(root)
        print(f"  {path.name}: {p} passed, {f} failed, {s} skipped")
        passed, failed, skipped = passed + p, failed + f, skipped + s
    if skipped:
        print(f"  ({skipped} skipped)")
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
