"""A large start's lattice comes out a few points short and is filled in the
boundary band (:func:`uniform2d.optimize.fill.fill_band_gaps`): exactly n
sites, inside the polygon and not crowded, the same gaps as filling over the
whole seed would choose, and at a cut of equal gaps evenly spaced ones."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

from support.benchmarks import benchmark_polygons
from uniform2d.testing.polygons import with_holes
from uniform2d.optimize import lattice_seed, schedule, seed
from uniform2d.optimize.boundary import target_size
from uniform2d.optimize.fill import _largest_spread
from uniform2d.optimize.fill import fill_band_gaps as _fill_band_gaps
from uniform2d.optimize.fill import fill_largest_gaps as _fill_largest_gaps
from uniform2d.optimize.rows import keep_clear as _keep_clear


def test_largest_spread_takes_the_larger_then_evenly_spaced_equal_ones():
    # one gap larger than all, ten equal ones in a line, the rest smaller
    area = np.array([0.5] * 5 + [1.0] * 10 + [2.0] + [0.5] * 5)
    c = np.stack([np.arange(len(area), dtype=float)[::-1], np.zeros(len(area))], 1)
    got = _largest_spread(area, c, 5)
    assert len(set(got.tolist())) == 5
    assert 15 in got and (area[got] >= 1.0).all()
    xs = np.sort(c[got[got != 15], 0])
    assert np.diff(xs).min() >= 2.0  # no two neighbours of the run of ten


@pytest.mark.parametrize("k", range(4))
def test_large_start_has_exactly_n_sites_inside_and_uncrowded(k, monkeypatch):
    p = [benchmark_polygons()["square2holes"], with_holes(11), with_holes(12), benchmark_polygons()["star10"]][k]
    n = 3000
    monkeypatch.setattr(schedule, "LARGE", 0)  # the large path at a size a test can afford
    h = target_size(p, n)
    sites, edges, frozen, nb = seed.start(p, n, h, seed.variants(p, n)[0])
    assert len(sites) == n
    inner = sites[nb:]  # after the points on the boundary
    assert shapely.contains_xy(p.to_shapely(), inner[:, 0], inner[:, 1]).all()
    d, _ = cKDTree(sites).query(sites, 2)
    assert d[:, 1].min() >= 0.3 * h


@pytest.mark.parametrize("name", ["square", "square2holes", "star10"])
def test_band_fill_chooses_gaps_as_large_as_the_whole_seed_fill(name):
    # a lattice with points taken out near the boundary (the band) and deep
    # inside is not asked for: the band fill adds as many, in gaps whose sizes
    # are those the fill over the whole triangulated seed takes
    p = benchmark_polygons()[name]
    n = 2000
    h = target_size(p, n)
    P = lattice_seed(p, n)
    sa, sb = _keep_clear(p)
    from uniform2d._kernel.distance import to_segments
    near = np.flatnonzero(to_segments(P, sa, sb, 3 * h) < 2 * h)
    P = np.delete(P, near[:: max(1, len(near) // 15)], axis=0)
    bpts = np.empty((0, 2))
    band = _fill_band_gaps(p, bpts, P, n, h, sa, sb)
    whole = _fill_largest_gaps(p, bpts, P, n)
    assert len(band) == len(whole) == n
    nn = lambda Q: np.sort(cKDTree(Q).query(Q[len(P):], 2)[0][:, 1])  # noqa: E731
    np.testing.assert_allclose(nn(band), nn(whole), rtol=1e-6)
