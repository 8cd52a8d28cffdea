"""Unity SphericalHarmonicsL2 convention (Documentation~/sh.md), vectorised over points.

SH arrays have shape (..., 27): index rgb*9 + i, coefficient order
(1, y, z, x, xy, yz, 3z^2-1, xz, x^2-y^2), coefficients pre-multiplied the way Unity stores them.
All arithmetic is float64; callers cast results to float32 where a file format needs it.
"""

from __future__ import annotations

import numpy as np

SH_COEFFICIENTS = 9
SH_FLOATS = 27
LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722], dtype=np.float64)


def basis(directions: np.ndarray) -> np.ndarray:
    """Polynomials P_i(n) for unit directions (..., 3) -> (..., 9)."""
    d = np.asarray(directions, dtype=np.float64)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack(
        [np.ones_like(x), y, z, x, x * y, y * z, 3.0 * z * z - 1.0, x * z, x * x - y * y], axis=-1
    )


def as_rgb_coefficients(sh: np.ndarray) -> np.ndarray:
    """(..., 27) -> (..., 3, 9) view in float64."""
    s = np.asarray(sh, dtype=np.float64)
    if s.shape[-1] != SH_FLOATS:
        raise ValueError(f"SH arrays need 27 values in their last axis, got shape {s.shape}")
    return s.reshape(s.shape[:-1] + (3, SH_COEFFICIENTS))


def evaluate(sh: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Evaluate SH (N, 27) in unit directions (D, 3) -> RGB (N, D, 3), float64.

    Sums in coefficient order, like the C# core, so both agree to rounding.
    """
    coeffs = as_rgb_coefficients(sh)  # (N, 3, 9)
    polys = basis(directions)  # (D, 9)
    return np.einsum("nci,di->ndc", coeffs, polys, optimize=False)


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Rec. 709 luminance of RGB values (..., 3)."""
    return np.asarray(rgb, dtype=np.float64) @ LUMINANCE_WEIGHTS


def rgb_to_ycocg(rgb: np.ndarray) -> np.ndarray:
    c = np.asarray(rgb, dtype=np.float64)
    r, g, b = c[..., 0], c[..., 1], c[..., 2]
    return np.stack([r / 4 + g / 2 + b / 4, r / 2 - b / 2, -r / 4 + g / 2 - b / 4], axis=-1)


def ycocg_to_rgb(ycocg: np.ndarray) -> np.ndarray:
    c = np.asarray(ycocg, dtype=np.float64)
    y, co, cg = c[..., 0], c[..., 1], c[..., 2]
    return np.stack([y + co - cg, y + cg, y - co - cg], axis=-1)


def ambient(rgb: np.ndarray) -> np.ndarray:
    """SH (..., 27) of a constant ambient colour (..., 3): adds to the DC term only."""
    c = np.asarray(rgb, dtype=np.float64)
    out = np.zeros(c.shape[:-1] + (3, SH_COEFFICIENTS), dtype=np.float64)
    out[..., 0] = c
    return out.reshape(c.shape[:-1] + (SH_FLOATS,))


def directional(direction: np.ndarray, rgb: np.ndarray, intensity: float | np.ndarray = 1.0) -> np.ndarray:
    """Unity AddDirectionalLight: SH (..., 27) of a light from unit `direction` (toward the light).

    k = 2 * intensity * rgb is formed in float32 as Unity's managed code does.
    """
    d = np.asarray(direction, dtype=np.float64)
    k = (np.float32(2.0) * np.asarray(intensity, dtype=np.float32)[..., None]
         * np.asarray(rgb, dtype=np.float32)).astype(np.float64)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    factors = np.stack(
        [
            np.full_like(x, 4.0 / 17.0),
            (8.0 / 17.0) * y,
            (8.0 / 17.0) * z,
            (8.0 / 17.0) * x,
            (15.0 / 17.0) * x * y,
            (15.0 / 17.0) * y * z,
            (5.0 / 68.0) * (3.0 * z * z - 1.0),
            (15.0 / 17.0) * x * z,
            (15.0 / 68.0) * (x * x - y * y),
        ],
        axis=-1,
    )  # (..., 9)
    out = k[..., :, None] * factors[..., None, :]  # (..., 3, 9)
    return out.reshape(out.shape[:-2] + (SH_FLOATS,))


def clamped_cosine_factors(direction: np.ndarray) -> np.ndarray:
    """(..., 9): the stored SH of max(0, n.l) for unit `direction` l (toward the light), one channel:
    the L2 least-squares fit in Unity's convention (sh.md "Ambient + directed" with a = 0, d = 1)."""
    l = np.asarray(direction, dtype=np.float64)
    lx, ly, lz = l[..., 0], l[..., 1], l[..., 2]
    return np.stack(
        [
            np.full_like(lx, 0.25),
            0.5 * ly,
            0.5 * lz,
            0.5 * lx,
            (15.0 / 16.0) * lx * ly,
            (15.0 / 16.0) * ly * lz,
            (5.0 / 64.0) * (3.0 * lz * lz - 1.0),
            (15.0 / 16.0) * lx * lz,
            (15.0 / 64.0) * (lx * lx - ly * ly),
        ],
        axis=-1,
    )


def ambient_plus_directed(ambient_rgb: np.ndarray, directed_rgb: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """L2 least-squares fit of a + d*max(0, n.l) per channel, in Unity's stored convention.

    ambient_rgb, directed_rgb: (..., 3); direction: unit (..., 3) toward the light. Returns (..., 27).
    """
    a = np.asarray(ambient_rgb, dtype=np.float64)
    d = np.asarray(directed_rgb, dtype=np.float64)
    factors = clamped_cosine_factors(direction)
    out = d[..., :, None] * factors[..., None, :]
    out[..., 0] += a
    return out.reshape(out.shape[:-2] + (SH_FLOATS,))


def blend(sh: np.ndarray, indices: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Weighted blend of probes: sh (P, 27), indices (M, K), weights (M, K) -> (M, 27) float64."""
    s = np.asarray(sh, dtype=np.float64)
    return np.einsum("mk,mkc->mc", np.asarray(weights, dtype=np.float64), s[np.asarray(indices)])
