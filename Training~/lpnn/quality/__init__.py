"""Placement quality (Documentation~/quality.md): how well a probe set reproduces the dense lighting.

Three subpackages, lowest first (each imports only those before it; Tools~/lint-python.py `SUBLAYERS`):
`metric` (interpolation as Unity does it: tetrahedra + barycentric weights, projection outside the hull; the error
metric; the leak rule), `placement` (the selection policies, insertion and its batched refinement, the baselines, the
methods that read the scores, the table of method names: methods.py, Documentation~/methods.md; `placement.decimation`
the two error-driven reference placements, which import no other placement module)
and `bench` (the speed/accuracy benchmark and its figures). One metric serves labels, validation, the tolerance
policy and the benchmark.
"""
