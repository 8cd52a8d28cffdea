#!/usr/bin/env python3
"""Times the Python spread ranking (lpnn.core.spread) on synthetic n^3 lattices with uniform random
scores (Documentation~/benchmarks.md "Scale: whole levels"), with the process's peak memory.

    PYTHONPATH=Training~ $PY Tools~/experiments/spread-bench.py [n ...]     (default 22 46 100: ~10^4, 10^5, 10^6 points)
"""

import resource
import sys
import time

import numpy as np

from lpnn.core.spread import spread_ranking


def main() -> int:
    sizes = [int(a) for a in sys.argv[1:]] or [22, 46, 100]
    spread_ranking(np.zeros((4, 3), dtype=np.float32) + np.eye(4, 3, dtype=np.float32), np.ones(4))  # compile
    print("points | spread ranking s | peak memory GB")
    for n in sizes:
        k, j, i = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
        positions = (np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1) * 0.5).astype(np.float32)
        scores = np.random.default_rng(0).uniform(0.0, 1.0, positions.shape[0]).astype(np.float32)
        start = time.perf_counter()
        spread_ranking(positions, scores)
        seconds = time.perf_counter() - start
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6  # kilobytes on Linux
        print(f"{positions.shape[0]:,} | {seconds:.1f} | {peak:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
