"""The spread ranking (selection.md "Spread ranking"): the fast exact implementation equals the plain
O(N^2) argmax loop of the spec, tie for tie, and Tests/Data/spread_golden.json pins it for C#."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.features import D14
from lpnn.core.spread import (SCORE_FLOOR, SpreadError, extreme_seeds, farthest_point_ranking, spread_ranking,
                              spread_weights)


# ------------------------------------------------------------------ the spec, written as plainly as possible

def naive_weights(scores: np.ndarray, exponent: float = 0.5) -> np.ndarray:
    s = np.asarray(scores, dtype=np.float64)
    s = np.where(np.isnan(s), SCORE_FLOOR, np.clip(s, SCORE_FLOOR, 1.0))
    ratio = s / float(np.median(s))
    return np.sqrt(ratio) if exponent == 0.5 else ratio**exponent


def naive_distance(points: np.ndarray, i: int) -> np.ndarray:
    d = points - points[i]
    return np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2])


def naive_farthest(points: np.ndarray, weights: np.ndarray, seeds: list[int]) -> np.ndarray:
    points = np.asarray(points, dtype=np.float64)
    n = points.shape[0]
    order = list(dict.fromkeys(int(s) for s in seeds)) or ([0] if n else [])
    distance = np.full(n, np.inf)
    chosen = np.zeros(n, dtype=bool)
    for s in order:
        distance = np.minimum(distance, naive_distance(points, s))
        chosen[s] = True
    while len(order) < n:
        key = weights * distance
        key[chosen] = -1.0
        p = int(np.argmax(key))  # the first maximum: ties to the lower index
        order.append(p)
        chosen[p] = True
        distance = np.minimum(distance, naive_distance(points, p))
    return np.asarray(order, dtype=np.int64)


def naive_spread(positions: np.ndarray, scores: np.ndarray, exponent: float = 0.5) -> np.ndarray:
    p = np.asarray(positions, dtype=np.float64)
    seeds = [int(np.argmax(p[:, 0] * d[0] + p[:, 1] * d[1] + p[:, 2] * d[2])) for d in D14] if p.shape[0] else []
    return naive_farthest(p, naive_weights(scores, exponent), seeds)


def lattice(nx: int, ny: int, nz: int, spacing: float = 1.0, origin=(0.0, 0.0, 0.0)) -> np.ndarray:
    """float32 lattice positions in grid order (x fastest), as grid.positions computes them."""
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    ids = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.float64)
    return (ids * spacing + np.asarray(origin)).astype(np.float32)


def assert_same(positions: np.ndarray, scores: np.ndarray, exponent: float = 0.5) -> np.ndarray:
    fast = spread_ranking(positions, scores, exponent)
    np.testing.assert_array_equal(fast, naive_spread(positions, scores, exponent))
    np.testing.assert_array_equal(np.sort(fast), np.arange(positions.shape[0]))
    return fast


# -------------------------------------------------------------------------------------------- tests

@pytest.mark.parametrize("seed", range(6))
def test_equals_the_naive_loop_on_random_irregular_sets(seed: int) -> None:
    rng = np.random.default_rng(seed)
    for n in (5, 17, 60, 250):
        positions = rng.normal(size=(n, 3)).astype(np.float32) * np.float32(rng.uniform(0.1, 10.0))
        assert_same(positions, rng.uniform(0.0, 1.0, n).astype(np.float32))


@pytest.mark.parametrize("scores_kind", ["equal", "repeated", "random", "binary"])
@pytest.mark.parametrize("shape,spacing", [((5, 4, 3), 1.0), ((6, 6, 6), 0.28), ((9, 3, 2), 0.5), ((7, 7, 1), 1.0)])
def test_equals_the_naive_loop_on_lattices_where_distances_tie(shape, spacing, scores_kind: str) -> None:
    positions = lattice(*shape, spacing=spacing)
    n = positions.shape[0]
    rng = np.random.default_rng(n)
    scores = {"equal": np.full(n, 0.7), "repeated": rng.choice([0.2, 0.5, 0.9], n),
              "random": rng.uniform(0.0, 1.0, n), "binary": rng.choice([0.0, 1.0], n)}[scores_kind]
    assert_same(positions, scores.astype(np.float32))


def test_equals_the_naive_loop_on_a_lattice_large_enough_for_every_batch_and_tree_level() -> None:
    positions = lattice(20, 15, 12, spacing=0.5)  # 3,600 points: several hierarchy levels, full batches
    rng = np.random.default_rng(7)
    assert_same(positions, np.full(positions.shape[0], 0.5, dtype=np.float32))
    assert_same(positions, rng.choice([0.1, 0.4, 1.0], positions.shape[0]).astype(np.float32))
    smooth = 0.5 + 0.5 * np.sin(positions[:, 0]) * np.cos(positions[:, 1] / 2.0)  # spatially varying weights
    assert_same(positions, smooth.astype(np.float32))


def test_special_scores_nan_zero_one_and_out_of_range() -> None:
    positions = lattice(4, 4, 3)
    n = positions.shape[0]
    scores = np.tile(np.array([np.nan, 0.0, 1.0, 0.5, -3.0, 7.0, np.inf, -np.inf], dtype=np.float32), n // 8)
    ranking = assert_same(positions, scores)
    np.testing.assert_array_equal(ranking, spread_ranking(positions, np.nan_to_num(scores, nan=0.0)))  # NaN = 0
    assert_same(positions, np.full(n, np.nan, dtype=np.float32))


def test_tiny_sets_coplanar_sets_and_duplicates() -> None:
    rng = np.random.default_rng(3)
    for n in (1, 2, 3, 4):
        positions = rng.normal(size=(n, 3)).astype(np.float32)
        assert_same(positions, rng.uniform(0, 1, n).astype(np.float32))
    assert spread_ranking(np.zeros((0, 3), dtype=np.float32), np.zeros(0)).shape == (0,)
    assert_same(lattice(6, 5, 1, spacing=0.3), rng.uniform(0, 1, 30).astype(np.float32))  # one plane
    assert_same(lattice(12, 1, 1), np.ones(12, dtype=np.float32))  # one line
    tilted = rng.normal(size=(40, 2)) @ np.array([[1.0, 2.0, -1.0], [0.5, -1.0, 3.0]])  # a slanted plane
    assert_same(tilted.astype(np.float32), rng.uniform(0, 1, 40).astype(np.float32))
    doubled = np.concatenate([lattice(3, 3, 2), lattice(3, 3, 2)])  # every position twice
    assert_same(doubled, rng.uniform(0, 1, 36).astype(np.float32))


def test_far_from_the_origin_and_exponents() -> None:
    rng = np.random.default_rng(11)
    positions = lattice(6, 5, 4, spacing=0.25, origin=(10000.0, -2500.0, 731.0))
    scores = rng.uniform(0, 1, positions.shape[0]).astype(np.float32)
    for exponent in (0.0, 0.5, 1.0, 2.0):
        assert_same(positions, scores, exponent)


def test_seeds_are_the_d14_extremes_in_order_with_lower_index_ties() -> None:
    positions = lattice(3, 3, 3)  # index = i + 3 j + 9 k
    # +x: (2,0,0)=2; -x: 0; +y: (0,2,0)=6; -y: 0; +z: (0,0,2)=18; -z: 0; then the corners
    # (+++)=26, (++-)=8, (+-+)=20, (+--)=2, (-++)=24, (-+-)=6, (--+)=18, (---)=0: repeats dropped.
    np.testing.assert_array_equal(extreme_seeds(positions), [2, 0, 6, 18, 26, 8, 20, 24])
    ranking = spread_ranking(positions, np.ones(27, dtype=np.float32))
    np.testing.assert_array_equal(ranking[:8], [2, 0, 6, 18, 26, 8, 20, 24])
    assert ranking[8] == 13  # then the centre, farthest from every corner


def test_weights_follow_the_spec() -> None:
    np.testing.assert_allclose(spread_weights(np.array([0.25, 1.0, 4.0])), [0.5, 1.0, 1.0])  # clipped at 1, median 1
    even = spread_weights(np.array([0.1, 0.2, 0.3, 0.5]))  # median = (0.2 + 0.3) / 2
    np.testing.assert_allclose(even, np.sqrt(np.array([0.1, 0.2, 0.3, 0.5]) / 0.25))
    floor = spread_weights(np.array([np.nan, 0.0, -1.0, 1e-6]))
    np.testing.assert_array_equal(floor, [1.0, 1.0, 1.0, 1.0])  # all at the floor: median 1e-6
    np.testing.assert_array_equal(spread_weights(np.array([0.3, 0.9]), 0.0), [1.0, 1.0])


def test_weighting_pulls_probes_towards_high_scores() -> None:
    positions = lattice(10, 10, 10)
    scores = np.where(positions[:, 0] < 5, 1.0, 0.01).astype(np.float32)
    ranking = spread_ranking(positions, scores)
    first = ranking[:200]
    assert np.count_nonzero(positions[first, 0] < 5) > 0.7 * first.shape[0]
    plain = spread_ranking(positions, scores, exponent=0.0)
    assert abs(np.count_nonzero(positions[plain[:200], 0] < 5) - 100) < 20


def test_farthest_point_ranking_with_given_seeds_equals_the_naive_loop() -> None:
    rng = np.random.default_rng(5)
    positions = lattice(7, 6, 5, spacing=0.5)
    weights = rng.uniform(0.5, 2.0, positions.shape[0])
    for seeds in ([], [3], [17, 3, 17, 40], list(range(0, 210, 7))):
        np.testing.assert_array_equal(farthest_point_ranking(positions, weights, np.asarray(seeds, dtype=np.int64)),
                                      naive_farthest(positions, weights, seeds))
    zero = np.where(np.arange(positions.shape[0]) % 3 == 0, 0.0, 1.0)  # weight 0: after every positive key
    np.testing.assert_array_equal(farthest_point_ranking(positions, zero, np.array([5])),
                                  naive_farthest(positions, zero, [5]))


def test_bad_inputs_name_the_value() -> None:
    positions = lattice(3, 3, 3)
    with pytest.raises(SpreadError, match=r"\(N, 3\)"):
        spread_ranking(positions[:, :2], np.ones(27))
    bad = positions.copy()
    bad[4, 1] = np.nan
    with pytest.raises(SpreadError, match="position 4"):
        spread_ranking(bad, np.ones(27))
    with pytest.raises(SpreadError, match="26 scores for 27 positions"):
        spread_ranking(positions, np.ones(26))
    with pytest.raises(SpreadError, match="exponent"):
        spread_ranking(positions, np.ones(27), exponent=-1.0)
    with pytest.raises(SpreadError, match="seed index 27"):
        farthest_point_ranking(positions, np.ones(27), np.array([27]))
    with pytest.raises(SpreadError, match="weight 2"):
        farthest_point_ranking(positions, np.array([1.0, 1.0, -1.0] + [1.0] * 24), np.array([0]))


def test_the_golden_file_matches(golden) -> None:
    data = golden("spread_golden.json")
    assert len(data["cases"]) >= 5
    for case in data["cases"]:
        positions = np.asarray(case["positions"], dtype=np.float32)
        scores = np.asarray([np.nan if s is None else s for s in case["scores"]], dtype=np.float32)
        ranking = spread_ranking(positions, scores, case["exponent"])
        np.testing.assert_array_equal(ranking, case["ranking"], err_msg=case["name"])
        np.testing.assert_array_equal(ranking, naive_spread(positions, scores, case["exponent"]), err_msg=case["name"])
