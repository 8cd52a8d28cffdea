"""Ranking only what a policy reads (core.spread.SpreadPrefix, policies.spread_prefix_selection,
lpnn_placement(full_ranking=False)) gives the very prefixes, probe sets and placements of the full
spread ranking."""

from __future__ import annotations

import numpy as np

from lpnn.core.capture import Capture
from lpnn.core.grid import EvaluationGrid
from lpnn.core.spread import SpreadPrefix, spread_ranking
from lpnn.quality.placement.lpnn_placement import lpnn_placement
from lpnn.quality.placement.policies import prefix_selection, spread_prefix_selection


def _lattice(shape: tuple[int, int, int]) -> tuple[np.ndarray, np.ndarray]:
    k, j, i = np.meshgrid(*(np.arange(n) for n in shape[::-1]), indexing="ij")
    ids = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.int32)
    return ids, ids.astype(np.float32) * 0.5


def test_prefixes_in_any_order_are_the_full_rankings_prefixes() -> None:
    ids, positions = _lattice((30, 20, 12))
    scores = np.random.default_rng(0).uniform(size=ids.shape[0]).astype(np.float32)
    full = spread_ranking(positions, scores)
    lazy = SpreadPrefix(positions, scores)
    for count in (1, 7, 5, 300, 64, 2_000, 7_199, 7_200, 10):
        np.testing.assert_array_equal(lazy.prefix(count), full[:count])
    assert lazy.computed == ids.shape[0]


class _PartialRanking:
    """A ranking computed exactly as far as asked (SpreadPrefix's interface), so that a flat prefix's
    completion is beyond the computed points."""

    def __init__(self, order: np.ndarray):
        self.order, self.point_count, self.computed = order, order.shape[0], 0

    def prefix(self, count: int) -> np.ndarray:
        self.computed = max(self.computed, min(count, self.point_count))
        return self.order[:count]

    def provisional_order(self) -> np.ndarray:
        rest = np.setdiff1d(np.arange(self.point_count), self.order[:self.computed])
        return np.concatenate([self.order[:self.computed], rest])


def test_a_flat_prefix_is_completed_from_the_whole_ranking() -> None:
    # The spread ranking's seeds span the volume, so its prefixes are never flat; this ranking puts a
    # whole layer first and the other layer in reverse index order, so the provisional order (unranked
    # points by index) would complete a prefix with the wrong point.
    ids, _ = _lattice((20, 20, 2))
    grid = EvaluationGrid(cell_size=0.5, ids=ids)
    lower, upper = np.flatnonzero(ids[:, 2] == 0), np.flatnonzero(ids[:, 2] == 1)
    order = np.concatenate([lower, upper[::-1]])
    full = prefix_selection(grid, order)
    for count in (1, 3, 4, 5, 40, 399, 400, 401, 800):
        np.testing.assert_array_equal(spread_prefix_selection(grid, _PartialRanking(order))(count), full(count))


def test_the_placement_is_the_same_with_a_partial_ranking(medium_capture: Capture) -> None:
    scores = np.random.default_rng(1).uniform(size=medium_capture.point_count).astype(np.float32)
    for policy in ({"budget": 0.05}, {"budget": 0.3}, {"tolerance": 0.05}, {"tolerance": 0.01}):
        whole = lpnn_placement(medium_capture, scores=scores, **policy)
        part = lpnn_placement(medium_capture, scores=scores, full_ranking=False, **policy)
        np.testing.assert_array_equal(part.indices, whole.indices)
        assert part.checked == whole.checked and part.requested == whole.requested
        np.testing.assert_array_equal(part.ranking, whole.ranking[:part.ranking.shape[0]])
