"""Tools~/experiments/README.md lists every driver with the doc section it reproduces, and each has a smoke test: a test
under Training~/tests that names it and runs in make test."""

from __future__ import annotations

import re

from tools_support import EXPERIMENTS_DIR, REPO

TESTS = REPO / "Training~" / "tests"


def _drivers() -> list[str]:
    top = [p.name for p in EXPERIMENTS_DIR.iterdir() if p.is_file() and p.suffix in (".py", ".sh")]
    return sorted(top + [f"{p.parent.name}/{p.name}" for p in EXPERIMENTS_DIR.glob("*/run.sh")])


def test_every_driver_is_listed_with_a_doc_and_a_smoke_test() -> None:
    readme = (EXPERIMENTS_DIR / "README.md").read_text(encoding="utf-8")
    rows = {m.group(1): (m.group(2), m.group(3)) for m in re.finditer(r"^\| `([^`]+)`[^|]* \| (.+) \| (.+) \|$", readme,
                                                                      re.M)}
    drivers = _drivers()
    assert len(drivers) >= 16  # the folder was found and read
    assert sorted(rows) == drivers
    for driver, (reproduces, smoke) in rows.items():
        assert re.search(r"\.md`? §|\.md` \"|\.md` \"|`[a-z-]+\.md`", reproduces), f"{driver}: no doc section"
        tests = re.findall(r"`([a-z]+/test_[a-z_]+\.py)`", smoke)
        assert tests, f"{driver}: no smoke test named"
        for test in tests:
            path = TESTS / test
            assert path.is_file(), f"{driver}: {test} does not exist"
            assert driver.split("/")[0] in path.read_text(encoding="utf-8"), f"{test} does not run {driver}"


def test_tools_keeps_no_experiment_driver() -> None:
    """Tools~ itself holds what make test and make demo run; the drivers of measured figures live in experiments/."""
    experiments = {name.split("/")[0] for name in _drivers()}
    assert not experiments & {p.name for p in (REPO / "Tools~").iterdir()}
