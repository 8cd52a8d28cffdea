"""The table of placement methods (quality/placement/methods.py) against the hand-written Tests/Data/placement_methods.json,
which the C# table (PlacementMethods, Tests/Core/PlacementMethodsTests.cs) and Documentation~/methods.md are pinned to too:
any drift in a name, label, need of a model, placeability or language fails here."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from lpnn.quality.placement.methods import (BATCHED, BENCH_METHODS, BY_NAME, DEFAULT_METHOD, EXACT, METHODS, PLACEABLE,
                                            RECOMMENDED_REFINE, SCORED, placement_method)

REPO_ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def table(golden) -> dict:
    return golden("placement_methods.json")


def test_the_python_table_is_the_golden_one_row_for_row(table):
    rows = [{"name": m.name, "label": m.label, "needs_model": m.needs_scores, "placeable": m.placeable,
             "languages": list(m.languages)} for m in METHODS]
    assert rows == table["methods"]
    assert DEFAULT_METHOD == table["default"]


def test_names_are_unique_and_the_default_is_placeable_without_a_model():
    assert len(BY_NAME) == len(METHODS)
    assert DEFAULT_METHOD in PLACEABLE and not BY_NAME[DEFAULT_METHOD].needs_scores


def test_each_method_that_reads_the_scores_runs_the_lpnn_placement_it_always_ran():
    # The old flags of `lpnn place --model M` each tier replaces (issue 34): the same keyword arguments, so the same probes.
    assert {name: BY_NAME[name].lpnn_options() for name in SCORED} == {
        "guided-refined": {"refine": RECOMMENDED_REFINE, "batched": True},  # --refine 2 --batched
        "guided": {"guided": True, "topk": False},  # --guided
        "network": {"guided": False, "topk": False},  # --model alone
        "network-topk": {"guided": False, "topk": True},  # --topk
        "guided-exact-refined": {"refine": RECOMMENDED_REFINE, "batched": False},  # --refine 2
    }
    assert BY_NAME["guided-exact-refined"].lpnn_options(3.0)["refine"] == 3.0  # the Python API keeps any factor
    assert RECOMMENDED_REFINE == 2.0
    assert {m.refinement for m in METHODS} == {None, EXACT, BATCHED}


def test_a_method_without_scores_has_no_lpnn_options():
    with pytest.raises(ValueError, match="insertion-refined does not read the network's scores"):
        BY_NAME["insertion-refined"].lpnn_options()


def test_an_unknown_name_lists_the_known_ones():
    with pytest.raises(KeyError, match="unknown placement method 'lpnn-batched'; the methods are insertion-refined, "):
        placement_method("lpnn-batched")


def test_bench_can_name_every_method_but_the_yardsticks_that_always_run():
    assert set(BENCH_METHODS) == set(BY_NAME) - {"fast-reference", "blockwise-reference"}
    assert [name for name in BY_NAME if not BY_NAME[name].placeable] == ["faithful-reference", "blockwise-reference"]


def test_the_documented_table_lists_the_golden_rows(table):
    """Documentation~/methods.md's table: one row per method, its name, label, model need and languages as pinned."""
    text = (REPO_ROOT / "Documentation~" / "methods.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `([a-z-]+)` \| ([^|]+?) \| [^|]+ \| (yes|no) \| ([^|]+?) \|", text, flags=re.MULTILINE)
    documented = [{"name": name, "label": label, "needs_model": model == "yes",
                   "languages": [language.strip() for language in languages.split(",")]}
                  for name, label, model, languages in rows]
    assert documented == [{key: row[key] for key in ("name", "label", "needs_model", "languages")}
                          for row in table["methods"]]
