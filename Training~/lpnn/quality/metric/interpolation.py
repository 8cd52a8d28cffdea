"""Probe interpolation as Unity does it: tetrahedra, barycentric blend, hull projection outside.

    stencil = stencil_for(probe_positions, query_positions)
    sh_at_query = lpnn.core.sh.blend(probe_sh, stencil.vertices, stencil.weights)

The SH blend is linear, so blending per-direction irradiance values gives the same numbers as
blending the SH and evaluating afterwards (the metric uses that).
"""

from __future__ import annotations

import numpy as np

from ...core import sh as shmath
from .location import Stencil, locate
from .triangulation import Frame, tetrahedralize


def stencil_for(probe_positions: np.ndarray, query_positions: np.ndarray, frame: Frame | None = None) -> Stencil:
    """Which probes (indices into probe_positions) and weights interpolate each query point."""
    return locate(tetrahedralize(probe_positions, frame), query_positions)


def interpolate_sh(probe_positions: np.ndarray, probe_sh: np.ndarray, query_positions: np.ndarray,
                   frame: Frame | None = None) -> np.ndarray:
    """SH (M, 27) float64 at the query points, blended from the probes (K, 3) / (K, 27)."""
    values = np.asarray(probe_sh, dtype=np.float64)
    if values.ndim != 2 or values.shape != (np.asarray(probe_positions).shape[0], shmath.SH_FLOATS):
        raise ValueError(f"probe SH must have shape ({np.asarray(probe_positions).shape[0]}, 27), "
                         f"got {list(values.shape)}")
    if not np.all(np.isfinite(values)):
        row = int(np.flatnonzero(~np.all(np.isfinite(values), axis=1))[0])
        raise ValueError(f"probe SH row {row} is not finite: re-bake the probes")
    stencil = stencil_for(probe_positions, query_positions, frame)
    return shmath.blend(values, stencil.vertices, stencil.weights)
