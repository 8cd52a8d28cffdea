"""The light-rig objective and its analytic gradient as one compiled pass over the visible pairs (model.py).

The same formula as model.ForwardModel.objective_numpy (Documentation~/lights.md §3): per target point, the
byte light E = ambient + fixed + 7500 sum_j g_ij e_j over its visible lights, the 255 clamp keeping the hue,
the residual against the target, then the gradient back through the clamp to every pair. numpy builds
(pairs, 3) temporaries for each of those steps; this loop keeps one point's numbers in registers and reads
each pair twice (once for E, once for the gradient), so an evaluation costs a pass over the pairs
(measured in lights.md §3: `tests/lights/objective_bench.py LEVEL`).

Pairs are given in CSR form: the lights visible from point i are lights[starts[i]:starts[i + 1]].

Determinism: points are cut into chunks_for(N) slices, a fixed function of N (never of the thread count);
each slice accumulates its value and gradient in its own buffers in point order, and the slices are summed
in slice order after the parallel loop. The same inputs give the same bits on any number of threads
(tests/lights/test_lights_objective.py runs 1 and 2 threads). Summation order differs from numpy's, so
the two agree to rounding (~1e-13 relative), not bit for bit.
Compiled with numba and cached on disk (core/cache.py).
"""

from __future__ import annotations

import numpy as np

from ..core.cache import use_project_cache_for_numba

use_project_cache_for_numba()
import numba  # noqa: E402  (after the cache folder is chosen)
from numba import njit, prange  # noqa: E402

PARALLEL_POINTS = 2048  # points per slice at least (fewer points: one slice, no threads woken for nothing)
PARALLEL_CHUNKS = 64  # slices at most


@njit(cache=True, parallel=True)
def objective_pass(points, normals, albedo, radiance, weights, fixed, ambient, positions, emitted, axes, cones,
                   starts, lights, point_scale, min_distance, spot_edge, byte_max, linear_per_byte, norm, with_gradient,
                   chunk_values, chunk_pos, chunk_emitted, chunk_axes, chunk_cones, chunk_ambient, upstream_out):
    """Fills chunk_values (C,), chunk_pos (C, J, 3), chunk_emitted (C, J, 3), chunk_axes (C, J, 3), chunk_cones
    (C, J), chunk_ambient (C, 3) with each slice's sum of w |m - r|^2 and of dL/d(position), dL/d(colour x
    intensity), dL/d(spot axis), dL/d(radiusByDist), dL/d(ambient) (all zero on entry); C = chunks_for(N) slices
    of the points. Light j is a spotlight when cones[j] > 0 (axis axes[j], q3map2's cone: spot_factor); else a
    point light (axes and cones unread, their gradient stays 0). With gradient, upstream_out (N, 3) receives every
    point's dL/dE when it has N rows (the surface lights' gradient, model.py); give it 0 rows to skip that."""
    keep_upstream = upstream_out.shape[0] == points.shape[0]
    n = points.shape[0]
    chunks = chunk_values.shape[0]
    min_sq = min_distance * min_distance
    for chunk in prange(chunks):
        lo = n * chunk // chunks
        hi = n * (chunk + 1) // chunks
        value = 0.0
        light = np.empty(3)
        upstream = np.empty(3)
        for i in range(lo, hi):
            px, py, pz = points[i, 0], points[i, 1], points[i, 2]
            nx, ny, nz = normals[i, 0], normals[i, 1], normals[i, 2]
            for c in range(3):
                light[c] = 0.0
            for k in range(starts[i], starts[i + 1]):
                j = lights[k]
                dx, dy, dz = positions[j, 0] - px, positions[j, 1] - py, positions[j, 2] - pz
                ndot = dx * nx + dy * ny + dz * nz
                if ndot > 0.0:
                    q = max(np.sqrt(dx * dx + dy * dy + dz * dz), 1e-9)
                    g = ndot / (q * max(q * q, min_sq))
                    if cones[j] > 0.0:
                        g *= spot_factor(-dx, -dy, -dz, axes[j, 0], axes[j, 1], axes[j, 2], cones[j], spot_edge)
                    for c in range(3):
                        light[c] += g * emitted[j, c]
            for c in range(3):
                light[c] = ambient[c] + fixed[i, c] + point_scale * light[c]
            top = 0
            for c in range(1, 3):
                if light[c] > light[top]:
                    top = c
            peak = light[top]
            scale = byte_max / peak if peak > byte_max else 1.0
            w = weights[i]
            for c in range(3):
                residual = albedo[i, c] * linear_per_byte * light[c] * scale - radiance[i, c]
                value += w * residual * residual
                upstream[c] = 2.0 * w * residual * albedo[i, c] * linear_per_byte / norm
            if not with_gradient:
                continue
            if peak > byte_max:  # d(255 E_c / E_k)/dE_m = (255 / E_k) (delta_cm - delta_mk E_c / E_k)
                along = (upstream[0] * light[0] + upstream[1] * light[1] + upstream[2] * light[2]) / peak
                for c in range(3):
                    upstream[c] *= scale
                upstream[top] -= scale * along
            for c in range(3):
                chunk_ambient[chunk, c] += upstream[c]
                if keep_upstream:
                    upstream_out[i, c] = upstream[c]
                upstream[c] *= point_scale
            for k in range(starts[i], starts[i + 1]):
                j = lights[k]
                dx, dy, dz = positions[j, 0] - px, positions[j, 1] - py, positions[j, 2] - pz
                ndot = dx * nx + dy * ny + dz * nz
                if ndot <= 0.0:
                    continue
                q = max(np.sqrt(dx * dx + dy * dy + dz * dz), 1e-9)
                u = upstream[0] * emitted[j, 0] + upstream[1] * emitted[j, 1] + upstream[2] * emitted[j, 2]
                # dg/dx for q >= R0: n/q^3 - 3 (n.d) d / q^5; for q < R0: n/(R0^2 q) - (n.d) d / (R0^2 q^3)
                if q >= min_distance:
                    g = ndot / (q * q * q)
                    along_normal = 1.0 / (q * q * q)
                    along_d = 3.0 * ndot / q ** 5
                else:
                    g = ndot / (q * min_sq)
                    along_normal = 1.0 / (q * min_sq)
                    along_d = ndot / (min_sq * q * q * q)
                gx = along_normal * nx - along_d * dx  # dg/dx
                gy = along_normal * ny - along_d * dy
                gz = along_normal * nz - along_d * dz
                if cones[j] > 0.0:
                    # h = g f: dh/dx = f dg/dx + g df/dx, with v = p - x = -d so df/dx = -df/dv
                    f = spot_factor(-dx, -dy, -dz, axes[j, 0], axes[j, 1], axes[j, 2], cones[j], spot_edge)
                    if f <= 0.0:
                        continue
                    if f < 1.0:  # the soft edge: f = (k t - r) / edge
                        vx, vy, vz = -dx, -dy, -dz
                        ax, ay, az = axes[j, 0], axes[j, 1], axes[j, 2]
                        k = cones[j]
                        t = vx * ax + vy * ay + vz * az
                        wx, wy, wz = vx - t * ax, vy - t * ay, vz - t * az
                        r = np.sqrt(wx * wx + wy * wy + wz * wz)
                        wn = wx * ax + wy * ay + wz * az  # 0 for a unit axis; kept so any axis is exact
                        # dr/dv = (w - (w.N) N) / r, dr/dN = -((w.N) v + t w) / r (0 on the axis)
                        inv = 1.0 / r if r > 1e-12 else 0.0
                        dvx = (k * ax - (wx - wn * ax) * inv) / spot_edge
                        dvy = (k * ay - (wy - wn * ay) * inv) / spot_edge
                        dvz = (k * az - (wz - wn * az) * inv) / spot_edge
                        ug = u * g / spot_edge
                        chunk_axes[chunk, j, 0] += ug * (k * vx + (wn * vx + t * wx) * inv)
                        chunk_axes[chunk, j, 1] += ug * (k * vy + (wn * vy + t * wy) * inv)
                        chunk_axes[chunk, j, 2] += ug * (k * vz + (wn * vz + t * wz) * inv)
                        chunk_cones[chunk, j] += ug * t
                        gx, gy, gz = f * gx - g * dvx, f * gy - g * dvy, f * gz - g * dvz
                    else:
                        gx, gy, gz = f * gx, f * gy, f * gz
                    g *= f
                for c in range(3):
                    chunk_emitted[chunk, j, c] += g * upstream[c]
                chunk_pos[chunk, j, 0] += u * gx
                chunk_pos[chunk, j, 1] += u * gy
                chunk_pos[chunk, j, 2] += u * gz
        chunk_values[chunk] = value


@njit(cache=True, inline="always")
def spot_factor(vx, vy, vz, ax, ay, az, k, edge):
    """q3map2's cone (light_ydnar.c LightContributionToSample, EMIT_SPOT) at offset v = p - x from a spotlight of
    axis N and radiusByDist k: t = v.N, r = |v - t N|, R = k t; 0 when t <= 0 or r >= R, (R - r) / edge on the
    soft edge, else 1 (emitters.spot_factor)."""
    t = vx * ax + vy * ay + vz * az
    if t <= 0.0:
        return 0.0
    wx, wy, wz = vx - t * ax, vy - t * ay, vz - t * az
    r = np.sqrt(wx * wx + wy * wy + wz * wz)
    return min(1.0, max(0.0, (k * t - r) / edge))


def run(threads: int, *arguments) -> None:
    """objective_pass on `threads` threads (1 for small inputs: waking threads costs more than they save), at
    most the caller's numba.get_num_threads(); the numbers do not depend on it."""
    previous = numba.get_num_threads()
    numba.set_num_threads(max(1, min(threads, previous)))
    try:
        objective_pass(*arguments)
    finally:
        numba.set_num_threads(previous)


def chunks_for(points: int) -> int:
    """Slices the points are cut into: a fixed function of their number, so results never depend on threads."""
    return max(1, min(points // PARALLEL_POINTS, PARALLEL_CHUNKS))


def threads_for(points: int) -> int:
    return numba.config.NUMBA_NUM_THREADS if chunks_for(points) >= 2 else 1


def csr(visible: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(starts (N + 1,), lights (P,)) of a (N, J) visibility matrix: the lights of point i, in light order."""
    point, light = np.nonzero(visible)
    starts = np.zeros(visible.shape[0] + 1, dtype=np.int64)
    np.cumsum(np.bincount(point, minlength=visible.shape[0]), out=starts[1:])
    return starts, light.astype(np.int64)
