"""The kernel's radix argsort against numpy's stable sort."""

from __future__ import annotations

import numpy as np
import pytest

from uniform2d._kernel.radix import stable_argsort


@pytest.mark.parametrize(
    "n, top",
    [(0, 1), (1, 1), (1, 9), (7, 3), (1000, 10), (1000, 1000), (5000, 10**12), (300, 2**62), (64, 2**8)],
)
def test_stable_argsort_is_numpys_mergesort_order(n, top):
    rng = np.random.default_rng(n + top % 1000)
    keys = rng.integers(0, top, n, dtype=np.int64)
    got = stable_argsort(keys)
    assert got.dtype == np.int64
    assert np.array_equal(got, np.argsort(keys, kind="mergesort"))


def test_stable_argsort_keeps_ties_in_index_order_and_leaves_keys_alone():
    keys = np.array([5, 0, 5, 2**40, 0, 5, 2**40 - 1], dtype=np.int64)
    before = keys.copy()
    assert stable_argsort(keys).tolist() == [1, 4, 0, 2, 5, 6, 3]
    assert np.array_equal(keys, before)
