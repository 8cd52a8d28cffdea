"""The signs a tie-broken Delaunay tetrahedralisation grown by insertion decides (regular_insertion.py): a point's side
of a plane, and whether it conflicts with a tetrahedron — below the lifted hyperplane of its corners, or for a hull face
(a tetrahedron with the vertex at INFINITE), beyond its plane or in it and inside its power circle.

Every sign is computed in double with a bound on its rounding (UNDECIDED_FRACTION of the determinant's permanent);
within the bound it is computed exactly (exact_predicates.py, called through numba's object mode; C#: ExactPredicates).
"""

from __future__ import annotations

from ...core.cache import use_project_cache_for_numba
from . import exact_predicates

use_project_cache_for_numba()
from numba import njit, objmode  # noqa: E402  (after the cache folder is chosen)

UNDECIDED_FRACTION = 1e-12  # a determinant within this x its permanent of 0 is not decided in double (C#: exactly)
INFINITE = -1  # slot 3 of a hull face's infinite tetrahedron


@njit(cache=True)
def orient(local, a, b, c, d):
    """det[b - a, c - a, d - a] and its permanent (the sum of its expansion's absolute products)."""
    ux, uy, uz = local[b, 0] - local[a, 0], local[b, 1] - local[a, 1], local[b, 2] - local[a, 2]
    vx, vy, vz = local[c, 0] - local[a, 0], local[c, 1] - local[a, 1], local[c, 2] - local[a, 2]
    wx, wy, wz = local[d, 0] - local[a, 0], local[d, 1] - local[a, 1], local[d, 2] - local[a, 2]
    det = ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx)
    permanent = (abs(ux) * (abs(vy * wz) + abs(vz * wy)) + abs(uy) * (abs(vz * wx) + abs(vx * wz))
                 + abs(uz) * (abs(vx * wy) + abs(vy * wx)))
    return det, permanent


# The exact signs (exact_predicates, plain Python) through object mode: each in its own compiled function, as numba
# cannot lower an object-mode block inside branches that reassign its output.
@njit(cache=True)
def _exact_orient(local, a, b, c, d):
    with objmode(sign="int64"):
        sign = exact_predicates.orient_sign(local, a, b, c, d)
    return sign


@njit(cache=True)
def _exact_power(local, height, a, b, c, d, p):
    with objmode(sign="int64"):
        sign = exact_predicates.power_sign(local, height, a, b, c, d, p)
    return sign


@njit(cache=True)
def _exact_power_in_plane(local, height, a, b, c, p):
    with objmode(sign="int64"):
        sign = exact_predicates.power_in_plane_sign(local, height, a, b, c, p)
    return sign


@njit(cache=True)
def orient_sign(local, a, b, c, d):
    """The exact sign of det[b - a, c - a, d - a]: the double one where it is decided, 0 where every product of the
    expansion is 0 (points in one axis-aligned plane), else computed exactly (exact_predicates)."""
    det, permanent = orient(local, a, b, c, d)
    if abs(det) > UNDECIDED_FRACTION * permanent:
        return 1 if det > 0.0 else -1
    if permanent == 0.0:
        return 0
    return _exact_orient(local, a, b, c, d)


@njit(cache=True)
def lifted_row(m, r, local, height, q, o):
    """Row r of m: point q about point o, lifted (|q - o|^2 plus the difference of their tie heights)."""
    dx, dy, dz = local[q, 0] - local[o, 0], local[q, 1] - local[o, 1], local[q, 2] - local[o, 2]
    m[r, 0], m[r, 1], m[r, 2] = dx, dy, dz
    m[r, 3] = dx * dx + dy * dy + dz * dz + (height[q] - height[o])


@njit(cache=True)
def determinant_sign(m):
    """The sign of the 4 x 4 determinant m (cofactors along the first row), or 2 within its rounding (undecided)."""
    det, permanent = 0.0, 0.0
    for col in range(4):
        c0 = 1 if col == 0 else 0
        c1 = 2 if col <= 1 else 1
        c2 = 3 if col <= 2 else 2
        minor = (m[1, c0] * (m[2, c1] * m[3, c2] - m[2, c2] * m[3, c1])
                 - m[1, c1] * (m[2, c0] * m[3, c2] - m[2, c2] * m[3, c0])
                 + m[1, c2] * (m[2, c0] * m[3, c1] - m[2, c1] * m[3, c0]))
        absolute = (abs(m[1, c0]) * (abs(m[2, c1] * m[3, c2]) + abs(m[2, c2] * m[3, c1]))
                    + abs(m[1, c1]) * (abs(m[2, c0] * m[3, c2]) + abs(m[2, c2] * m[3, c0]))
                    + abs(m[1, c2]) * (abs(m[2, c0] * m[3, c1]) + abs(m[2, c1] * m[3, c0])))
        det += (1.0 if col % 2 == 0 else -1.0) * m[0, col] * minor
        permanent += abs(m[0, col]) * absolute
    if abs(det) > UNDECIDED_FRACTION * permanent:
        return 1 if det > 0.0 else -1
    return 2


@njit(cache=True)
def conflict(V, local, height, m, t, p):
    """+1: p is in conflict with tetrahedron t (in its cavity), -1: not, 0: a true tie (p cospherical with t's corners in
    the lifted sense, which the tie heights exclude)."""
    a, b, c, d = V[t, 0], V[t, 1], V[t, 2], V[t, 3]
    if d != INFINITE:  # below the lifted hyperplane of the positively oriented (a, b, c, d): a negative determinant
        lifted_row(m, 0, local, height, a, p)
        lifted_row(m, 1, local, height, b, p)
        lifted_row(m, 2, local, height, c, p)
        lifted_row(m, 3, local, height, d, p)
        sign = determinant_sign(m)
        if sign == 2:
            sign = _exact_power(local, height, a, b, c, d, p)
        return -sign
    side = orient_sign(local, a, b, c, p)
    if side != 0:
        return side  # beyond the hull face (+1) or inside (-1)
    # In the hull face's plane: inside its power circle (the lifted determinant of b - a, c - a, p - a and the normal).
    lifted_row(m, 0, local, height, b, a)
    lifted_row(m, 1, local, height, c, a)
    lifted_row(m, 2, local, height, p, a)
    m[3, 0] = m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]
    m[3, 1] = m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]
    m[3, 2] = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    m[3, 3] = 0.0
    sign = determinant_sign(m)
    if sign == 2:
        sign = _exact_power_in_plane(local, height, a, b, c, p)
    return sign
