"""Lloyd's iterations on the kernel's mesh (:mod:`uniform2d.optimize.lloyd`): the
weighted centroids of the Voronoi cells within the mesh, one compiled pass over
the triangles, and the moves towards them.

The moves are the spring rounds' (:mod:`.spring`): all free vertices at once,
those that would invert a triangle undone (exact), then Lawson flips make the
mesh the constrained Delaunay triangulation of its points again (see
:mod:`.relax`), so no iteration builds a triangulation afresh.
"""

import numpy as np
from ._jit import njit

from .cdt import snap
from .rank import bilinear
from .spring import _commit
from .star import FREE, legalize_live, live_slots

__all__ = ["grid_size", "grid_sizes", "lloyd", "weighted_centroids"]


@njit(cache=True, inline="always")
def _per(g):
    """Cells per unit length of the grid g were it even: :func:`_cell`'s first guess."""
    return (g.shape[0] - 1) / (g[-1] - g[0])


@njit(cache=True, inline="always")
def _cell(g, x, per):
    """The largest i <= len(g) - 2 with g[i] <= x (0 if none), for sorted g: what
    :func:`.rank._right_of` minus one, clamped, gives, found from where x would be
    on an even grid (the fields' grids are; others take a few more steps);
    ``per`` is :func:`_per` of g (a loop over many points computes it once)."""
    last = g.shape[0] - 2
    i = int((x - g[0]) * per)
    i = min(max(i, 0), last)
    while i > 0 and g[i] > x:
        i -= 1
    while i < last and g[i + 1] <= x:
        i += 1
    return i


@njit(cache=True, inline="always")
def grid_size(gx, gy, gv, x, y):
    """The size field on the grid (gx, gy, gv) at (x, y): bilinear, clamped; the
    formula of :func:`.rank.size_at` and ``uniform2d.sizefield`` on bare arrays."""
    return _size(gx, gy, gv, _per(gx), _per(gy), x, y)


@njit(cache=True, inline="always")
def _size(gx, gy, gv, perx, pery, x, y):
    """:func:`grid_size` with the grid's :func:`_per` known."""
    x = min(max(x, gx[0]), gx[-1])
    y = min(max(y, gy[0]), gy[-1])
    return bilinear(gx, gy, gv, _cell(gx, x, perx), _cell(gy, y, pery), x, y)


@njit(cache=True)
def grid_sizes(gx, gy, gv, p):
    """(k,) :func:`grid_size` at each of the points p (k, 2), C-contiguous: the
    values of ``uniform2d.sizefield.SizeField`` without numpy's per-call cost
    (the graded start evaluates the field a few dozen times a round on small
    arrays)."""
    out = np.empty(p.shape[0])
    perx, pery = _per(gx), _per(gy)
    for k in range(p.shape[0]):
        out[k] = _size(gx, gy, gv, perx, pery, p[k, 0], p[k, 1])
    return out


@njit(cache=True, inline="always")
def _sub(px, py, ax, ay, bx, by, gx, gy, gv, perx, pery, power):
    """The sub-triangle (p, a, b) of a cell: (its signed area times 1 / h**power at
    its centroid, the centroid's x, y).  Power 4, the graded path's, multiplied
    out: numba's integer power computes h**4 as the same (h * h) * (h * h), in a
    loop that cost the pass a sixth of its time."""
    cx = (px + ax + bx) / 3.0
    cy = (py + ay + by) / 3.0
    area = 0.5 * ((ax - px) * (by - py) - (ay - py) * (bx - px))
    h = _size(gx, gy, gv, perx, pery, cx, cy)
    if power == 4:
        h2 = h * h
        return area / (h2 * h2), cx, cy
    return area / h ** power, cx, cy


@njit(cache=True, error_model="numpy")
def weighted_centroids(xy, tri, gx, gy, gv, power):
    """(N, 2) centroid of every vertex's Voronoi cell within the mesh (xy (N, 2),
    tri (M, 3)) for the density 1 / h**power, h the grid (gx, gy, gv).

    The cell of v within triangle (v, a, b) is the two triangles
    (v, mid(v, a), c) and (v, c, mid(v, b)), c the circumcentre, with signed
    areas (obtuse triangles add up right).  NaN for a vertex in no triangle.
    """
    return _centroids(xy, xy.shape[0], tri.ravel(), tri.shape[0], gx, gy, gv, power)


@njit(cache=True, error_model="numpy")
def _centroids(xy, n, tv, nt, gx, gy, gv, power):
    """:func:`weighted_centroids` of the first n points and the nt triangles of
    the flat vertex list tv (3 per triangle)."""
    num = np.zeros((n, 2))
    den = np.zeros(n)
    perx, pery = _per(gx), _per(gy)
    for t in range(nt):
        a, b, c = tv[3 * t], tv[3 * t + 1], tv[3 * t + 2]
        bx, by = xy[b, 0] - xy[a, 0], xy[b, 1] - xy[a, 1]
        cx, cy = xy[c, 0] - xy[a, 0], xy[c, 1] - xy[a, 1]
        d = 2.0 * (bx * cy - by * cx)
        bb, cc = bx * bx + by * by, cx * cx + cy * cy
        ox = xy[a, 0] + (cy * bb - by * cc) / d
        oy = xy[a, 1] + (bx * cc - cx * bb) / d
        for k in range(3):
            v, w1, w2 = (a, b, c) if k == 0 else ((b, c, a) if k == 1 else (c, a, b))
            px, py = xy[v, 0], xy[v, 1]
            m1x, m1y = 0.5 * (px + xy[w1, 0]), 0.5 * (py + xy[w1, 1])
            m2x, m2y = 0.5 * (px + xy[w2, 0]), 0.5 * (py + xy[w2, 1])
            wa, sax, say = _sub(px, py, m1x, m1y, ox, oy, gx, gy, gv, perx, pery, power)
            wb, sbx, sby = _sub(px, py, ox, oy, m2x, m2y, gx, gy, gv, perx, pery, power)
            # both halves added in turn (the sums' order of one at a time), stored once
            num[v, 0] = (num[v, 0] + wa * sax) + wb * sbx
            num[v, 1] = (num[v, 1] + wa * say) + wb * sby
            den[v] = (den[v] + wa) + wb
    out = np.empty((n, 2))
    for v in range(n):
        out[v, 0] = num[v, 0] / den[v]
        out[v, 1] = num[v, 1] / den[v]
    return out


@njit(cache=True, error_model="numpy")
def lloyd(m, role, gx, gy, gv, power, iters, omega):
    """``iters`` Lloyd iterations on the Tri ``m``: every FREE vertex (``role``)
    moves ``omega`` times the way to its cell's centroid for the density
    1 / h**power (h the grid (gx, gy, gv), in the Tri's coordinates), all at
    once; a move that would invert a triangle is undone with the others of that
    triangle, and the mesh is legalised.  Returns the moves made."""
    n = m.nv
    xy = m.xy
    alive, slots, movers = live_slots(m, role, False)
    new = np.empty((n, 2))
    newt = np.zeros(n)
    hv = np.ones(n)
    moved = np.zeros(n, np.bool_)
    todo = np.empty(64, np.int32)
    made = 0
    for _ in range(iters):
        C = _centroids(xy, n, m.tv, m.nt, gx, gy, gv, power)
        for v in movers:
            moved[v] = False
            if role[v] != FREE or not (np.isfinite(C[v, 0]) and np.isfinite(C[v, 1])):
                continue
            x = xy[v, 0] + omega * (C[v, 0] - xy[v, 0])
            y = xy[v, 1] + omega * (C[v, 1] - xy[v, 1])
            new[v, 0], new[v, 1] = snap(m, x, y)
            moved[v] = new[v, 0] != xy[v, 0] or new[v, 1] != xy[v, 1]
        _commit(m, role, newt, new, newt, moved, hv, 0.0, slots, movers)
        for v in movers:
            if moved[v]:
                made += 1
        todo, slots, _, _, _ = legalize_live(m, moved, todo, alive, slots, todo, np.int64(-1))
    return made
