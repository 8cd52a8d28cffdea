"""Which points of a capture are in use (Documentation~/in-use.md "What placement does with the mask"): every point of
a `band` or `reachable` capture, the `in_use` section's points of an `all` capture, none known for a capture written
before the rule existed. Reports show the error at these points, so the dilution by the air stays visible.
"""

from __future__ import annotations

import numpy as np

from .capture import Capture

IN_USE_SECTION = "in_use"  # uint8 [N]: 1 = in use by the report rule (source.in_use_report_rule)
FILTERED_RULES = ("band", "reachable")  # captures holding their in-use points only


def capture_rule(capture: Capture) -> str:
    """The capture's in-use rule; "all" for one imported before the rule existed."""
    return str(capture.source.get("in_use", "all"))


def in_use_points(capture: Capture) -> np.ndarray | None:
    """(N,) bool points in use, or None when the capture cannot say (an `all` capture without the section)."""
    if capture_rule(capture) in FILTERED_RULES:
        return np.ones(capture.point_count, dtype=bool)
    section = capture.extra_sections.get(IN_USE_SECTION)
    return None if section is None else np.asarray(section).reshape(-1) != 0


def in_use_label(capture: Capture) -> str:
    """Which points a report's "in use" figures are over, for its parenthesis: "reachable" or "band" for a capture that
    holds only them; for an `all` capture (every point placed) the count and rule of its section, e.g. "12,345 points by
    the reachable rule", so the air the placement also covered is not read as in use; "not recorded" without one."""
    rule = capture_rule(capture)
    if rule != "all":
        return rule
    mask = in_use_points(capture)
    if mask is None:
        return "not recorded"
    return f"{int(mask.sum()):,} points by the {capture.source.get('in_use_report_rule', '?')} rule"


def in_use_text(error: float) -> str:
    """An error at the points in use as reports print it: 4 decimals, "n/a" when not known."""
    return "n/a" if error != error else f"{error:.4f}"  # NaN: the capture cannot say which points are in use
