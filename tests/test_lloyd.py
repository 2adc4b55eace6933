"""Weighted Lloyd iterations (uniform2d.optimize.lloyd): the density's power decides
how the cells follow the size (a centroidal Voronoi tessellation of density ρ has
cells of diameter about ρ^(-1/4)), checked on the triangulation of the result."""

from __future__ import annotations

import numpy as np

from uniform2d import Polygon, SizeField
from uniform2d.geometry import unique_edges
from uniform2d.insert import insert
from uniform2d.optimize.lloyd import weighted_lloyd
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate

STRIP = Polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
ITER = 400  # Lloyd redistributes over long distances slowly
FIELD = SizeField([0, 4], [0, 1], [[0.05, 0.45], [0.05, 0.45]])  # h = 0.05 + 0.1 x


def _slope(power: int) -> float:
    """Least-squares slope of log(edge length / h(midpoint)) against log h over the
    interior edges after Lloyd: 0 when the cells follow h."""
    start = insert(STRIP, 400, size=FIELD).points[len(STRIP.vertices):]
    on = (start[:, 1] <= 0) | (start[:, 1] >= 1) | (start[:, 0] <= 0) | (start[:, 0] >= 4)
    moved = weighted_lloyd(STRIP, start, on, FIELD, iterations=ITER, omega=1.8, power=power)
    assert np.array_equal(moved[on], start[on])
    P, T = triangulate(STRIP, moved, None)
    E = unique_edges(T)
    mid = 0.5 * (P[E[:, 0]] + P[E[:, 1]])
    inner = (mid[:, 1] > 0.15) & (mid[:, 1] < 0.85) & (mid[:, 0] > 0.3) & (mid[:, 0] < 3.7)
    h = FIELD(mid[inner])
    q = np.linalg.norm(P[E[inner, 0]] - P[E[inner, 1]], axis=1) / h
    return float(np.polyfit(np.log(h), np.log(q), 1)[0])


def test_density_power_four_follows_the_size():
    s2, s4 = _slope(2), _slope(4)
    # with 1 / h² the edges grow like sqrt(h): q falls where h is large
    assert s2 < -0.15
    assert abs(s4) < 0.5 * abs(s2)


def _reference_centroids(P, T, field, power):
    """The cells' weighted centroids in plain numpy, sub-triangle by sub-triangle."""
    num = np.zeros((len(P), 2))
    den = np.zeros(len(P))
    for tri in T:
        a, b, c = P[tri]
        d = 2 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]))
        sa, sb, sc = a @ a, b @ b, c @ c
        cc = np.array([sa * (b[1] - c[1]) + sb * (c[1] - a[1]) + sc * (a[1] - b[1]),
                       sa * (c[0] - b[0]) + sb * (a[0] - c[0]) + sc * (b[0] - a[0])]) / d
        for k in range(3):
            v, w1, w2 = tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]
            p = P[v]
            for x, y in ((0.5 * (p + P[w1]), cc), (cc, 0.5 * (p + P[w2]))):
                g = (p + x + y) / 3
                area = 0.5 * ((x[0] - p[0]) * (y[1] - p[1]) - (x[1] - p[1]) * (y[0] - p[0]))
                w = area / field(g[None])[0] ** power
                num[v] += w * g
                den[v] += w
    return num / den[:, None]


def test_compiled_centroids_match_numpy():
    from uniform2d._kernel.cells import weighted_centroids

    start = insert(STRIP, 60, size=FIELD).points[len(STRIP.vertices):]
    P, T = triangulate(STRIP, start, None)
    got = weighted_centroids(P, T, FIELD.x, FIELD.y, FIELD.values, 4)
    assert np.allclose(got, _reference_centroids(P, T, FIELD, 4), rtol=1e-12, atol=1e-12)
    # a vertex in no triangle has no centroid
    lone = weighted_centroids(np.vstack([P, [[9.0, 9.0]]]), T, FIELD.x, FIELD.y, FIELD.values, 4)
    assert np.isnan(lone[-1]).all() and np.isfinite(lone[:-1]).all()


def test_lloyd_is_deterministic_and_keeps_fixed_points():
    start = insert(STRIP, 200, size=FIELD).points[len(STRIP.vertices):]
    on = (start[:, 1] <= 0) | (start[:, 1] >= 1) | (start[:, 0] <= 0) | (start[:, 0] >= 4)
    a = weighted_lloyd(STRIP, start, on, FIELD, iterations=10, power=4)
    b = weighted_lloyd(STRIP, start, on, FIELD, iterations=10, power=4)
    assert a.tobytes() == b.tobytes()
    assert np.array_equal(a[on], start[on]) and not np.array_equal(a[~on], start[~on])


def test_lloyd_in_the_kernel_is_lloyd_with_a_fresh_triangulation_each_time():
    """The kernel moves the points and flips (no rebuild); the reference triangulates
    anew every iteration and takes the numpy centroids: the same sites (from the
    graded rows, whose points keep off the boundary: no move is refused)."""
    from uniform2d.graded import boundary_sites
    from uniform2d.grading import scale_for_count
    from uniform2d.optimize.packing import rows_start

    s = scale_for_count(STRIP, FIELD, 150)
    b, e = boundary_sites(STRIP, FIELD, s, 150)
    start, on = rows_start(STRIP, 150, FIELD, s, b, e)
    got = weighted_lloyd(STRIP, start, on, FIELD, iterations=8, omega=1.5, power=4)
    S = start.copy()
    for _ in range(8):
        P, T = triangulate(STRIP, S, None)
        c = _reference_centroids(P, T, FIELD, 4)[len(STRIP.vertices):]
        S[~on] += 1.5 * (c[~on] - S[~on])
    assert np.allclose(got, S, rtol=0, atol=1e-9)
    assert np.array_equal(got[on], start[on])
    P, T = triangulate(STRIP, got, None)
    check_mesh(P, T, STRIP, n_steiner=150)


def test_compiled_grid_size_is_the_fields_bilinear():
    """The cells' lookup (one point, and the batched grid_sizes) starts from where a
    point would be on an even grid: on an uneven one, and outside the grid
    (clamped), the very values of SizeField."""
    from numba import njit

    from uniform2d._kernel.cells import grid_size, grid_sizes

    @njit
    def sizes(gx, gy, gv, P):
        out = np.empty(len(P))
        for k in range(len(P)):
            out[k] = grid_size(gx, gy, gv, P[k, 0], P[k, 1])
        return out

    rng = np.random.default_rng(7)
    for x in (np.linspace(-1.0, 3.0, 41), np.array([-1.0, -0.9, 0.0, 0.05, 2.0, 3.0])):
        y = np.array([0.0, 0.1, 0.15, 1.0, 4.0])
        f = SizeField(x, y, rng.uniform(0.1, 2.0, (len(y), len(x))))
        P = np.column_stack([rng.uniform(-2, 4, 2000), rng.uniform(-1, 5, 2000)])
        P = np.vstack([P, np.column_stack([np.repeat(x, len(y)), np.tile(y, len(x))])])
        assert sizes(f.x, f.y, f.values, P).tobytes() == f(P).tobytes()
        assert grid_sizes(f.x, f.y, f.values, P).tobytes() == f(P).tobytes()
