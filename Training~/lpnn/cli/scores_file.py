"""The scores file `lpnn score` writes and `lpnn place --scores` reads: CSV `index,i,j,k,score`, one line
per point in capture order, '.' decimals, 9 significant digits (round-trips float32)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import UserError

SCORES_HEADER = ("index", "i", "j", "k", "score")


def scores_csv(ids: np.ndarray, scores: np.ndarray) -> str:
    """One line per point in capture order; '.' decimals and 9 significant digits (round-trips float32)."""
    rows = (f"{n},{i},{j},{k},{s:.9g}" for n, ((i, j, k), s) in enumerate(zip(ids.tolist(), scores.tolist())))
    return "\n".join([",".join(SCORES_HEADER), *rows]) + "\n"


def write_scores_csv(path: str | os.PathLike, ids: np.ndarray, scores: np.ndarray) -> None:
    from ..core.atomic import write_text_atomic

    write_text_atomic(path, scores_csv(ids, scores))


def read_scores_csv(path: str | os.PathLike, ids: np.ndarray) -> np.ndarray:
    """Scores in capture order from `lpnn score`'s CSV; the ids must match the capture's."""
    file = Path(path)
    try:
        lines = file.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise UserError(f"{file}: cannot read scores: {exc}") from exc
    rows = [(number, line) for number, line in enumerate(lines, start=1) if line.strip()]
    if not rows or tuple(c.strip() for c in rows[0][1].split(",")) != SCORES_HEADER:
        raise UserError(f"{file}: line 1: expected the header {','.join(SCORES_HEADER)} (as `lpnn score` writes)")
    body = rows[1:]
    if len(body) != ids.shape[0]:
        raise UserError(f"{file}: {len(body):,} score rows for a capture of {ids.shape[0]:,} points")
    scores = np.empty(len(body))
    for position, (number, line) in enumerate(body):
        fields = [c.strip() for c in line.split(",")]
        if len(fields) != len(SCORES_HEADER):
            raise UserError(f"{file}: line {number}: {len(fields)} fields, expected {len(SCORES_HEADER)}")
        try:
            index, i, j, k = (int(v) for v in fields[:4])
            scores[position] = float(fields[4])
        except ValueError:
            raise UserError(f"{file}: line {number}: {line!r} is not index,i,j,k,score with '.' decimals") from None
        if index != position or (i, j, k) != tuple(int(v) for v in ids[position]):
            raise UserError(f"{file}: line {number}: point {index} id ({i},{j},{k}) does not match the capture's "
                            f"point {position} id {tuple(int(v) for v in ids[position])}: scores of another capture?")
    return scores
