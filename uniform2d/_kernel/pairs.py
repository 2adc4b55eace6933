"""Which pairs of sites may give the subsegment's maximum: found by sorting.

The pairs whose equidistant point's certified upper bound can reach the prune
level lie on a few short stretches of the subsegment; :func:`_region` finds
those spans, :func:`_gather_near` the pairs landing in them, and :func:`_seed`
the first best value the level starts from (see :mod:`.segment`).
"""

import numpy as np
from ._jit import njit

from .envelope import _argsort, _certify, _inside, _lower_envelope, _point_error, _prune_level
from .radix import stable_argsort
from .rank import _right_of, size_at
from .visible import _nearest_visible

__all__ = ["MAX_SPANS"]

# spans of h searched pair by pair at most (:func:`_region`); more are merged
MAX_SPANS = 16


@njit(cache=True, inline="always")
def _along(m, sites):
    """Every site's squared distance c from h's start a and its projection t on
    h (unnormalised: (p - a) . (b - a)): the site's distance to a + s (b - a) is
    c - 2 s t + s^2 |h|^2 (the form :func:`_lower_envelope` takes)."""
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
    return c, t


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
    c, t = _along(m, sites)
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
    c, t = _along(m, sites)
    kv = np.empty(ns, np.float64)
    cap = 16
    keys = np.empty(cap, np.int64)
    vals = np.empty(cap, np.float64)
    xs = np.empty(cap, np.float64)
    ys = np.empty(cap, np.float64)
    cnt = np.int64(0)  # not a literal 0: _grown compiles for one type of count
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
