"""The envelope pruning's arithmetic: sorting, the lower envelope, the levels.

Helpers of :mod:`.pairs`: the sites' lower envelope along the subsegment, the
certificate that a site is visible over a stretch, the prune level below the best
value found and the floor of the tied group (see :mod:`.segment` for why the
result stays bit for bit that of the plain scan).
"""

import numpy as np
from ._jit import njit

from .cdt import nxt
from .predicates import orient2d
from .rank import tied_above

__all__ = ["PRUNE_REL"]

# relative distance below the best value found, under which points are dismissed
# by their bound (:func:`_prune_level`); any value > REL_TIE keeps the result exact
PRUNE_REL = 1e-7


@njit(cache=True)
def _argsort(keys):
    """Indices (int64) that sort the float64 ``keys`` ascending, equal keys in index
    order (a bottom-up merge sort: numba's generic argsort costs far more to
    compile)."""
    n = keys.shape[0]
    order = np.empty(n, np.int64)
    spare = np.empty(n, np.int64)
    for i in range(n):
        order[i] = i
    width = 1
    while width < n:
        for lo in range(0, n, 2 * width):
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i, j = lo, mid
            for k in range(lo, hi):
                if i < mid and (j >= hi or keys[order[i]] <= keys[order[j]]):
                    spare[k] = order[i]
                    i += 1
                else:
                    spare[k] = order[j]
                    j += 1
        order, spare = spare, order
        width *= 2
    return order


@njit(cache=True)
def _lower_envelope(c, t):
    """The lower envelope over s in [0, 1] of the lines c[k] - 2 s t[k]: (sites, cuts),
    the envelope's lines from s = 0 to s = 1 and the s between consecutive ones.

    With x(s) = a + s (b - a), |x(s) - p|^2 = |b - a|^2 s^2 + c_p - 2 s t_p for
    c_p = |p - a|^2 and t_p = (b - a).(p - a): the common term aside, the
    squared distances to the sites along h are lines, and their lower envelope
    (the nearest site, visibility aside) is a convex-hull-trick sweep over the
    lines sorted by slope, O(sites log sites).  Plain floating point: it only
    chooses which site bounds which part of h (:func:`_certify` and
    :func:`_envelope_max` check everything they rely on exactly).
    """
    n = c.shape[0]
    order = _argsort(t)
    st = np.empty(n, np.int64)
    k = 0
    for r in range(n):
        i = order[r]
        if k > 0 and t[st[k - 1]] == t[i]:
            if c[i] >= c[st[k - 1]]:
                continue
            k -= 1
        while k >= 2:
            i1, i2 = st[k - 2], st[k - 1]
            # i2 is not on the envelope if i crosses i1 no later than i2 does
            if (c[i] - c[i1]) * (t[i2] - t[i1]) <= (c[i2] - c[i1]) * (t[i] - t[i1]):
                k -= 1
            else:
                break
        st[k] = i
        k += 1
    sites = np.empty(k, np.int64)
    cuts = np.empty(max(k - 1, 0), np.float64)
    np_ = 0
    lo = 0.0
    for r in range(k):
        hi = 1.0
        if r + 1 < k:
            i1, i2 = st[r], st[r + 1]
            hi = (c[i2] - c[i1]) / (2.0 * (t[i2] - t[i1]))
        if hi > lo or (r + 1 == k and np_ == 0):
            if np_ > 0:
                cuts[np_ - 1] = lo
            sites[np_] = st[r]
            np_ += 1
            lo = max(lo, hi)
        if lo >= 1.0:
            break
    return sites[:np_], cuts[: max(np_ - 1, 0)]


@njit(cache=True)
def _certify(m, ne, z, x1, y1, x2, y2):
    """True if site z sees every point of the closed triangle (z, (x1, y1), (x2, y2))
    by :func:`_visible`'s rule: each collected constrained edge not at z lies in
    the closed outer half-plane of one of the triangle's sides, or the triangle
    in a closed half-plane of the edge's line (exact signs; the separating-axis
    test of two convex sets, up to touching), after the cheap test against the
    triangle's bounding box.

    Why that is enough: for x in the triangle the open segment x -> z lies in
    it, and an edge crossing that segment properly would have a point inside
    the triangle off that side's line, or -- on a side through z -- would not
    have its ends strictly on both sides of the line x -> z; and it would have
    x and z strictly on both sides of its own line.  O(edges).
    """
    xy = m.xy
    zx, zy = xy[z, 0], xy[z, 1]
    if orient2d(x1, y1, x2, y2, zx, zy) <= 0.0:
        return False
    xlo, xhi = min(zx, x1, x2), max(zx, x1, x2)
    ylo, yhi = min(zy, y1, y2), max(zy, y1, y2)
    for k in range(ne):
        h = m.ebuf[k]
        e0 = m.tv[h]
        e1 = m.tv[nxt(h)]
        if e0 == z or e1 == z:
            continue
        px, py, qx, qy = xy[e0, 0], xy[e0, 1], xy[e1, 0], xy[e1, 1]
        # beside the triangle's bounding box (an axis-parallel separating line)
        if ((px < xlo and qx < xlo) or (px > xhi and qx > xhi)
                or (py < ylo and qy < ylo) or (py > yhi and qy > yhi)):
            continue
        if orient2d(x1, y1, x2, y2, px, py) <= 0.0 and orient2d(x1, y1, x2, y2, qx, qy) <= 0.0:
            continue
        if orient2d(x2, y2, zx, zy, px, py) <= 0.0 and orient2d(x2, y2, zx, zy, qx, qy) <= 0.0:
            continue
        if orient2d(zx, zy, x1, y1, px, py) <= 0.0 and orient2d(zx, zy, x1, y1, qx, qy) <= 0.0:
            continue
        # or the triangle on one closed side of the edge's line: x and z are
        # then never strictly on both sides of it
        o1 = orient2d(px, py, qx, qy, zx, zy)
        o2 = orient2d(px, py, qx, qy, x1, y1)
        o3 = orient2d(px, py, qx, qy, x2, y2)
        if (o1 >= 0.0 and o2 >= 0.0 and o3 >= 0.0) or (o1 <= 0.0 and o2 <= 0.0 and o3 <= 0.0):
            continue
        return False
    return True


@njit(cache=True)
def _inside(zx, zy, x1, y1, x2, y2, x, y):
    """Whether (x, y) lies in the closed counter-clockwise triangle (z, 1, 2) (exact)."""
    return (orient2d(x1, y1, x2, y2, x, y) >= 0.0
            and orient2d(x2, y2, zx, zy, x, y) >= 0.0
            and orient2d(zx, zy, x1, y1, x, y) >= 0.0)


@njit(cache=True)
def _prune_level(L, wg):
    """Points whose value is certainly below this are not gathered once a point of
    value L is known: far enough below L's tie threshold (:func:`tied_above`)
    that the tied group of the maximum (>= L) almost never reaches it."""
    return L * (1.0 - PRUNE_REL) - 4.0 * wg


@njit(cache=True)
def _group_floor(vals, n, wg):
    """The smallest value of the maximum's tied group among vals[:n]: values taken
    from the largest down while each is tied with the one above it.  O(n) per
    distinct value of the group (a handful)."""
    lo = vals[0]
    for i in range(1, n):
        lo = max(lo, vals[i])
    while True:
        nxt_ = -np.inf
        for i in range(n):
            if vals[i] < lo and vals[i] > nxt_:
                nxt_ = vals[i]
        if nxt_ == -np.inf or nxt_ < tied_above(lo, wg):
            return lo
        lo = nxt_


@njit(cache=True)
def _point_error(ax, ay, dx, dy):
    """A bound on how far, in each coordinate, the computed point
    ``(ax + s * dx, ay + s * dy)`` for 0 <= s <= 1 is from the exact a + s (b - a):
    two roundings, each at most u |operand| (u = 2**-53)."""
    return 2.01 * 2.0**-53 * (abs(ax) + abs(ay) + abs(dx) + abs(dy)) + 1e-300
