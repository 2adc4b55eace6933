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
(near-linear in the sites for a straight edge facing a long coastline): the pairs
in :mod:`.pairs`, the envelope, certificates and levels in :mod:`.envelope`,
visibility in :mod:`.visible`.
"""

import numpy as np
from ._jit import njit

from .cdt import new_tag, nxt, prv, reserve
from .predicates import dot2d, orient2d
from .envelope import _group_floor, _prune_level
from .pairs import _gather_near, _pieces, _region, _seed, _size_floor, _whole
from .rank import better, size_at, tied_above

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
