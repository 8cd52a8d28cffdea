"""Variable-length index ranges without Python loops (faces' vertices, leaves' brushes, ...)."""

from __future__ import annotations

import numpy as np


def concatenated_ranges(first: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """arange(first[0], first[0] + counts[0]) ++ arange(first[1], ...) ++ ... as int64."""
    counts = np.asarray(counts, dtype=np.int64)
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    # each element = its range's first value + its position inside the range
    offsets = np.repeat(np.asarray(first, dtype=np.int64) - (np.cumsum(counts) - counts), counts)
    return offsets + np.arange(total, dtype=np.int64)
