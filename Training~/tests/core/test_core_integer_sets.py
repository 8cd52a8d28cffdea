"""core/integer_sets.py: np.unique's answers by sorting, element for element."""

import numpy as np
import pytest

from lpnn.core.integer_sets import sorted_contains, sorted_unique, sorted_unique_first_inverse


def _cases():
    rng = np.random.default_rng(7)
    yield np.zeros(0, dtype=np.int64)
    yield np.array([5], dtype=np.int64)
    yield np.array([3, 3, 3, 3], dtype=np.int64)  # all equal
    yield np.array([9, -2, 9, 0, -2, 7], dtype=np.int64)  # negatives, repeats out of order
    yield np.arange(1000, dtype=np.int64)[::-1].copy()  # distinct, descending
    yield rng.integers(0, 50, size=5000).astype(np.int32)  # many repeats, another width
    yield rng.integers(-(1 << 62), 1 << 62, size=20000)  # keys near the int64 range
    yield np.repeat(rng.integers(0, 1 << 40, size=300), 7)[rng.permutation(2100)]


@pytest.mark.parametrize("values", list(_cases()), ids=lambda v: f"{v.dtype}x{v.shape[0]}")
def test_sorted_unique_is_numpys_unique(values):
    got = sorted_unique(values)
    expected = np.unique(values)
    assert got.dtype == expected.dtype
    np.testing.assert_array_equal(got, expected)


@pytest.mark.parametrize("values", list(_cases()), ids=lambda v: f"{v.dtype}x{v.shape[0]}")
def test_first_and_inverse_are_numpys(values):
    keys, first, inverse = sorted_unique_first_inverse(values)
    expected_keys, expected_first, expected_inverse = np.unique(values, return_index=True, return_inverse=True)
    np.testing.assert_array_equal(keys, expected_keys)
    np.testing.assert_array_equal(first, expected_first)  # the first occurrence of each value, as np.unique's
    np.testing.assert_array_equal(inverse, expected_inverse.reshape(-1))
    if values.shape[0]:
        np.testing.assert_array_equal(keys[inverse], values)  # the inverse rebuilds the input


@pytest.mark.parametrize("bad", [np.array([1.0, 2.0]), np.array([[1, 2], [3, 4]]), np.array([np.nan])])
def test_refuses_what_is_not_a_flat_integer_array(bad):
    with pytest.raises(ValueError, match="1-D integer array"):
        sorted_unique(bad)
    with pytest.raises(ValueError, match="1-D integer array"):
        sorted_unique_first_inverse(bad)


@pytest.mark.parametrize("values", list(_cases()), ids=lambda v: f"{v.dtype}x{v.shape[0]}")
def test_sorted_contains_is_numpys_isin(values):
    rng = np.random.default_rng(11)
    members = np.unique(values[: values.shape[0] // 2])
    probe = np.concatenate([values, rng.integers(-60, 60, size=40).astype(values.dtype)])
    np.testing.assert_array_equal(sorted_contains(probe, members), np.isin(probe, members))
    assert not sorted_contains(probe, members[:0]).any()  # an empty set holds nothing (no index error)
