"""The seeding's point-to-segment distance: bucketed search against brute force."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from uniform2d._kernel.distance import BRUTE_MAX, to_segments


def reference(P, a, b, cap=np.inf):
    """numpy, all pairs, the kernel's formula (same operations, same rounding)."""
    d = b - a
    L2 = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]
    px, py = P[:, None, 0], P[:, None, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        s = ((px - a[:, 0]) * d[:, 0] + (py - a[:, 1]) * d[:, 1]) / L2
    s = np.where(L2 > 0, s, 0.0)
    s = np.minimum(np.maximum(s, 0.0), 1.0)
    qx = a[:, 0] + s * d[:, 0] - px
    qy = a[:, 1] + s * d[:, 1] - py
    return np.minimum(np.sqrt((qx * qx + qy * qy).min(axis=1)), cap)


def ring(m, scale=1.0, shift=0.0):
    t = np.linspace(0.0, 2.0 * np.pi, m, endpoint=False)
    a = np.stack([np.cos(t), np.sin(t) * 0.6 + 0.3 * np.sin(3 * t)], axis=1) * scale + shift
    return a, np.roll(a, -1, axis=0)


@pytest.mark.parametrize("scale,shift", [(1.0, 0.0), (1e-6, 0.0), (1e6, 0.0), (1.0, 1e6)])
@pytest.mark.parametrize("cap", [0.0, 0.02, 0.3, np.inf])
def test_bucketed_search_returns_the_brute_force_bits(scale, shift, cap):
    rng = np.random.default_rng(7)
    a, b = ring(300, scale, shift)
    b[::17] = a[::17]  # zero-length segments
    lo, hi = a.min(axis=0), a.max(axis=0)
    P = rng.uniform(lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo), size=(2500, 2))
    P[:50] = a[:50]  # on segment ends
    P[50:100] = 0.5 * (a[100:150] + b[100:150])  # on segments
    got = to_segments(P, a, b, cap * scale)
    np.testing.assert_array_equal(got, reference(P, a, b, cap * scale))
    if cap == np.inf:  # and the geometry is right (GEOS, its own formula)
        parts = [
            shapely.Point(p) if np.array_equal(p, q) else shapely.LineString([p, q])
            for p, q in zip(a, b)
        ]
        want = shapely.distance(shapely.GeometryCollection(parts), shapely.points(P))
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-13 * np.abs(a).max())


def test_few_segments_and_degenerate_grids_take_the_brute_force():
    rng = np.random.default_rng(3)
    P = rng.normal(size=(500, 2))
    a, b = ring(BRUTE_MAX)
    np.testing.assert_array_equal(to_segments(P, a, b, 0.1), reference(P, a, b, 0.1))
    # all segments one point: a zero-size grid
    a = np.zeros((40, 2))
    np.testing.assert_array_equal(to_segments(P, a, a, 0.5), reference(P, a, a, 0.5))
