"""The in-use rule's names and defaults (Documentation~/in-use.md "Parameters"), importable without numpy so the
CLI's --help can print them; lpnn.core.in_use validates and applies them."""

RULES = ("reachable", "band", "all")
# benchmarks.md "Points in use": chosen on training and validation levels. The API (import_level) keeps "all", the
# volume's old behaviour, for the recipe's captures; `lpnn scene import` and `make demo` use this.
DEFAULT_RULE = "reachable"
BAND_HEIGHT = 3.0  # metres: a 2 m character (Unity NavMesh agentHeight) jumping ~1 m (Quake III: 45.6 units)
SLOPE_LIMIT_DEGREES = 45.0  # Unity NavMesh agentSlope; Quake III MIN_WALK_NORMAL 0.7 (45.6 degrees)
STEP_HEIGHT = 0.5  # metres: above Quake III STEPSIZE (18 units, 0.457 m) and Unity NavMesh agentClimb (0.4 m)
