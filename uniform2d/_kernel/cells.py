"""Weighted centroids of the Voronoi cells within a mesh: the step of Lloyd's
iterations (:mod:`uniform2d.optimize.lloyd`), one compiled pass over the triangles.
"""

import numpy as np
from ._jit import njit

from .rank import _right_of

__all__ = ["grid_size", "weighted_centroids"]


@njit(cache=True, inline="always")
def grid_size(gx, gy, gv, x, y):
    """The size field on the grid (gx, gy, gv) at (x, y): bilinear, clamped; the
    formula of :func:`.rank.size_at` and ``uniform2d.sizefield`` on bare arrays."""
    x = min(max(x, gx[0]), gx[-1])
    y = min(max(y, gy[0]), gy[-1])
    i = min(max(_right_of(gx, x) - 1, 0), gx.shape[0] - 2)
    j = min(max(_right_of(gy, y) - 1, 0), gy.shape[0] - 2)
    tx = (x - gx[i]) / (gx[i + 1] - gx[i])
    ty = (y - gy[j]) / (gy[j + 1] - gy[j])
    return (
        gv[j, i] * (1 - tx) * (1 - ty)
        + gv[j, i + 1] * tx * (1 - ty)
        + gv[j + 1, i] * (1 - tx) * ty
        + gv[j + 1, i + 1] * tx * ty
    )


@njit(cache=True, inline="always")
def _add(num, den, v, px, py, ax, ay, bx, by, gx, gy, gv, power):
    """Add the sub-triangle (p, a, b) of v's cell, weighted by its signed area
    times 1 / h**power at its centroid."""
    cx = (px + ax + bx) / 3.0
    cy = (py + ay + by) / 3.0
    area = 0.5 * ((ax - px) * (by - py) - (ay - py) * (bx - px))
    w = area / grid_size(gx, gy, gv, cx, cy) ** power
    num[v, 0] += w * cx
    num[v, 1] += w * cy
    den[v] += w


@njit(cache=True, error_model="numpy")
def weighted_centroids(xy, tri, gx, gy, gv, power):
    """(N, 2) centroid of every vertex's Voronoi cell within the mesh (xy (N, 2),
    tri (M, 3)) for the density 1 / h**power, h the grid (gx, gy, gv).

    The cell of v within triangle (v, a, b) is the two triangles
    (v, mid(v, a), c) and (v, c, mid(v, b)), c the circumcentre, with signed
    areas (obtuse triangles add up right).  NaN for a vertex in no triangle.
    """
    n = xy.shape[0]
    num = np.zeros((n, 2))
    den = np.zeros(n)
    for t in range(tri.shape[0]):
        a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
        bx, by = xy[b, 0] - xy[a, 0], xy[b, 1] - xy[a, 1]
        cx, cy = xy[c, 0] - xy[a, 0], xy[c, 1] - xy[a, 1]
        d = 2.0 * (bx * cy - by * cx)
        bb, cc = bx * bx + by * by, cx * cx + cy * cy
        ox = xy[a, 0] + (cy * bb - by * cc) / d
        oy = xy[a, 1] + (bx * cc - cx * bb) / d
        for k in range(3):
            v, w1, w2 = tri[t, k], tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]
            px, py = xy[v, 0], xy[v, 1]
            m1x, m1y = 0.5 * (px + xy[w1, 0]), 0.5 * (py + xy[w1, 1])
            m2x, m2y = 0.5 * (px + xy[w2, 0]), 0.5 * (py + xy[w2, 1])
            _add(num, den, v, px, py, m1x, m1y, ox, oy, gx, gy, gv, power)
            _add(num, den, v, px, py, ox, oy, m2x, m2y, gx, gy, gv, power)
    out = np.empty((n, 2))
    for v in range(n):
        out[v, 0] = num[v, 0] / den[v]
        out[v, 1] = num[v, 1] / den[v]
    return out
