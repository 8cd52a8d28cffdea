"""The exact signs of regular_insertion.py's determinants, for the values its double evaluation cannot decide (within
its rounding bound of 0): every double is an integer times a power of two, so the determinant of the given doubles is
computed in Python's integers, without any rounding, after scaling every coordinate by one power of two 2^K that makes
them all integers (and every tie height by 2^2K, the scale of a squared distance). Each row is then a positive multiple
of the exact one column by column (K on the coordinates, 2K on the lifted column), so each determinant is a positive
multiple of the exact one and has its sign. Ties are left only where the points really are coplanar or cospherical (a
lattice's planes). The C# core's ExactPredicates, the same determinants (in BigInteger); plain Python, called from the
compiled insertion only when a sign is undecided — on lattice crops a few hundred times a placement, from the starting
hull's convexity check (tilted planes through lattice points), where integers take a fifth of rationals' time.
"""

from __future__ import annotations

import numpy as np


def _sign(value: int) -> int:
    return (value > 0) - (value < 0)


def _scaled(values: list[float], heights: list[float] = ()) -> tuple[list[int], list[int]]:
    """The exact integers `values` x 2^K and `heights` x 2^2K, for the smallest K >= 0 that makes them all integers."""
    coordinates = [v.as_integer_ratio() for v in values]
    lifts = [h.as_integer_ratio() for h in heights]
    shift = max([d.bit_length() - 1 for _, d in coordinates] + [(d.bit_length()) // 2 for _, d in lifts] + [0])
    return ([n << (shift - (d.bit_length() - 1)) for n, d in coordinates],
            [n << (2 * shift - (d.bit_length() - 1)) for n, d in lifts])


def _determinant3(m: list[list[int]]) -> int:
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def _determinant4(m: list[list[int]]) -> int:
    total = 0
    for col in range(4):
        minor = [[row[c] for c in range(4) if c != col] for row in m[1:]]
        term = m[0][col] * _determinant3(minor)
        total += term if col % 2 == 0 else -term
    return total


def _lifted_rows(local: np.ndarray, height: np.ndarray, rows: list[int], o: int) -> list[list[int]]:
    """Rows (q - o, |q - o|^2 + h(q) - h(o)) of `rows`, each column scaled exactly (module text)."""
    points = [o] + list(rows)
    coordinates, heights = _scaled(local[points].ravel().tolist(), height[points].tolist())
    lifted = []
    for i in range(1, len(points)):
        delta = [coordinates[3 * i + k] - coordinates[k] for k in range(3)]
        lifted.append(delta + [sum(x * x for x in delta) + heights[i] - heights[0]])
    return lifted


def orient_sign(local: np.ndarray, a: int, b: int, c: int, d: int) -> int:
    """The sign of det[b - a, c - a, d - a] (rows of `local`)."""
    coordinates, _ = _scaled(local[[a, b, c, d]].ravel().tolist())
    return _sign(_determinant3([[coordinates[3 * i + k] - coordinates[k] for k in range(3)] for i in (1, 2, 3)]))


def power_sign(local: np.ndarray, height: np.ndarray, a: int, b: int, c: int, d: int, p: int) -> int:
    """The sign of the lifted determinant with rows (q - p, |q - p|^2 + h(q) - h(p)) for q = a, b, c, d."""
    return _sign(_determinant4(_lifted_rows(local, height, [a, b, c, d], p)))


def power_in_plane_sign(local: np.ndarray, height: np.ndarray, a: int, b: int, c: int, p: int) -> int:
    """The sign of the lifted determinant with rows (q - a, |q - a|^2 + h(q) - h(a)) for q = b, c, p and
    ((b - a) x (c - a), 0): for p in the plane of (a, b, c), positive when p lies inside their power circle."""
    m = _lifted_rows(local, height, [b, c, p], a)
    m.append([m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2],
              m[0][0] * m[1][1] - m[0][1] * m[1][0], 0])
    return _sign(_determinant4(m))
