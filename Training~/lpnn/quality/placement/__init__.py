"""Placement methods (quality.md §3-5): the selection policies (budget, tolerance), error-driven insertion and its
batched refinement, the baselines (uniform, random, heuristic, APV-style), the methods that read the scores, the table of method names (methods.py), pins, and the probes file.
The error-driven references live in `placement.decimation`. Imports lpnn.quality.metric, never lpnn.quality.bench."""
