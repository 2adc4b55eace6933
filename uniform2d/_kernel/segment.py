"""A boundary subsegment as an INSERT candidate: its largest visible distance.

:func:`eval_segment` gives the value and place of the subsegment candidate (see
:mod:`.insert`): the midpoint when nothing encroaches, else the maximum of the
visible lower envelope of the sites near it.

That maximum is defined by a scan (:func:`_envelope_max`): every pair of the
gathered sites gives the point of h equidistant from both, each point is valued
by its nearest visible site, and the best by the tie rule wins.  INSERT ranks
the result against other candidates with exact ties, so the scan's result is
kept bit for bit (the plain scan, O(sites^3), is ``tests/reference_envelope.py``)
while only the few points that can matter are valued: those whose certified
upper bound reaches just below the best value found, found by sorting the sites
(near-linear in the sites for a straight edge facing a long coastline).
"""

import numpy as np
from ._jit import njit

from .cdt import new_tag, nxt, prv, reserve
from .predicates import dot2d, orient2d
from .radix import stable_argsort
from .rank import _right_of, better, size_at, tied_above

__all__ = ["eval_segment", "seg_dist2", "DISK_SLACK"]

DISK_SLACK = 1e-12  # inclusive slack when collecting sites near a subsegment (harmless)
# relative slack on the bound of eval_segment: values may rise by the tie
# tolerance (1e-9) between evaluations, where rounding computes them differently
NEAR_SLACK = 1e-6
# relative distance below the best value found, under which points are dismissed
# by their bound (:func:`_prune_level`); any value > REL_TIE keeps the result exact
PRUNE_REL = 1e-7
# spans of h searched pair by pair at most (:func:`_region`); more are merged
MAX_SPANS = 16


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
def _site_list(m, h, nv):
    """The sites a candidate point of h is measured against: h's ends a, b first
    (always visible), then the nv gathered ones in gathering order -- the order
    that makes the pairs' order, which the tie rule's scan depends on."""
    ns = nv + 2
    sites = np.empty(ns, np.int32)
    sites[0] = m.tv[h]
    sites[1] = m.tv[nxt(h)]
    for i in range(nv):
        sites[2 + i] = m.vbuf[i]
    return sites


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


@njit(cache=True, inline="always")
def _inside(zx, zy, x1, y1, x2, y2, x, y):
    """Whether (x, y) lies in the closed counter-clockwise triangle (z, 1, 2) (exact)."""
    return (orient2d(x1, y1, x2, y2, x, y) >= 0.0
            and orient2d(x2, y2, zx, zy, x, y) >= 0.0
            and orient2d(zx, zy, x1, y1, x, y) >= 0.0)


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def _point_error(ax, ay, dx, dy):
    """A bound on how far, in each coordinate, the computed point
    ``(ax + s * dx, ay + s * dy)`` for 0 <= s <= 1 is from the exact a + s (b - a):
    two roundings, each at most u |operand| (u = 2**-53)."""
    return 2.01 * 2.0**-53 * (abs(ax) + abs(ay) + abs(dx) + abs(dy)) + 1e-300


@njit(cache=True)
def _pieces(m, sites, ne):
    """The nearest site along h (visibility aside) as pieces, and a site certainly
    seen from each piece: (pz, cuts, cz, tri).  Piece k is s in
    [cuts[k-1], cuts[k]], nearest to site index pz[k]; if cz[k] >= 0, site index
    cz[k] sees the whole triangle tri[k] = (x1, y1, x2, y2) with it, which holds
    every point computed as a + s (b - a) for s in the piece (:func:`_triangle`).

    The piece's own site is tried first.  Where a constrained edge hides it (a
    site behind the outline), the site certified for the piece before it, then
    the one for the piece after it, is tried instead: the sites that do see a
    stretch of h usually see its neighbours too.  O(pieces x edges).
    """
    xy = m.xy
    a, b = sites[0], sites[1]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    ns = sites.shape[0]
    c = np.empty(ns, np.float64)
    t = np.empty(ns, np.float64)
    for i in range(ns):
        p = sites[i]
        c[i] = (xy[p, 0] - ax) ** 2 + (xy[p, 1] - ay) ** 2
        t[i] = dx * (xy[p, 0] - ax) + dy * (xy[p, 1] - ay)
    pz, cuts = _lower_envelope(c, t)
    npc = pz.shape[0]
    cz = np.empty(npc, np.int64)
    for k in range(npc):
        cz[k] = -1
    tri = np.empty((npc, 4), np.float64)
    for k in range(npc):
        if pz[k] >= 2:  # h's ends are counted everywhere (_nearest_visible)
            _try_site(m, ne, sites, pz[k], cuts, k, cz, tri)
    for sweep in range(2):
        last = np.int64(-1)
        for r in range(npc):
            k = r if sweep == 0 else npc - 1 - r
            if cz[k] >= 0:
                last = cz[k]
            elif last >= 0 and pz[k] >= 2:
                _try_site(m, ne, sites, last, cuts, k, cz, tri)
    return pz, cuts, cz, tri


@njit(cache=True)
def _try_site(m, ne, sites, i, cuts, k, cz, tri):
    """Certify site index i for piece k (see :func:`_pieces`): set cz[k] = i and
    tri[k] if the triangle from it over the piece holds the piece's rectangle and
    is seen whole from it (:func:`_certify`).

    The rectangle is twice as wide as the rounding of a computed point
    (:func:`_point_error`) could move it off h; the triangle's base lies below
    h by twice that (and 1e-9 |h|) and reaches beyond the piece along h by more
    than that drop times the slope of its sides, so that the rectangle fits
    under them.  Whether it does is checked exactly (orient2d on its four
    corners), so the margins only decide how often a site is certified."""
    xy = m.xy
    npc = cz.shape[0]
    a, b = sites[0], sites[1]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    z = sites[i]
    zx, zy = xy[z, 0], xy[z, 1]
    ln = np.sqrt(dx * dx + dy * dy)
    ux, uy = dx / ln, dy / ln
    e = 4.0 * _point_error(ax, ay, dx, dy)  # the rectangle's half-width
    marg = 1e-9 + 2.0 * e / ln  # the base's drop, in units of s
    lo = cuts[k - 1] if k > 0 else 0.0
    hi = cuts[k] if k < npc - 1 else 1.0
    sz = (dx * (zx - ax) + dy * (zy - ay)) / (ln * ln)
    hz = (dx * (zy - ay) - dy * (zx - ax)) / ln
    if not hz > 0.0:
        return
    s0 = lo - marg * (2.0 + 4.0 * abs(sz - lo) * ln / hz)
    s1 = hi + marg * (2.0 + 4.0 * abs(sz - hi) * ln / hz)
    x1 = ax + s0 * dx + marg * dy
    y1 = ay + s0 * dy - marg * dx
    x2 = ax + s1 * dx + marg * dy
    y2 = ay + s1 * dy - marg * dx
    for end in range(2):
        se = lo if end == 0 else hi
        sg = -1.0 if end == 0 else 1.0
        for side in range(2):
            sn = -1.0 if side == 0 else 1.0
            px = ax + se * dx + e * (sg * ux - sn * uy)
            py = ay + se * dy + e * (sg * uy + sn * ux)
            if not _inside(zx, zy, x1, y1, x2, y2, px, py):
                return
    if _certify(m, np.int64(ne), z, x1, y1, x2, y2):
        cz[k] = i
        tri[k, 0], tri[k, 1], tri[k, 2], tri[k, 3] = x1, y1, x2, y2


@njit(cache=True, inline="always")
def _bound(m, sites, cz, cuts, tri, s, x, y):
    """A value the point (x, y) = a + s (b - a) of h certainly does not exceed:
    the distance to h's ends or to its piece's site where that site certainly
    sees it, over the size field, in :func:`_nearest_visible`'s arithmetic
    (so >= the value :func:`_envelope_max` computes there, bit for bit)."""
    xy = m.xy
    a, b = sites[0], sites[1]
    w = min((xy[a, 0] - x) ** 2 + (xy[a, 1] - y) ** 2, (xy[b, 0] - x) ** 2 + (xy[b, 1] - y) ** 2)
    k = _right_of(cuts, s)
    if cz[k] >= 0:
        z = sites[cz[k]]
        zx, zy = xy[z, 0], xy[z, 1]
        d2 = (zx - x) ** 2 + (zy - y) ** 2
        if d2 < w and _inside(zx, zy, tri[k, 0], tri[k, 1], tri[k, 2], tri[k, 3], x, y):
            w = d2
    return np.sqrt(w) / size_at(m, x, y)


@njit(cache=True)
def _size_floor(m, sites):
    """A size no computed point of h goes below (with a size field): the smallest
    grid value at the corners of the cells around h's bounding box (grown by the
    rounding of its points), less a relative 1e-12.  :func:`size_at` is a
    bilinear mean of one cell's corners, so at most a few ulps below them."""
    xy = m.xy
    a, b = sites[0], sites[1]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    e = 2.0 * _point_error(ax, ay, dx, dy)
    gx, gy, gv = m.sgx, m.sgy, m.sgv
    nx, ny = gx.shape[0], gy.shape[0]
    i0 = min(max(_right_of(gx, min(ax, ax + dx) - e) - 1, 0), nx - 2)
    i1 = min(max(_right_of(gx, max(ax, ax + dx) + e) - 1, 0), nx - 2)
    j0 = min(max(_right_of(gy, min(ay, ay + dy) - e) - 1, 0), ny - 2)
    j1 = min(max(_right_of(gy, max(ay, ay + dy) + e) - 1, 0), ny - 2)
    lo = np.inf
    for j in range(j0, j1 + 2):
        for i in range(i0, i1 + 2):
            lo = min(lo, gv[j, i])
    return lo * (1.0 - 1e-12)


@njit(cache=True)
def _region(m, sites, cz, cuts, tau):
    """Where along h a computed point's bound (:func:`_bound`, without its division
    by the size field) may reach tau: (lo, hi, count), disjoint intervals of s in
    increasing order, at most MAX_SPANS of them (nearby ones merged: a
    superset); tau > 0.

    A point's bound is its distance to a or b, or to its piece's certified site z,
    which in exact terms along h is |h| s, |h| (1 - s) and
    sqrt(|h|^2 (s - s_z)^2 + h_z^2); the bound of the computed point (rounded
    by :func:`_point_error`, its distances and square root by a few ulps) reaches
    tau only where these exact distances all reach tau' = tau - 2 e - a few ulps,
    a piece of [tau'/|h|, 1 - tau'/|h|] minus an interval around s_z.  Every
    end is moved outwards by 1e-12 (its own rounding is ~1e-15 in s)."""
    xy = m.xy
    a, b = sites[0], sites[1]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    ln = np.sqrt(dx * dx + dy * dy)
    e = _point_error(ax, ay, dx, dy)
    tp = tau * (1.0 - 1e-14) - 2.0 * e
    npc = cz.shape[0]
    lo = np.empty(2 * npc + 1, np.float64)
    hi = np.empty(2 * npc + 1, np.float64)
    cnt = 0
    if not tp > 0.0:
        lo[0], hi[0] = 0.0, 1.0
        return lo, hi, 1
    e0 = tp / ln * (1.0 - 1e-12) - 1e-12
    e1 = 1.0 - e0
    for k in range(npc):
        plo = max(cuts[k - 1] if k > 0 else 0.0, e0)
        phi = min(cuts[k] if k < npc - 1 else 1.0, e1)
        if plo > phi:
            continue
        xlo, xhi = 1.0, -1.0  # the excluded open interval, empty
        if cz[k] >= 0:
            z = sites[cz[k]]
            zx, zy = xy[z, 0] - ax, xy[z, 1] - ay
            sz = (dx * zx + dy * zy) / (ln * ln)
            hz = (dx * zy - dy * zx) / ln
            r2 = tp * tp - hz * hz - 1e-12 * (tp * tp + hz * hz + ln * ln)
            if r2 > 0.0:
                r = np.sqrt(r2) / ln * (1.0 - 1e-12) - 1e-12
                if r > 0.0:
                    xlo, xhi = sz - r, sz + r
        if xlo < xhi:
            if plo < xlo:
                cnt = _add_span(lo, hi, cnt, plo - 1e-12, min(phi, xlo) + 1e-12)
            if xhi < phi:
                cnt = _add_span(lo, hi, cnt, max(plo, xhi) - 1e-12, phi + 1e-12)
        else:
            cnt = _add_span(lo, hi, cnt, plo - 1e-12, phi + 1e-12)
    if cnt > MAX_SPANS:
        # merge into MAX_SPANS runs of consecutive spans (each run: first lo, last hi)
        per = (cnt + MAX_SPANS - 1) // MAX_SPANS
        k2 = 0
        for i in range(0, cnt, per):
            lo[k2] = lo[i]
            hi[k2] = hi[min(i + per, cnt) - 1]
            k2 += 1
        cnt = k2
    return lo, hi, cnt


@njit(cache=True, inline="always")
def _whole():
    """The span of :func:`_region` that is all of h (a little more)."""
    lo = np.empty(1, np.float64)
    hi = np.empty(1, np.float64)
    lo[0], hi[0] = -1e-12, 1.0 + 1e-12
    return lo, hi, 1


@njit(cache=True, inline="always")
def _add_span(lo, hi, cnt, s0, s1):
    """Append [s0, s1] to the increasing spans, merging it into the last one if
    they overlap or touch.  Returns the new count."""
    if cnt > 0 and s0 <= hi[cnt - 1]:
        hi[cnt - 1] = max(hi[cnt - 1], s1)
        return cnt
    lo[cnt] = s0
    hi[cnt] = s1
    return cnt + 1


@njit(cache=True)
def _gather_near(m, sites, ne, cz, cuts, tri, L, tau, fixed, lo, hi, nspan):
    """The points of h equidistant from a pair of sites (the pair's arithmetic
    unchanged) that fall in the spans (:func:`_region`, or all of h) and whose
    bound (:func:`_bound`) is not below the pruning level, with their exact
    values, in the order of the pairs (the tie scan's): (vals, xs, ys, count,
    level reached, L).  The level is ``tau`` if ``fixed``, else it follows the
    largest value seen (from L).  The pairs outside the spans' windows are not
    visited.

    A pair (p, q) whose computed s lies in [S1, S2] has
    |k_q - k_p| <= |h|^2 (1.01 (S2 - S1) + 128 u) for k = c - 2 S t at the middle S
    of the span (c, t as in :func:`_lower_envelope`; the pair's point solves
    c_q - c_p = 2 s (t_q - t_p), |t_q - t_p| <= 1.01 |h|^2 since all sites lie in
    h's diametral disk, and the rounding of s, of the denominator and of k costs
    at most 128 u |h|^2 however ill-conditioned the pair).  So the sites sorted
    by k are scanned with a window of that width: O(sites log sites) a span
    plus the pairs in the windows."""
    xy = m.xy
    a, b = sites[0], sites[1]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    l2 = dx * dx + dy * dy
    ns = sites.shape[0]
    c = np.empty(ns, np.float64)
    t = np.empty(ns, np.float64)
    for i in range(ns):
        p = sites[i]
        c[i] = (xy[p, 0] - ax) ** 2 + (xy[p, 1] - ay) ** 2
        t[i] = dx * (xy[p, 0] - ax) + dy * (xy[p, 1] - ay)
    kv = np.empty(ns, np.float64)
    cap = 16
    keys = np.empty(cap, np.int64)
    vals = np.empty(cap, np.float64)
    xs = np.empty(cap, np.float64)
    ys = np.empty(cap, np.float64)
    cnt = 0
    for r in range(nspan):
        s1, s2 = lo[r], hi[r]
        sm = 0.5 * (s1 + s2)
        width = l2 * (1.01 * (s2 - s1) + 128.0 * 2.0**-53)
        for i in range(ns):
            kv[i] = c[i] - 2.0 * sm * t[i]
        order = _argsort(kv)
        for u in range(ns):
            iu = order[u]
            for w in range(u + 1, ns):
                iw = order[w]
                if kv[iw] - kv[iu] > width:
                    break
                i, j = min(iu, iw), max(iu, iw)
                p = sites[i]
                q = sites[j]
                pa2 = c[i]
                qa2 = c[j]
                den = 2.0 * (dx * (xy[q, 0] - xy[p, 0]) + dy * (xy[q, 1] - xy[p, 1]))
                if den == 0.0:
                    continue
                s = (qa2 - pa2) / den
                if not (0.0 < s < 1.0 and s1 <= s <= s2):
                    continue
                x = ax + s * dx
                y = ay + s * dy
                if _bound(m, sites, cz, cuts, tri, s, x, y) < tau:
                    continue
                val = np.sqrt(_nearest_visible(m, sites, ne, x, y)) / size_at(m, x, y)
                if cnt == cap:
                    cap *= 2
                    keys, vals, xs, ys = _grown(keys, vals, xs, ys, cnt, cap)
                keys[cnt] = i * ns + j
                vals[cnt], xs[cnt], ys[cnt] = val, x, y
                cnt += 1
                if val > L:
                    L = val
                    if not fixed:
                        tau = max(tau, _prune_level(L, m.wg))
    # the scan's order: by pair
    idx = stable_argsort(keys[:cnt])
    v2 = np.empty(max(cnt, 1), np.float64)
    x2 = np.empty(max(cnt, 1), np.float64)
    y2 = np.empty(max(cnt, 1), np.float64)
    for k in range(cnt):
        v2[k], x2[k], y2[k] = vals[idx[k]], xs[idx[k]], ys[idx[k]]
    return v2, x2, y2, cnt, tau, L


@njit(cache=True)
def _grown(keys, vals, xs, ys, cnt, cap):
    """The four record arrays copied into new ones of length cap."""
    k2 = np.empty(cap, np.int64)
    v2 = np.empty(cap, np.float64)
    x2 = np.empty(cap, np.float64)
    y2 = np.empty(cap, np.float64)
    for k in range(cnt):
        k2[k], v2[k], x2[k], y2[k] = keys[k], vals[k], xs[k], ys[k]
    return k2, v2, x2, y2


@njit(cache=True, inline="always")
def _seed(m, sites, ne, pz, cuts):
    """The exact value of one pair's point, a lower bound of the maximum to prune
    against from the start: the envelope's breakpoint farthest from its two
    sites (visibility aside), if it is a point the pair scan makes.  -1 if none."""
    xy = m.xy
    a, b = sites[0], sites[1]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    best, bi = -1.0, -1
    for k in range(cuts.shape[0]):
        s = cuts[k]
        x = ax + s * dx
        y = ay + s * dy
        z = sites[pz[k]]
        d2 = (xy[z, 0] - x) ** 2 + (xy[z, 1] - y) ** 2
        if d2 > best:
            best, bi = d2, k
    if bi < 0:
        return -1.0
    p = sites[pz[bi]]
    q = sites[pz[bi + 1]]
    # the pair's own arithmetic (its point does not depend on the pair's order)
    pa2 = (xy[p, 0] - ax) ** 2 + (xy[p, 1] - ay) ** 2
    qa2 = (xy[q, 0] - ax) ** 2 + (xy[q, 1] - ay) ** 2
    den = 2.0 * (dx * (xy[q, 0] - xy[p, 0]) + dy * (xy[q, 1] - xy[p, 1]))
    if den == 0.0:
        return -1.0
    s = (qa2 - pa2) / den
    if not (0.0 < s < 1.0):
        return -1.0
    x = ax + s * dx
    y = ay + s * dy
    return np.sqrt(_nearest_visible(m, sites, ne, x, y)) / size_at(m, x, y)


@njit(cache=True, inline="always")
def _envelope_max(m, h, nv, ne, mx, my, xtol):
    """(value, x, y) of the best point of h equidistant from two of its ends and
    the nv collected sites, by the visible distance and the tie rule; value < 0
    when there is none.

    The result is, bit for bit, that of scanning every pair's point in pair
    order and keeping the best by :func:`better` (the reference,
    ``tests/reference_envelope.py``).  That scan's result depends only on the
    *tied group* of the maximum V -- the values taken from V down while each is
    tied (:func:`tied_above`) with the one above, down to theta: a point below
    ``tied_above(theta)`` never beats one of the group, and loses to the first
    of them it meets.  So only the points whose value may reach a pruning level
    tau <= tied_above(theta) need their exact value (O(sites) each, as before);
    the others are dismissed by an upper bound, the distance to h's ends or to a
    site certainly visible from them (:func:`_bound`, :func:`_pieces`).  The
    level starts from one point's exact value (:func:`_seed`) and rises with
    the values found; the pairs whose point may reach it are found by sorting
    (:func:`_region`, :func:`_gather_near`; with a size field, against the
    level times the field's least value near h, :func:`_size_floor`), or,
    before any value is known,
    every pair is visited (one span over all of h, O(sites^2) cheap steps).  The points kept are scanned in
    pair order.  If the group turns out to reach below the level, the pass is
    repeated from lower down (twice; then over every pair, unpruned).

    Cost: O(sites log sites) for the envelope, O(pieces x edges) to certify its
    sites, O(sites log sites) per span searched, and O(sites) per point valued.
    """
    sites = _site_list(m, h, nv)
    ne = np.int64(ne)  # one specialisation of the callees (not a literal 0)
    pz, cuts, cz, tri = _pieces(m, sites, ne)
    L = _seed(m, sites, ne, pz, cuts)
    tau = _prune_level(L, m.wg) if L >= 0.0 else -np.inf
    fixed = False
    for rounds in range(4):
        if tau > 0.0:
            # a value reaching tau is a distance reaching tau times the size there
            lo, hi, nspan = _region(m, sites, cz, cuts, tau if not m.sized else tau * _size_floor(m, sites))
        else:  # every pair: one span over all of h
            lo, hi, nspan = _whole()
        vals, xs, ys, cnt, tau, L = _gather_near(m, sites, ne, cz, cuts, tri, L, np.float64(tau),
                                                 np.bool_(fixed), lo, hi, np.int64(nspan))
        if cnt == 0:
            if tau == -np.inf:
                return -1.0, mx, my
            tau = -np.inf  # cannot happen (the seed's point is gathered): every pair then
            fixed = True
            continue
        theta = _group_floor(vals, cnt, m.wg)
        if tau <= tied_above(theta, m.wg):
            break
        # the group reaches below the level: gather again from lower down
        tau = _prune_level(tied_above(theta, m.wg), m.wg) if rounds < 2 else -np.inf
        fixed = True
    bv, bx_, by_ = -1.0, mx, my
    for k in range(cnt):
        val, x, y = vals[k], xs[k], ys[k]
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
    make the maximum are at the value from it.  (A long subsegment shadowed by
    a piece running close beside it keeps hundreds of sites in its disk as the
    mesh around it fills up.)  The maximum is found by :func:`_envelope_max`,
    which values only the pairs' points that may reach it.
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
