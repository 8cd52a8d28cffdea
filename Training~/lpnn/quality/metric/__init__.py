"""The placement error (quality.md §1-2): interpolation as Unity does it (tetrahedralization, point location,
projection onto the hull), the error metric and its kernels, the leak rule. Imports no other part of lpnn.quality."""
