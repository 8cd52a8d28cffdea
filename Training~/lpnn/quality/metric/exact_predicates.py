"""The exact signs of regular_insertion.py's determinants, for the rare values its double evaluation cannot decide
(within its rounding bound of 0): every double is a rational number, so the determinant of the given doubles is computed
in Python's rational arithmetic (fractions.Fraction), without any rounding. Ties are left only where the points really
are coplanar or cospherical (a lattice's axis-aligned planes). The C# core's ExactPredicates, the same determinants (in
BigInteger); plain Python, called from the compiled insertion only when a sign is undecided.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np


def _sign(value: Fraction) -> int:
    return (value > 0) - (value < 0)


def _determinant3(m: list[list[Fraction]]) -> Fraction:
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def _determinant4(m: list[list[Fraction]]) -> Fraction:
    total = Fraction(0)
    for col in range(4):
        minor = [[row[c] for c in range(4) if c != col] for row in m[1:]]
        term = m[0][col] * _determinant3(minor)
        total += term if col % 2 == 0 else -term
    return total


def _lifted_rows(local: np.ndarray, height: np.ndarray, rows: list[int], o: int) -> list[list[Fraction]]:
    """Rows (q - o, |q - o|^2 + h(q) - h(o)) of `rows`, exactly."""
    origin = [Fraction(float(v)) for v in local[o]]
    lifted = []
    for q in rows:
        delta = [Fraction(float(v)) - origin[k] for k, v in enumerate(local[q])]
        lifted.append(delta + [sum(d * d for d in delta) + Fraction(float(height[q])) - Fraction(float(height[o]))])
    return lifted


def orient_sign(local: np.ndarray, a: int, b: int, c: int, d: int) -> int:
    """The sign of det[b - a, c - a, d - a] (rows of `local`)."""
    origin = [Fraction(float(v)) for v in local[a]]
    return _sign(_determinant3([[Fraction(float(v)) - origin[k] for k, v in enumerate(local[q])] for q in (b, c, d)]))


def power_sign(local: np.ndarray, height: np.ndarray, a: int, b: int, c: int, d: int, p: int) -> int:
    """The sign of the lifted determinant with rows (q - p, |q - p|^2 + h(q) - h(p)) for q = a, b, c, d."""
    return _sign(_determinant4(_lifted_rows(local, height, [a, b, c, d], p)))


def power_in_plane_sign(local: np.ndarray, height: np.ndarray, a: int, b: int, c: int, p: int) -> int:
    """The sign of the lifted determinant with rows (q - a, |q - a|^2 + h(q) - h(a)) for q = b, c, p and
    ((b - a) x (c - a), 0): for p in the plane of (a, b, c), positive when p lies inside their power circle."""
    m = _lifted_rows(local, height, [b, c, p], a)
    m.append([m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2],
              m[0][0] * m[1][1] - m[0][1] * m[1][0], Fraction(0)])
    return _sign(_determinant4(m))
