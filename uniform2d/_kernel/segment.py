"""A boundary subsegment as an INSERT candidate: its largest visible distance.

:func:`eval_segment` gives the value and place of the subsegment candidate (see
:mod:`.insert`): the midpoint when nothing encroaches, else the maximum of the
visible lower envelope of the sites near it.
"""

import numpy as np
from ._jit import njit

from .cdt import new_tag, nxt, prv, reserve
from .predicates import dot2d, orient2d
from .rank import better, size_at

__all__ = ["eval_segment", "seg_dist2", "DISK_SLACK"]

DISK_SLACK = 1e-12  # inclusive slack when collecting sites near a subsegment (harmless)
# relative slack on the bound of eval_segment: values may rise by the tie
# tolerance (1e-9) between evaluations, where rounding computes them differently
NEAR_SLACK = 1e-6


@njit(cache=True)
def seg_dist2(ux, uy, vx, vy, px, py):
    """Squared distance from (px, py) to the segment (ux, uy) - (vx, vy)."""
    dx, dy = vx - ux, vy - uy
    L2 = dx * dx + dy * dy
    s = ((px - ux) * dx + (py - uy) * dy) / L2
    s = min(1.0, max(0.0, s))
    qx, qy = ux + s * dx - px, uy + s * dy - py
    return qx * qx + qy * qy


@njit(cache=True)
def _visible(m, ne, x, y, q):
    """True if no collected constrained edge properly crosses segment (x, y) -> q."""
    xy = m.xy
    qx, qy = xy[q, 0], xy[q, 1]
    for k in range(ne):
        h = m.ebuf[k]
        e0 = m.tv[h]
        e1 = m.tv[nxt(h)]
        if e0 == q or e1 == q:
            continue
        s1 = orient2d(xy[e0, 0], xy[e0, 1], xy[e1, 0], xy[e1, 1], x, y)
        s2 = orient2d(xy[e0, 0], xy[e0, 1], xy[e1, 0], xy[e1, 1], qx, qy)
        if not ((s1 > 0.0 and s2 < 0.0) or (s1 < 0.0 and s2 > 0.0)):
            continue
        s3 = orient2d(x, y, qx, qy, xy[e0, 0], xy[e0, 1])
        s4 = orient2d(x, y, qx, qy, xy[e1, 0], xy[e1, 1])
        if (s3 > 0.0 and s4 < 0.0) or (s3 < 0.0 and s4 > 0.0):
            return False
    return True


@njit(cache=True, inline="always")
def _collect(m, h, mx, my, r2, near2):
    """Search from the triangle on h across unconstrained edges that meet the disk
    (centre (mx, my), squared radius r2): the sites strictly inside it on the
    inner side of h and within squared distance ``near2`` of h go to
    ``m.vbuf``, the constrained edges met (h and its twin excepted) to
    ``m.ebuf``.  Returns (sites, edges) collected."""
    xy = m.xy
    a = m.tv[h]
    b = m.tv[nxt(h)]
    ax, ay, bx, by = xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1]
    tag = new_tag(m)
    t0 = h // 3
    m.tmark[t0] = tag
    m.stack[0] = t0
    sp = 1
    nv = 0
    ne = 0
    m.vmark[a] = tag
    m.vmark[b] = tag
    while sp > 0:
        reserve(m, max(sp, nv, ne) + 4)
        sp -= 1
        t = m.stack[sp]
        for i in range(3):
            e = 3 * t + i
            w = m.tv[e]
            if m.vmark[w] != tag:
                m.vmark[w] = tag
                ddx, ddy = xy[w, 0] - mx, xy[w, 1] - my
                # a site not strictly on the inner side of h's line is never seen
                # from inside h (the segment would leave P at once), nor nearer
                # than a or b if it lies on that line
                if (ddx * ddx + ddy * ddy < r2
                        and seg_dist2(ax, ay, bx, by, xy[w, 0], xy[w, 1]) <= near2
                        and orient2d(ax, ay, bx, by, xy[w, 0], xy[w, 1]) > 0.0):
                    m.vbuf[nv] = w
                    nv += 1
            g = m.tw[e]
            if g < 0 or m.tc[e]:
                if e != h and g != h:
                    m.ebuf[ne] = e
                    ne += 1
                continue
            n = g // 3
            if m.tmark[n] == tag:
                continue
            u = m.tv[e]
            v = m.tv[nxt(e)]
            if seg_dist2(xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], mx, my) < r2:
                m.tmark[n] = tag
                m.stack[sp] = n
                sp += 1
    return nv, ne


@njit(cache=True, inline="always")
def _nearest_visible(m, sites, ne, x, y):
    """Squared distance from (x, y) on the subsegment to the nearest visible site
    (sites[0], sites[1] are its ends, always visible)."""
    xy = m.xy
    wmin = np.inf
    for k in range(sites.shape[0]):
        z = sites[k]
        d2 = (xy[z, 0] - x) ** 2 + (xy[z, 1] - y) ** 2
        if d2 < wmin and (k < 2 or _visible(m, np.int64(ne), x, y, z)):
            wmin = d2
    return wmin


@njit(cache=True, inline="always")
def _envelope_max(m, h, nv, ne, mx, my, xtol):
    """(value, x, y) of the best point of h equidistant from two of its ends and
    the nv collected sites, by the visible distance and the tie rule; value < 0
    when there is none."""
    xy = m.xy
    a = m.tv[h]
    b = m.tv[nxt(h)]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    ns = nv + 2
    sites = np.empty(ns, np.int32)
    sites[0] = a
    sites[1] = b
    for i in range(nv):
        sites[2 + i] = m.vbuf[i]
    bv, bx_, by_ = -1.0, mx, my
    for i in range(ns):
        p = sites[i]
        pa2 = (xy[p, 0] - ax) ** 2 + (xy[p, 1] - ay) ** 2
        for j in range(i + 1, ns):
            q = sites[j]
            qa2 = (xy[q, 0] - ax) ** 2 + (xy[q, 1] - ay) ** 2
            den = 2.0 * (dx * (xy[q, 0] - xy[p, 0]) + dy * (xy[q, 1] - xy[p, 1]))
            if den == 0.0:
                continue
            s = (qa2 - pa2) / den
            if not (0.0 < s < 1.0):
                continue
            x = ax + s * dx
            y = ay + s * dy
            val = np.sqrt(_nearest_visible(m, sites, ne, x, y)) / size_at(m, x, y)
            if bv < 0.0 or better(val, x, y, bv, bx_, by_, xtol, m.wg):
                bv, bx_, by_ = val, x, y
    return bv, bx_, by_


@njit(cache=True, inline="always")
def eval_segment(m, h, xtol, bound):
    """Largest visible distance on constrained subsegment h and where: (value, x, y),
    value = distance / size field (the distance itself without a field).
    ``bound`` is a value h cannot exceed (an earlier value of it: values only
    fall as sites are added), or inf.

    h is a boundary subsegment or one side of an interior piece.  A piece is a
    candidate once per side, valued by the sites on that side: approached from
    one side, the visible distance tends to that side's value, so the largest
    visible distance near the piece is attained there (taking the smaller of
    the two sides at the piece itself would leave a supremum no point attains).
    If the apex of the triangle on h is outside the open diametral disk of h, no
    visible site is inside that disk and the midpoint wins with |h|/2.
    Otherwise gather, by a search across unconstrained edges that meet the disk,
    the sites in it on the inner side of h and the constrained edges around them;
    the maximum of the visible lower envelope is at a point of h equidistant from
    two of them.  Visibility from x on h to such a site q is decided against the
    gathered constrained edges only, which is enough: x -> q enters P through the
    triangle on h and lies in the disk, so every triangle it crosses before its
    first constrained edge is reached by the search, and so is that edge.

    Without a size field only the sites within ``bound`` (with a relative 1e-6
    and the rounding grain to spare) of h are gathered: a site farther away is
    farther than the value from every point of h, so it is nobody's nearest and
    leaves every point's visible distance as it was, while the two sites that
    make the maximum are at the value from it.  The maximum is found over every
    pair of gathered sites (O(sites^3)), and a long subsegment shadowed by a
    piece running close beside it keeps hundreds of sites in its disk as the
    mesh around it fills up: gathering them all made each step cost ~1 s.
    """
    xy = m.xy
    a = m.tv[h]
    b = m.tv[nxt(h)]
    c = m.tv[prv(h)]
    ax, ay, bx, by = xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1]
    dx, dy = bx - ax, by - ay
    half = 0.5 * np.sqrt(dx * dx + dy * dy)
    mx, my = ax + 0.5 * dx, ay + 0.5 * dy
    if dot2d(ax, ay, bx, by, xy[c, 0], xy[c, 1]) >= 0.0:
        return half / size_at(m, mx, my), mx, my
    # the subsegment is encroached
    near2 = np.inf
    if not m.sized and bound < np.inf:
        near = bound * (1.0 + NEAR_SLACK) + m.wg
        near2 = near * near
    nv, ne = _collect(m, h, mx, my, half * half * (1.0 + DISK_SLACK), near2)
    bv, bx_, by_ = _envelope_max(m, h, nv, ne, mx, my, xtol)
    if bv < 0.0:
        return half / size_at(m, mx, my), mx, my
    return bv, bx_, by_
