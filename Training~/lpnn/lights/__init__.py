"""The light rig from baked lighting: recover point lights from a level's lightmaps.

The inverse method of the third seed document (Documentation~/lights.md): a radiance target on the
level's surfaces (lightmap x texture, mass-lumped L2 projection), a differentiable forward model of
point lights with Embree shadow rays, and Adam / L-BFGS phases that fit the lights to the target.
Modules, one responsibility each:
  surfaces    the lit surfaces of a level as one attributed triangle mesh (lightmap / vertex-lit)
  textures    albedo from the level's pk3 textures (Pillow), with the documented fallback
  target      Algorithm 4.1: texture x lightmap projected onto the mesh vertices; subdivision
  model       radiance of point lights (and fitted surface lights and suns) at the target points, its gradient,
              shadow-ray visibility
  shadows     q3map2's shadow casters: the geometry of every visibility ray (no patches, no entity surfaces)
  objective_kernel   the objective and its gradient as one compiled pass over the visible pairs
  visibility_kernel  a visibility refresh's candidate pairs and rays, one compiled pass
  emitters    spotlights and shader surface lights of a compile; per-shader bases of the fitted ones
  rig         the rig file (JSON, version 3: point, spot, surface lights, suns): write, read, validate; the
              level's own light entities
  optimise    initial grid in open space, penalties, Adam / L-BFGS phases, schemes
  pointlight  what a point light gives a free point (grid rule): shared by compare and bake
  bake        probe SH at any points from a rig: direct light with shadow rays, one gathered bounce
  relight     a rig as the importer's lighting (--lighting rig:RIG.json) and the capture's record
  bake_check  the baker's validation against the stored light grid (benchmarks.md "The light rig")
"""
