"""Placement quality (Documentation~/quality.md): how well a probe set reproduces the dense lighting.

Interpolation as Unity does it (tetrahedra + barycentric weights, projection outside the hull), the
error metric, the two error-driven reference placements, the selection policies, the baselines and
the speed/accuracy benchmark. One metric serves labels, validation, the tolerance policy and the
benchmark.
"""
