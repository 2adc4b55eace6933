"""Nearness in a bucket grid (uniform2d._kernel.clearance) against the k-d
tree queries it stands in for: which points have none of a set nearer than r
(``cKDTree(R).query(P, distance_upper_bound=r)[0] >= r``) on random points, on
lattices with points at exactly r (ties), far outside the set's box and with
an empty set; the closest pair (``cKDTree(P).query(P, k=2)``), INSERT's d_n
included."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from uniform2d._kernel.clearance import bucket_grid, closest_pair, none_within


def _both(P, R, r, cell):
    grid = bucket_grid(R, cell)
    x0, y0, nx, ny, start, order = grid
    ours = none_within(P, R, x0, y0, cell, nx, ny, start, order, r)
    if len(R) == 0:
        return ours, np.ones(len(P), bool)
    return ours, cKDTree(R).query(P, distance_upper_bound=r)[0] >= r


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("r", [0.05, 0.1, 0.3])
def test_random_points_as_the_tree(seed, r):
    rng = np.random.default_rng(seed)
    R = rng.random((300, 2))
    P = rng.random((2000, 2)) * 1.4 - 0.2  # some outside R's box
    ours, tree = _both(P, R, r, 0.12)  # r above the bucket side too (0.3)
    assert ours.dtype == bool and np.array_equal(ours, tree)
    assert 0 < ours.sum() < len(P) or r == 0.3


def test_ties_at_exactly_r():
    # points of an even integer lattice; the odd midpoints between two of them
    # lie at exactly 1 from both
    g = np.arange(-6.0, 7.0, 2.0)
    R = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    P = R + np.array([[1.0, 0.0]])
    for r in (1.0, np.nextafter(1.0, 2.0), np.sqrt(2.0), 0.999):
        ours, tree = _both(P, R, r, 1.2)
        assert np.array_equal(ours, tree)
    assert _both(P, R, 1.0, 1.2)[0].all()  # at exactly r is not nearer than r
    assert not _both(P, R, np.nextafter(1.0, 2.0), 1.2)[0].any()


def test_far_and_empty():
    R = np.array([[0.0, 0.0], [1.0, 1.0]])
    P = np.array([[1e6, -1e6], [0.5, 0.5], [-50.0, 0.0]])
    ours, tree = _both(P, R, 1.0, 1.2)
    assert np.array_equal(ours, tree) and ours.tolist() == [True, False, True]
    ours, _ = _both(P, np.empty((0, 2)), 1.0, 1.2)
    assert ours.all()


def _tree_min(P):
    return float(cKDTree(P).query(P, k=2)[0][:, 1].min())


@pytest.mark.parametrize("seed", range(5))
def test_closest_pair_as_the_tree(seed):
    rng = np.random.default_rng(seed)
    P = rng.random((500, 2)) * np.array([4.0, 1.0])
    d2, certain = closest_pair(P, 0.1)
    assert certain and np.sqrt(d2) == _tree_min(P)
    # a duplicate point: distance 0
    Q = np.concatenate([P, P[7:8]])
    assert closest_pair(Q, 0.1) == (0.0, True)
    # buckets too small to tell: not certain (the caller asks the tree)
    d2, certain = closest_pair(P[:20], 1e-4)
    assert not certain


def test_min_distance_after_as_the_tree():
    from uniform2d import Polygon, insert
    from uniform2d.insert import min_distance_after

    sq = Polygon([(0, 0), (3, 0), (3, 1), (0, 1)])
    for n in (1, 30, 400):
        r = insert(sq, n)
        assert min_distance_after(sq, n) == r.min_distance() == _tree_min(r.mesh_points)
