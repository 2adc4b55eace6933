"""Algorithm INSERT on the flat-array CDT: one loop, pop -> validate -> insert -> push.

Candidates (the only places the farthest point can be):

* a triangle ``t`` whose circumcentre lies in the closed triangle -- no obtuse
  angle, and no right angle facing a boundary edge (that circumcentre is the
  midpoint of a boundary subsegment and belongs to the subsegment's entry).
  Its value, the circumradius, never changes while the triangle lives.
  Payload ``(t, tstamp[t])``: alive while the slot's stamp is unchanged.
* a constrained subsegment ``u -> v`` (a boundary half-edge, or one side of an
  interior segment piece, valued by the sites on that side): its largest visible
  distance, found by :func:`eval_segment`; it changes only when sites appear
  near it.  Payload ``(-(u + 1), v)``: alive while ``u -> v`` is a constrained
  half-edge (:func:`find_constrained`).  A point chosen there splits the
  piece on both sides.

The main queue M (a value heap, key = an upper bound of the candidate's weight:
exact for triangles, the last evaluation or |uv|/2 for subsegments) holds every
candidate.  Weights only decrease as sites are added, so the first candidate
served whose value survives re-evaluation is a global maximum W.

Ties: the rule is "among candidates with weight >= W (1 - REL_TIE), the smallest
x; among those within ``xtol`` of that x, the smallest y; among those within
``xtol`` of that y, the smallest x" -- tolerances on both coordinates, so that
points tied by symmetry are ordered by geometry, not by rounding noise.  Doing that
by popping the whole tied group every step is quadratic on symmetric polygons,
where thousands of candidates tie.  So the tied group is kept between steps in a
*pool*: slots (payload, weight, x, y) indexed by a value heap (to find W), and
split into the *x-window* (members with x <= x_min + xtol, in heaps by x and by
y) and the rest (a heap by x).  Both persist across steps.  A step

1. validates the pool's largest member (W), then moves every candidate of M with
   key >= W (1 - REL_TIE) into the pool, re-evaluating subsegments on the way;
2. finds x_min (smallest valid x, window or outside), pulls outside members with
   x <= x_min + xtol into the window, and takes the window's smallest y; a new
   member with a smaller x than the window's rebuilds the window;
3. inserts the chosen point and pushes the new candidates into M.

Pool members are validated whenever they are served (a dead triangle is dropped,
a subsegment whose value or point changed goes back to M with its fresh value),
and thresholds only decrease, so the pool always holds exactly the tied group
(plus stale entries skipped lazily).  Cost: O(log n) amortised per step.

Rounding.  The chosen point is rounded to the caller's coordinates
(:func:`cdt.snap`) and then located exactly from its candidate's triangle (a
walk by exact ``orient2d``, a full scan should the walk give up): a rounded
circumcentre that crossed a boundary edge, or lies within ``snap_d`` of one,
is put on that subsegment and rounded again; a boundary point splits its
subsegment by index (``vseg``), wherever rounding put it across the edge's
line.  Far from the origin that rounding can move a weight by ``m.wg``, which
the tie threshold absorbs (:func:`tied_above`), so the canonical order does not
depend on the polygon's position.
"""

import numpy as np
from ._jit import njit

from . import heap
from .borrow import borrowed, settle
from .cavity import _insert_point
from .external import called_by_name
from .cdt import circumcircle, constrained, locate, locate_scan, nxt, prv, snap
from .predicates import dot2d
from .outcomes import ERR_EMPTY, ERR_LOCATE, ERR_PRECISION
from .place import between, insert_nearby, near_boundary, project
from .pool import dump_window, new_pool, pool_add, pool_kill, to_window
from .rank import REL_TIE, size_at, tied_above
from .segment import eval_segment

__all__ = ["REL_TIE", "ERR_EMPTY", "ERR_LOCATE", "ERR_PRECISION", "new_pool", "push_initial", "run"]



@njit(cache=True)
def _centre(xy, tv, tw, tc, t):
    """(candidate, cx, cy, r): t's circumcircle, and whether its centre is a
    candidate (see the module doc).  Arrays, not the triangulation's structref:
    passing a structref costs a counted reference."""
    for i in range(3):
        h = 3 * t + i
        s = dot2d(
            xy[tv[h], 0], xy[tv[h], 1],
            xy[tv[nxt(h)], 0], xy[tv[nxt(h)], 1],
            xy[tv[prv(h)], 0], xy[tv[prv(h)], 1],
        )  # fmt: skip
        if s < 0.0 or (s == 0.0 and (tw[h] < 0 or tc[h] != 0)):  # constrained(m, h)
            return False, 0.0, 0.0, 0.0
    cx, cy, r = circumcircle(xy, tv[3 * t], tv[3 * t + 1], tv[3 * t + 2])
    return True, cx, cy, r


@njit(cache=True, inline="always")
def triangle_key(m, t):
    """Its value (circumradius / size there) if t's circumcentre is a candidate (see
    the module doc), else -1."""
    ok, cx, cy, r = _centre(m.xy, m.tv, m.tw, m.tc, t)
    if not ok:
        return -1.0
    return r / size_at(m, cx, cy)


@njit(cache=True, inline="always")
def _push_triangle(m, M, t):
    r = triangle_key(m, t)
    if r > 0.0:
        heap.push(M, r, np.int32(t), m.tstamp[t])


@njit(cache=True)
def _push_segment(m, M, h):
    u = m.tv[h]
    v = m.tv[nxt(h)]
    ddx = m.xy[v, 0] - m.xy[u, 0]
    ddy = m.xy[v, 1] - m.xy[u, 1]
    heap.push(M, 0.5 * np.sqrt(ddx * ddx + ddy * ddy) / m.hmin, np.int32(-(u + 1)), v)


@njit(cache=True)
def push_initial(m, M):
    """Entries for every candidate triangle and every constrained subsegment."""
    for t in range(m.nt):
        _push_triangle(m, M, np.int64(t))
    for h in range(3 * m.nt):
        if _subsegment(m, h):
            _push_segment(m, M, h)


@njit(cache=True, inline="always")
def _subsegment(m, h):
    """Whether h is a subsegment candidate: a boundary half-edge, or either side
    of an interior piece (each valued by its own side, :func:`eval_segment`)."""
    return constrained(m, h)


@njit(cache=True, inline="always")
def push_new(m, M, k, split):
    """Entries for the k new triangles cav[:k] and, after a split, the two new halves."""
    p = m.nv - 1
    for i in range(k):
        t = np.int64(m.cav[i])
        # _push_triangle, on arrays: no counted reference per triangle
        ok, cx, cy, r = _centre(m.xy, m.tv, m.tw, m.tc, t)
        if ok:
            if m.sized:
                r = r / size_at(m, cx, cy)  # (without a field size_at is 1.0: r / 1.0 is r)
            if r > 0.0:
                if M.size == M.keys.shape[0]:
                    heap.grow(M)
                heap.sift_up(M.keys, M.pa, M.pb, M.size, r, np.int32(t), m.tstamp[t])
                M.size += 1
        if split:
            for e in range(3):
                h = 3 * t + e
                if _subsegment(m, h) and (m.tv[h] == p or m.tv[nxt(h)] == p):
                    _push_segment(m, M, h)


@njit(cache=True)
def find_constrained(m, u, v):
    """The constrained half-edge u -> v (boundary or flagged), or -1: a turn
    around u from ``vseg[u]`` or ``vcs[u]``, both ways (a boundary vertex's
    turn stops at the boundary)."""
    h = m.vseg[u]
    if h >= 0 and m.tv[nxt(h)] == v:
        return h
    h0 = m.vcs[u]
    if h0 < 0:
        return -1
    h = h0
    while True:  # counter-clockwise
        if m.tc[h] and m.tv[nxt(h)] == v:
            return h
        h = m.tw[prv(h)]
        if h < 0 or h == h0:
            break
    if h == h0:
        return -1
    h = h0
    while True:  # clockwise, from u's flagged edge back to the boundary
        g = m.tw[h]
        if g < 0:
            return -1
        h = nxt(g)
        if h == h0:
            return -1
        if m.tc[h] and m.tv[nxt(h)] == v:
            return h


@njit(cache=True)
def _subsegment_now(m, a, b, xtol, bound):
    """:func:`_current` of subsegment candidate (a, b): re-evaluated."""
    h = find_constrained(m, -a - 1, np.int64(b))
    if h < 0:
        return False, 0.0, 0.0, 0.0
    w, x, y = eval_segment(m, h, xtol, bound)
    return True, w, x, y


# the subsegments' search is the largest tree under INSERT's steps, reached from
# both of them (_gather, _choose) and from _revalidate: one compile, called by
# name; a triangle's re-evaluation, the common case, stays in its callers
_subsegment_now_bn = called_by_name(_subsegment_now)


@njit(cache=True)
def _current(m, a, b, xtol, bound):
    """(alive, weight, x, y) of candidate (a, b) now (a subsegment is re-evaluated;
    ``bound``: a value it cannot exceed, its last key or value)."""
    if a >= 0:
        if m.tstamp[a] != b:
            return False, 0.0, 0.0, 0.0
        cx, cy, r = circumcircle(m.xy, m.tv[3 * a], m.tv[3 * a + 1], m.tv[3 * a + 2])
        return True, r / size_at(m, cx, cy), cx, cy
    return _subsegment_now_bn(m, a, b, xtol, bound)


@njit(cache=True)
def _kept(tstamp, pa, pb, pw, px, py, s):
    """Whether pool member s is a live triangle, whose value and centre are what
    they were when filed (its vertices cannot change while its stamp does not;
    recomputing them gives the same bits, unless one is NaN, never equal): then
    :func:`_revalidate` returns True.  Arrays, not the structrefs, so that the
    common case costs no counted reference."""
    a = pa[s]
    if a >= 0 and tstamp[a] == pb[s]:
        w, x, y = pw[s], px[s], py[s]
        return w == w and x == x and y == y
    return False


@njit(cache=True)
def _revalidate(m, M, P, s, thr, xtol):
    """Is member s current and unchanged?  If dead it is dropped; if changed it is
    re-filed with its fresh values (in the pool if still >= thr, else in M)."""
    if _kept(m.tstamp, P.pa, P.pb, P.pw, P.px, P.py, np.int64(s)):
        return True
    a, b = P.pa[s], P.pb[s]
    alive, w, x, y = _current(m, a, b, xtol, P.pw[s])
    if alive and w == P.pw[s] and x == P.px[s] and y == P.py[s]:
        return True
    pool_kill(P, np.int64(s))
    if alive:
        if w >= thr:
            pool_add(P, a, b, w, x, y, xtol)
        else:
            heap.push(M, w, a, b)
    return False


@njit(cache=True)
def _gather(m, M, P, xtol):
    """Step 1: validate the pool's maximum W and pull every candidate of M with key
    >= W (1 - REL_TIE) into the pool.  Returns (W, a, b, x, y): W < 0 when no
    candidate is left; a winner (a, b, x, y) directly when it is the only member of
    its tied group (the common case, which needs no pool at all), else a = b = -1
    and the group is in the pool."""
    W = -1.0
    pv = P.pv
    while pv.size > 0:
        w, s, g = pv.keys[0], pv.pa[0], pv.pb[0]
        if P.pgen[s] != g:
            heap.pop(pv)
            continue
        if _kept(m.tstamp, P.pa, P.pb, P.pw, P.px, P.py, np.int64(s)) or _revalidate(
            m, M, P, np.int64(s), np.inf, xtol
        ):
            W = w
            break
    while M.size > 0 and (W < 0.0 or heap.top_key(M) >= tied_above(W, m.wg)):
        key, a, b = heap.pop(M)
        alive, w, x, y = _current(m, a, b, xtol, key)
        if not alive:
            continue
        if w < key and (W < 0.0 or w < tied_above(W, m.wg)):
            heap.push(M, w, a, b)  # stale subsegment key; it may come back
            continue
        if W < 0.0 and P.nslots == P.nfree and heap.top_key(M) < tied_above(w, m.wg):
            return w, a, b, x, y  # alone in its tied group
        pool_add(P, a, b, w, x, y, xtol)
        if w > W:
            W = w
    return W, -1, -1, 0.0, 0.0


@njit(cache=True, inline="always")
def _lclean(m, M, P, L, loc, thr, xtol):
    """Drop stale or invalid entries from the top of L (an (x, y) heap whose members
    have ploc == loc); returns the top x, or inf when L is empty."""
    while True:
        x, s = _ltop(P, L, loc, m.tstamp)
        if s < 0 or _revalidate(m, M, P, np.int64(s), thr, xtol):
            return x


@njit(cache=True)
def _ltop(P, L, loc, tstamp):
    """:func:`_lclean` up to the first member that needs re-evaluation: (top x,
    -1) when the top member is kept (:func:`_kept`) or L is empty (x = inf),
    (x, s) when member s on top must be re-evaluated.  A dead triangle is
    dropped here as :func:`_revalidate` would drop it.  Two structrefs, not
    four: the common cases cost fewer counted references."""
    while L.size > 0:
        x, s, g = heap.ltop(L)
        if P.pgen[s] != g or P.ploc[s] != loc:
            heap.lpop(L)
            continue
        if _kept(tstamp, P.pa, P.pb, P.pw, P.px, P.py, np.int64(s)):
            return x, np.int64(-1)
        a = P.pa[s]
        if a >= 0 and tstamp[a] != P.pb[s]:  # pool_kill(P, s), without passing P
            P.pgen[s] += 1
            P.pfree[P.nfree] = s
            P.nfree += 1
            continue
        return x, np.int64(s)
    return np.inf, np.int64(-1)


@njit(cache=True)
def _choose(m, M, P, W, xtol):
    """Step 2: the slot of the canonical candidate (or -1)."""
    thr = tied_above(W, m.wg)
    wx, lo, wy = P.wx, P.lo, P.wy  # read once: each read of a structref field is counted
    while True:
        xw, s = _ltop(P, wx, np.int64(1), m.tstamp)  # _lclean, common case first
        if s >= 0:
            xw = _lclean(m, M, P, wx, np.int64(1), thr, xtol)
        xo, s = _ltop(P, lo, np.int64(0), m.tstamp)
        if s >= 0:
            xo = _lclean(m, M, P, lo, np.int64(0), thr, xtol)
        if xw == np.inf and xo == np.inf:
            return -1
        if xo < xw and xw != np.inf:  # a smaller x outside: rebuild the window
            dump_window(P)
            continue
        P.bound = min(xw, xo) + xtol
        restart = False
        while lo.size > 0:  # pull members with x <= B into the window
            x, s, g = heap.ltop(lo)
            if P.pgen[s] != g or P.ploc[s] != 0:
                heap.lpop(lo)
                continue
            if x > P.bound:
                break
            heap.lpop(lo)
            if not (
                _kept(m.tstamp, P.pa, P.pb, P.pw, P.px, P.py, np.int64(s))
                or _revalidate(m, M, P, np.int64(s), thr, xtol)
            ):
                restart = True  # a re-filed member may have moved the anchor
                break
            to_window(P, np.int64(s))
        if restart:
            continue
        ymin = np.inf
        nsel = 0
        while wy.size > 0:  # window members with y <= y_min + xtol
            y, s, g = heap.ltop(wy)
            if P.pgen[s] != g or P.ploc[s] != 1:
                heap.lpop(wy)
                continue
            if nsel > 0 and y > ymin + xtol:
                break
            if not (
                _kept(m.tstamp, P.pa, P.pb, P.pw, P.px, P.py, np.int64(s))
                or _revalidate(m, M, P, np.int64(s), thr, xtol)
            ):
                restart = True
                break
            heap.lpop(wy)
            if nsel == 0:
                ymin = y
            if nsel == P.sel.shape[0]:
                P.sel = heap.grown(P.sel, 2 * nsel)
            P.sel[nsel] = s
            nsel += 1
        best = -1
        for i in range(nsel):  # put them back; the smallest x wins
            s = P.sel[i]
            heap.lpush(wy, P.py[s], P.px[s], np.int64(s), P.pgen[s])
            if best < 0 or P.px[s] < P.px[best]:
                best = s
        if restart:
            continue
        if best >= 0:
            return best
        if not restart:
            dump_window(P)


# called once per step: run holds two calls, not a copy of each one's tree
# (with the candidates' re-evaluation), which it would optimise and generate again
_gather_bn = called_by_name(_gather)
_choose_bn = called_by_name(_choose)


@njit(cache=True)
def run(m, M, P, n, out_xy, out_w, out_b, xtol, snap_d):
    """Insert n points; returns n, or a negative status on failure (:func:`_steps`).

    The steps run on borrowed copies of m, M and P (:mod:`.borrow`): their
    arrays are read without reference counting, which was most of the time.
    A buffer that grows is a new, counted array, so the copies are settled and
    borrowed again whenever one has grown (about log n times).
    """
    j = 0
    while 0 <= j < n:
        v = borrowed(m)
        V = borrowed(M)
        Q = borrowed(P)
        Q.pv = borrowed(P.pv)
        Q.lo = borrowed(P.lo)
        Q.wx = borrowed(P.wx)
        Q.wy = borrowed(P.wy)
        j = _steps(v, V, Q, np.int64(j), n, out_xy, out_w, out_b, xtol, snap_d)
        settle(m, v)
        settle(M, V)
        settle(P.pv, Q.pv)
        settle(P.lo, Q.lo)
        settle(P.wx, Q.wx)
        settle(P.wy, Q.wy)
        settle(P, Q)
    return j


@njit(cache=True, inline="always")
def _steps(m, M, P, j0, n, out_xy, out_w, out_b, xtol, snap_d):
    """Insert points j0..n-1; returns n, or a negative status on failure, or
    the next step once a buffer has grown (see :func:`run`).

    A circumcentre closer than ``snap_d`` to a boundary subsegment of its triangle
    is placed on that subsegment (it is numerically on the boundary; inside it
    would only make a sliver).  Every point is rounded to what the caller's
    coordinates hold (:func:`cdt.snap`) before it is located and inserted, so the
    exact predicates decide on the coordinates actually returned.  On failure
    ``out_*[j]`` describe the failing point and the status is ``code - 100 * j``.
    """
    pv, lo, wx, wy = P.pv, P.lo, P.wx, P.wy
    room = _room(m.stack, M.keys, P.pa, P.sel, pv.keys, lo.e, wx.e, wy.e)
    for j in range(j0, n):
        w, a, b, x, y = _gather_bn(m, M, P, xtol)
        if w < 0.0:
            return ERR_EMPTY - 100 * j
        if a == -1 and b == -1:
            s = _choose_bn(m, M, P, w, xtol)
            if s < 0:
                return ERR_EMPTY - 100 * j
            a, b, w, x, y = P.pa[s], P.pb[s], P.pw[s], P.px[s], P.py[s]
            pool_kill(P, np.int64(s))
        if a >= 0:
            x, y = snap(m, x, y)
            loc = locate(m, np.int64(a), x, y, np.int64(64), np.bool_(True))
            if loc < -(m.tv.shape[0] + 1):  # the walk gave up: look everywhere
                loc = locate_scan(m, x, y)
                if loc < 0:
                    return ERR_LOCATE - 100 * j
            if loc >= 0:
                t0 = loc
                hsplit = near_boundary(m, loc, x, y, snap_d)
            else:
                hsplit = -loc - 1  # the rounded circumcentre crossed this constraint
                t0 = hsplit // 3
            if hsplit >= 0:
                x, y = project(m, hsplit, x, y)
                x, y = snap(m, x, y)
        else:
            hsplit = find_constrained(m, -a - 1, np.int64(b))
            t0 = hsplit // 3
            x, y = snap(m, x, y)
        out_xy[j, 0] = x
        out_xy[j, 1] = y
        out_w[j] = w * size_at(m, x, y)  # the distance (w is distance / size)
        out_b[j] = hsplit >= 0
        k = ERR_PRECISION
        if between(m, hsplit, x, y):
            k = _insert_point(m, x, y, np.int64(t0), np.int64(hsplit))
        if k < 0:
            k, x, y = insert_nearby(m, x, y, t0, hsplit)
            if k < 0:
                return k - 100 * j
            out_xy[j, 0] = x
            out_xy[j, 1] = y
        push_new(m, M, k, hsplit >= 0)
        if _room(m.stack, M.keys, P.pa, P.sel, pv.keys, lo.e, wx.e, wy.e) != room:
            return j + 1
    return n


@njit(cache=True)
def _room(a, b, c, d, e, f, g, h):
    """The total capacity of the buffers that grow (it changes when one does);
    arrays, not their structrefs: passing a structref costs a counted reference."""
    return (
        a.shape[0] + b.shape[0] + c.shape[0] + d.shape[0]
        + e.shape[0] + f.shape[0] + g.shape[0] + h.shape[0]
    )

