"""Real levels without Unity: OpenArena / Quake III (IBSP v46) levels as light-probe captures.

Documentation~/openarena.md describes the decisions (units, coordinates, ray geometry, patches).
Modules, one responsibility each:
  errors     BspError
  ranges     variable-length index ranges without loops
  levels     where a level's bytes come from (.bsp file, pak.pk3:maps/x.bsp, or a map name)
  bsp        the IBSP v46 reader (lumps as numpy structured arrays, validated)
  entities   the entity lump's text
  defaults   units and import defaults (no numpy)
  coords     Quake units/axes -> Unity metres/axes (the one mapping used everywhere)
  patches    Bezier patch tessellation at a fixed level
  surfaces   which faces are geometry for rays, as one triangle soup
  lightgrid  sampling the baked light grid like the renderer, and its SH
  raycast    first-hit rays against the level (Embree)
  solid      point in solid / outside the map (BSP tree + brushes)
  importer   level -> evaluation grid -> SH + features -> capture
  info       what `lpnn scene info` reports
  pack       import every level of a pack and report the ones that fail
"""
