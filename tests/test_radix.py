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


@pytest.mark.parametrize("seed", range(4))
def test_build_adjacency_pairs_half_edges_in_the_stable_order_of_their_keys(seed):
    """build_adjacency's twins: consecutive equal keys smaller * nv + larger in a
    stable sort of them are paired, the rest are boundary (twin -1), also with
    a vertex on many half-edges (its run is sorted another way) and with
    edges repeated (ties taken in index order)."""
    from numba import njit

    from uniform2d._kernel import adjacency, cdt

    @njit
    def twins(m):
        return m.tw[: 3 * m.nt].copy()

    rng = np.random.default_rng(seed)
    nv = 40
    tris = rng.integers(0, nv, (300, 3)).astype(np.int32)
    tris[:40, 0] = 0  # vertex 0 on many edges: a run longer than SHORT_RUN
    tris = tris[(tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2]) & (tris[:, 0] != tris[:, 2])]
    tris = np.ascontiguousarray(tris)
    m, _ = cdt.allocate(nv, len(tris))
    cdt.set_nv(m, nv)
    nb = adjacency.build_adjacency(m, tris)
    u = tris.astype(np.int64).ravel()
    v = tris[:, [1, 2, 0]].astype(np.int64).ravel()
    keys = np.minimum(u, v) * nv + np.maximum(u, v)
    order = np.argsort(keys, kind="mergesort")
    want = np.full(len(keys), -1)
    i = 0
    while i < len(order):
        if i + 1 < len(order) and keys[order[i]] == keys[order[i + 1]]:
            want[order[i]], want[order[i + 1]] = order[i + 1], order[i]
            i += 2
        else:
            i += 1
    assert np.count_nonzero(np.bincount(np.minimum(u, v)) > adjacency.SHORT_RUN) >= 1
    assert np.array_equal(twins(m), want)
    assert nb == np.count_nonzero(want < 0)
