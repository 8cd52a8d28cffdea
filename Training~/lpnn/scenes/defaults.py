"""Units and import defaults, importable without numpy (the CLI's --help prints them)."""

METRES_PER_UNIT = 0.0254  # one Quake unit is one inch
# 64 units: the light grid's xy spacing, so the world-anchored lattice lands on its xy nodes.
DEFAULT_CELL_UNITS = 64
DEFAULT_CELL = DEFAULT_CELL_UNITS * METRES_PER_UNIT  # 1.6256 m
DEFAULT_POINT_LIMIT = 2_000_000  # the grid's own default (grid.md)

