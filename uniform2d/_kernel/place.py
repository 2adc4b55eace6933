"""Placing INSERT's chosen point on what the caller's coordinates hold.

The chosen point is rounded (:func:`.cdt.snap`) and located; one that crossed
a boundary edge, or lies within ``snap`` of one (:func:`near_boundary`), is put
on that subsegment (:func:`project`) and rounded again.  Far from the origin the
rounded point can miss the region where its insertion is valid, or fall past an
end of its subsegment (:func:`between`); then a neighbouring representable
point is tried (:func:`insert_nearby`).
"""

import numpy as np

from ._jit import njit
from .cavity import _insert_point
from .cdt import constrained, nxt
from .outcomes import ERR_PRECISION
from .predicates import dot2d
from .segment import seg_dist2

__all__ = ["between", "insert_nearby", "near_boundary", "project"]


@njit(cache=True)
def between(m, h, x, y):
    """Whether (x, y) projects strictly inside boundary subsegment h (exact; True
    for h = -1).  A point rounded past an end of its subsegment would fold the
    boundary chain back on itself: valid triangles, but not a mesh of P."""
    if h < 0:
        return True
    xy = m.xy
    u = m.tv[h]
    v = m.tv[nxt(h)]
    return (
        dot2d(x, y, xy[v, 0], xy[v, 1], xy[u, 0], xy[u, 1]) > 0.0
        and dot2d(x, y, xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1]) > 0.0
    )


@njit(cache=True, inline="always")
def insert_nearby(m, x, y, t0, hs):
    """Insert at one of the 8 points the caller's coordinates hold next to (x, y).

    Only far from the origin, where those coordinates are coarse, can the
    rounded point miss the region in which its insertion is valid (a subsegment a
    few units in the last place long, next to a corner); a neighbouring
    representable point, tried in a fixed order, may be inside it (and, for a
    boundary point, strictly between its subsegment's ends).  Returns
    (status, x, y) as :func:`.cavity.insert_point`."""
    s = m.gs
    cx = m.gc[0]
    cy = m.gc[1]
    X = x * s + cx
    Y = y * s + cy
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            if dx == 0 and dy == 0:
                continue
            Xn = np.nextafter(X, dx * np.inf) if dx != 0 else X
            Yn = np.nextafter(Y, dy * np.inf) if dy != 0 else Y
            xn = (Xn - cx) / s
            yn = (Yn - cy) / s
            if not between(m, hs, xn, yn):
                continue
            k = _insert_point(m, xn, yn, np.int64(t0), np.int64(hs))
            if k >= 0:
                return k, xn, yn
    return ERR_PRECISION, x, y


@njit(cache=True)
def near_boundary(m, t, x, y, snap):
    """A constrained half-edge of t within distance ``snap`` of (x, y), or -1."""
    xy = m.xy
    for i in range(3):
        h = 3 * t + i
        if not constrained(m, h):
            continue
        u = m.tv[h]
        v = m.tv[nxt(h)]
        if seg_dist2(xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], x, y) <= snap * snap:
            return h
    return -1


@njit(cache=True)
def project(m, h, x, y):
    xy = m.xy
    u = m.tv[h]
    v = m.tv[nxt(h)]
    dx, dy = xy[v, 0] - xy[u, 0], xy[v, 1] - xy[u, 1]
    s = ((x - xy[u, 0]) * dx + (y - xy[u, 1]) * dy) / (dx * dx + dy * dy)
    s = min(1.0 - 1e-12, max(1e-12, s))
    return xy[u, 0] + s * dx, xy[u, 1] + s * dy
