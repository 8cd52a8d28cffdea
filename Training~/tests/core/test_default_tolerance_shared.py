"""The default tolerance and policy an artist gets are one story across languages (issue 17 item 17): the Unity volume's
defaults come from Core's SelectionSettings, whose value must equal the CLI's DEFAULT_TOLERANCE."""

from __future__ import annotations

import re
from pathlib import Path

from lpnn.quality.placement.policy_rules import DEFAULT_TOLERANCE

PACKAGE = Path(__file__).resolve().parents[3] / "Packages" / "com.lpnn.probes" / "Runtime"


def test_core_default_tolerance_equals_the_cli_default() -> None:
    source = (PACKAGE / "Core" / "Selection" / "SelectionSettings.cs").read_text(encoding="utf-8")
    match = re.search(r"public const double DefaultTolerance = ([0-9.]+);", source)
    assert match, "SelectionSettings.DefaultTolerance not found"
    assert float(match.group(1)) == DEFAULT_TOLERANCE
    assert "public const SelectionPolicy DefaultPolicy = SelectionPolicy.Tolerance;" in source


def test_unity_volume_takes_its_defaults_from_core() -> None:
    source = (PACKAGE / "LpnnVolume.cs").read_text(encoding="utf-8")
    assert "private SelectionPolicy policy = SelectionSettings.DefaultPolicy;" in source
    assert "private float tolerance = (float)SelectionSettings.DefaultTolerance;" in source


def test_the_default_placement_is_insertion_refined_in_batches_in_the_volume_and_the_cli() -> None:
    """benchmarks.md "The speed/accuracy trade, every method": with the dense lighting (always there in the Unity pipeline and in a capture) insertion refined
    in batches is the best method measured on the validation crops (the network's guide ties once refined), so a new
    volume places by insertion and refines on Apply, and `lpnn place` without --method does the same (one method,
    InsertionRefined / insertion-refined: Documentation~/methods.md)."""
    from lpnn.quality.placement.methods import DEFAULT_METHOD

    core = (PACKAGE / "Core" / "Selection" / "PlacementMethod.cs").read_text(encoding="utf-8")
    assert "public const PlacementMethod Default = PlacementMethod.InsertionRefined;" in core
    assert DEFAULT_METHOD == "insertion-refined"
    volume = (PACKAGE / "LpnnVolume.cs").read_text(encoding="utf-8")
    assert "refineInBatches" not in volume  # the refinement is part of the method, not a separate toggle
    assert "private PlacementMethod placementMethod = PlacementMethods.Default;" in volume
