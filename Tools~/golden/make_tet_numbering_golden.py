"""Writes Tests/Data/tet_numbering_golden.json: a few tetrahedra and the order Documentation~/quality.md §1 "Ties" numbers
them in (the hash of each one's point indices, splitmix64's finaliser chained over the four ascending indices).

By construction, not by the code it checks: the rule is written out again here in plain Python integers (standard
library only, no numpy, no lpnn), from the text of quality.md. Usage: python3 make_tet_numbering_golden.py TESTS_DATA_DIR
"""

import json
import sys
from pathlib import Path

MASK = (1 << 64) - 1
GAMMA = 0x9E3779B97F4A7C15


def mix(z: int) -> int:
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return z ^ (z >> 31)


def tet_hash(a: int, b: int, c: int, d: int) -> int:
    h = mix((a + GAMMA) & MASK)
    for v in (b, c, d):
        h = mix(h ^ v)
    return h


def main() -> None:
    # Point indices of a probe set's 9 positions (any order, as an insertion round lists its probes), large ones included
    # so that the sums and products wrap around 2^64.
    ids = [17, 3, 1_000_003, 42, 0, 2_147_483_646, 99, 5, 65_536]
    # Tetrahedra as positions in the set, in a scrambled order and corner order (as a tetrahedraliser may list them).
    tetrahedra = [[2, 0, 5, 7], [8, 1, 4, 3], [6, 5, 4, 0], [1, 3, 2, 0], [4, 8, 7, 6], [0, 3, 1, 8], [5, 2, 6, 1]]
    rows = []
    for tet in tetrahedra:
        corners = sorted(tet, key=lambda position: ids[position])
        points = [ids[c] for c in corners]
        rows.append((tet_hash(*points), points, corners))
    rows.sort(key=lambda row: (row[0], row[1]))
    golden = {
        "contract": "Documentation~/quality.md §1 'Ties': tetrahedra ordered by tet_hash of their ascending point indices",
        "splitmix64": {"gamma": f"0x{GAMMA:016X}", "multipliers": ["0xBF58476D1CE4E5B9", "0x94D049BB133111EB"],
                       "shifts": [30, 27, 31]},
        "ids": ids,
        "tetrahedra": tetrahedra,
        "numbered": [row[2] for row in rows],
        "hashes": [f"0x{row[0]:016X}" for row in rows],
    }
    out = Path(sys.argv[1]) / "tet_numbering_golden.json"
    out.write_text(json.dumps(golden, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
