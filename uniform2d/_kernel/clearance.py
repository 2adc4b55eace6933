"""Nearness in a bucket grid: which points have none of a fixed set nearer
than a distance (:func:`none_within`), and the closest pair of a point set
(:func:`closest_pair`).

The optimiser's starts test some ten lattices a start against the rows placed
before them (:class:`uniform2d.optimize.lattice.Candidates`): a lattice point
stays only if no row point is nearer than ``r`` (three quarters of the
spacing tried).  A k-d tree's query costs some 15 microseconds a call before
the first point and 0.2 a point after; here the row points are put in a
bucket grid once (:func:`bucket_grid`) and each test reads the few buckets
around a point (:func:`none_within`).

The decision is the one of ``cKDTree.query(P, distance_upper_bound=r)[0] >=
r`` (scipy's k-d tree, p = 2, ``eps`` = 0): the squared distances are summed
as it sums them (``dx * dx + dy * dy``, either order: the same bits), a point
within the bound is one whose squared distance is below ``r * r``, and the
distance compared with ``r`` is the square root of the smallest.

:func:`closest_pair` stands in for ``cKDTree(P).query(P, k=2)[0][:, 1].min()``
(INSERT's d_n, some 1000 to 10000 points a mesh): the square root of the
smallest squared distance between two points, summed as the tree sums it, is
that minimum (the square root is monotone).
"""

import numpy as np

from ._jit import njit

__all__ = ["bucket_grid", "none_within", "clear_at", "closest_pair"]

#: Slack, in buckets, of the buckets a test reads beyond ``r``: the bucket
#: index of a point is rounded, and a point nearer than ``r`` must never be
#: missed.
SLACK = 0.01


@njit(cache=True)
def bucket_grid(R, cell):
    """The points R (k, 2) by bucket of a square grid of side ``cell``, from
    the lower left of their box: (x0, y0, nx, ny, start, order), the points of
    bucket (i, j) being ``order[start[j * nx + i]:start[j * nx + i + 1]]``."""
    k = R.shape[0]
    x0 = np.inf
    y0 = np.inf
    x1 = -np.inf
    y1 = -np.inf
    for a in range(k):
        x0 = min(x0, R[a, 0])
        y0 = min(y0, R[a, 1])
        x1 = max(x1, R[a, 0])
        y1 = max(y1, R[a, 1])
    if k == 0:
        x0, y0, x1, y1 = 0.0, 0.0, 0.0, 0.0
    nx = int((x1 - x0) / cell) + 1
    ny = int((y1 - y0) / cell) + 1
    which = np.empty(k, np.int64)
    start = np.zeros(nx * ny + 1, np.int64)
    for a in range(k):
        i = min(int((R[a, 0] - x0) / cell), nx - 1)
        j = min(int((R[a, 1] - y0) / cell), ny - 1)
        which[a] = j * nx + i
        start[which[a] + 1] += 1
    for b in range(nx * ny):
        start[b + 1] += start[b]
    fill = start[:-1].copy()
    order = np.empty(k, np.int64)
    for a in range(k):
        order[fill[which[a]]] = a
        fill[which[a]] += 1
    return x0, y0, nx, ny, start, order


@njit(cache=True)
def none_within(P, R, x0, y0, cell, nx, ny, start, order, r):
    """For each point of P (m, 2): whether no point of R (in the grid of
    :func:`bucket_grid`) is nearer than ``r`` (module docstring: the k-d tree's
    decision).  (m,) bool."""
    m = P.shape[0]
    out = np.ones(m, np.bool_)
    for a in range(m):
        out[a] = clear_at(P[a, 0], P[a, 1], R, x0, y0, cell, nx, ny, start, order, r)
    return out


@njit(cache=True, borrowed=True)
def clear_at(px, py, R, x0, y0, cell, nx, ny, start, order, r):
    """:func:`none_within` of the one point (px, py)."""
    r2 = r * r
    reach = int(r / cell + SLACK) + 1
    fi = np.floor((px - x0) / cell)
    fj = np.floor((py - y0) / cell)
    i0 = int(max(fi - reach, 0.0))
    i1 = int(min(fi + reach, nx - 1.0))
    j0 = int(max(fj - reach, 0.0))
    j1 = int(min(fj + reach, ny - 1.0))
    best = np.inf
    for j in range(j0, j1 + 1):
        for i in range(i0, i1 + 1):
            b = j * nx + i
            for s in range(start[b], start[b + 1]):
                q = order[s]
                dx = R[q, 0] - px
                dy = R[q, 1] - py
                best = min(best, dx * dx + dy * dy)
    return not (best < r2 and np.sqrt(best) < r)


#: :func:`closest_pair` is certain when the smallest squared distance it finds
#: is below (1 - CERTAIN) times the bucket side's square: every pair nearer
#: than that is in adjacent buckets, however their bucket indices round.
CERTAIN = 1e-6


@njit(cache=True)
def closest_pair(P, cell):
    """(the smallest squared distance between two points of P (k >= 2, (k, 2))
    in the same or adjacent buckets of side ``cell``, whether it is the
    smallest of all pairs): it is when it is below (1 - CERTAIN) cell**2;
    else the caller measures every pair another way."""
    x0, y0, nx, ny, start, order = bucket_grid(P, cell)
    best = np.inf
    for a in range(P.shape[0]):
        px = P[a, 0]
        py = P[a, 1]
        i = min(int((px - x0) / cell), nx - 1)
        j = min(int((py - y0) / cell), ny - 1)
        for jj in range(max(j - 1, 0), min(j + 1, ny - 1) + 1):
            for ii in range(max(i - 1, 0), min(i + 1, nx - 1) + 1):
                b = jj * nx + ii
                for s in range(start[b], start[b + 1]):
                    q = order[s]
                    if q != a:
                        dx = P[q, 0] - px
                        dy = P[q, 1] - py
                        best = min(best, dx * dx + dy * dy)
    return best, best < (1.0 - CERTAIN) * (cell * cell)
