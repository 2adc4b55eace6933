"""Algorithm INSERT on the flat-array CDT: one loop, pop -> validate -> insert -> push.

Candidates (design notes §2):

* a triangle ``t`` whose circumcentre lies in the closed triangle -- no obtuse
  angle, and no right angle facing a boundary edge (that circumcentre is the
  midpoint of a boundary subsegment and belongs to the subsegment's entry).
  Its value, the circumradius, never changes while the triangle lives.
  Payload ``(t, tstamp[t])``: alive while the slot's stamp is unchanged.
* a boundary subsegment ``u -> v``: its largest visible distance, found by
  :func:`eval_segment`; it changes only when sites appear near it.
  Payload ``(-(u + 1), v)``: alive while ``u -> v`` is a boundary half-edge.

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
from numba import njit, types
from numba.experimental import structref

from . import heap
from .cavity import insert_point
from .cdt import circumcircle, locate, locate_scan, new_tag, nxt, prv, reserve, snap
from .predicates import dot2d, orient2d

REL_TIE = 1e-9
DISK_SLACK = 1e-12  # inclusive slack when collecting sites near a subsegment (harmless)

ERR_EMPTY = -10  # no candidate left (cannot happen for a valid polygon)
ERR_LOCATE = -11  # a circumcentre could not be located (cannot happen)
ERR_PRECISION = -12  # no point the caller's coordinates hold there can be inserted


@njit(cache=True, inline="always")
def tied_above(W, wg):
    """Weights above this tie with W: within REL_TIE of it, or within ``wg`` (the
    rounding of points to the caller's coordinates far from the origin, which
    can move a weight that much)."""
    return W * (1.0 - REL_TIE) - wg


@njit(cache=True, inline="always")
def better(w1, x1, y1, w2, x2, y2, xtol, wg):
    """The tie rule for two candidates: does 1 come before 2?"""
    hi = tied_above(max(w1, w2), wg)
    if w1 < hi or w2 < hi:
        return w1 > w2
    if x1 < x2 - xtol:
        return True
    if x2 < x1 - xtol:
        return False
    if y1 < y2 - xtol:
        return True
    if y2 < y1 - xtol:
        return False
    return x1 < x2


@njit(cache=True)
def size_at(m, x, y):
    """The size field h at (x, y): bilinear on its grid, clamped; 1 without a field.

    Candidates are ranked by value = distance / h, so a field makes points denser
    where h is small; without one every value is the plain distance.
    """
    if not m.sized:
        return 1.0
    gx, gy, gv = m.sgx, m.sgy, m.sgv
    x = min(max(x, gx[0]), gx[-1])
    y = min(max(y, gy[0]), gy[-1])
    i = min(max(np.searchsorted(gx, x, side="right") - 1, 0), gx.shape[0] - 2)
    j = min(max(np.searchsorted(gy, y, side="right") - 1, 0), gy.shape[0] - 2)
    tx = (x - gx[i]) / (gx[i + 1] - gx[i])
    ty = (y - gy[j]) / (gy[j + 1] - gy[j])
    return (
        gv[j, i] * (1 - tx) * (1 - ty)
        + gv[j, i + 1] * tx * (1 - ty)
        + gv[j + 1, i] * (1 - tx) * ty
        + gv[j + 1, i + 1] * tx * ty
    )


@njit(cache=True)
def triangle_key(m, t):
    """Its value (circumradius / size there) if t's circumcentre is a candidate (see
    the module doc), else -1."""
    xy = m.xy
    for i in range(3):
        h = 3 * t + i
        s = dot2d(
            xy[m.tv[h], 0], xy[m.tv[h], 1],
            xy[m.tv[nxt(h)], 0], xy[m.tv[nxt(h)], 1],
            xy[m.tv[prv(h)], 0], xy[m.tv[prv(h)], 1],
        )  # fmt: skip
        if s < 0.0 or (s == 0.0 and m.tw[h] < 0):
            return -1.0
    cx, cy, r = circumcircle(xy, m.tv[3 * t], m.tv[3 * t + 1], m.tv[3 * t + 2])
    return r / size_at(m, cx, cy)


@njit(cache=True)
def _seg_dist2(ux, uy, vx, vy, px, py):
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


@njit(cache=True)
def eval_segment(m, h, xtol):
    """Largest visible distance on boundary subsegment h and where: (value, x, y),
    value = distance / size field (the distance itself without a field).

    If the apex of the triangle on h is outside the open diametral disk of h, no
    visible site is inside that disk and the midpoint wins with |h|/2.
    Otherwise gather, by a search across unconstrained edges that meet the disk,
    the sites in it on the inner side of h and the constrained edges around them;
    the maximum of the visible lower envelope is at a point of h equidistant from
    two of them.  Visibility from x on h to such a site q is decided against the
    gathered constrained edges only, which is enough: x -> q enters P through the
    triangle on h and lies in the disk, so every triangle it crosses before its
    first constrained edge is reached by the search, and so is that edge.
    """
    xy = m.xy
    a = m.tv[h]
    b = m.tv[nxt(h)]
    c = m.tv[prv(h)]
    ax, ay, bx, by = xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1]
    dx, dy = bx - ax, by - ay
    half = 0.5 * np.sqrt(dx * dx + dy * dy)
    if dot2d(ax, ay, bx, by, xy[c, 0], xy[c, 1]) >= 0.0:
        mx, my = ax + 0.5 * dx, ay + 0.5 * dy
        return half / size_at(m, mx, my), mx, my
    # -- slow path: the subsegment is encroached
    mx, my = ax + 0.5 * dx, ay + 0.5 * dy
    r2 = half * half * (1.0 + DISK_SLACK)
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
                if ddx * ddx + ddy * ddy < r2 and orient2d(ax, ay, bx, by, xy[w, 0], xy[w, 1]) > 0.0:
                    m.vbuf[nv] = w
                    nv += 1
            g = m.tw[e]
            if g < 0:
                if e != h:
                    m.ebuf[ne] = e
                    ne += 1
                continue
            n = g // 3
            if m.tmark[n] == tag:
                continue
            u = m.tv[e]
            v = m.tv[nxt(e)]
            if _seg_dist2(xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], mx, my) < r2:
                m.tmark[n] = tag
                m.stack[sp] = n
                sp += 1
    # sites: a, b and the collected ones
    ns = nv + 2
    sites = np.empty(ns, np.int32)
    sites[0] = a
    sites[1] = b
    sites[2:] = m.vbuf[:nv]
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
            wmin = np.inf
            for k in range(ns):
                z = sites[k]
                d2 = (xy[z, 0] - x) ** 2 + (xy[z, 1] - y) ** 2
                if d2 < wmin and (k < 2 or _visible(m, np.int64(ne), x, y, z)):
                    wmin = d2
            val = np.sqrt(wmin) / size_at(m, x, y)
            if bv < 0.0 or better(val, x, y, bv, bx_, by_, xtol, m.wg):
                bv, bx_, by_ = val, x, y
    if bv < 0.0:
        return half / size_at(m, mx, my), mx, my
    return bv, bx_, by_


@njit(cache=True)
def _push_triangle(m, M, t):
    r = triangle_key(m, t)
    if r > 0.0:
        heap.push(M, r, t, m.tstamp[t])


@njit(cache=True)
def _push_segment(m, M, h):
    u = m.tv[h]
    v = m.tv[nxt(h)]
    ddx = m.xy[v, 0] - m.xy[u, 0]
    ddy = m.xy[v, 1] - m.xy[u, 1]
    heap.push(M, 0.5 * np.sqrt(ddx * ddx + ddy * ddy) / m.hmin, -(u + 1), v)


@njit(cache=True)
def push_initial(m, M):
    """Entries for every candidate triangle and every boundary subsegment."""
    for t in range(m.nt):
        _push_triangle(m, M, np.int64(t))
    for h in range(3 * m.nt):
        if m.tw[h] < 0:
            _push_segment(m, M, h)


@njit(cache=True)
def push_new(m, M, k, split):
    """Entries for the k new triangles cav[:k] and, after a split, the two new halves."""
    p = m.nv - 1
    for i in range(k):
        t = m.cav[i]
        _push_triangle(m, M, np.int64(t))
        if split:
            for e in range(3):
                h = 3 * t + e
                if m.tw[h] < 0 and (m.tv[h] == p or m.tv[nxt(h)] == p):
                    _push_segment(m, M, h)


@njit(cache=True)
def _current(m, a, b, xtol):
    """(alive, weight, x, y) of candidate (a, b) now (a subsegment is re-evaluated)."""
    if a >= 0:
        if m.tstamp[a] != b:
            return False, 0.0, 0.0, 0.0
        cx, cy, r = circumcircle(m.xy, m.tv[3 * a], m.tv[3 * a + 1], m.tv[3 * a + 2])
        return True, r / size_at(m, cx, cy), cx, cy
    h = m.vseg[-a - 1]
    if h < 0 or m.tv[nxt(h)] != b:
        return False, 0.0, 0.0, 0.0
    w, x, y = eval_segment(m, h, xtol)
    return True, w, x, y


# -- the pool of tied candidates -------------------------------------------------------------
# Slot s holds payload (pa, pb), weight pw, point (px, py); pgen[s] bumps when s is
# freed, so a heap entry (s, gen) is current while pgen[s] == gen; ploc[s] is 1 in
# the x-window, 0 outside; free slots are stacked in pfree[:nfree].  ``bound`` is the
# window bound B = x_min + xtol (-inf: no window).  Heaps: pv (value, all members),
# lo ((x, y), members outside the window), wx ((x, y)) and wy ((y, x)) of the window;
# sel is scratch for the y-window.


@structref.register
class PoolType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Pool(structref.StructRefProxy):
    """The tied group (see above)."""


structref.define_proxy(
    Pool,
    PoolType,
    ["pa", "pb", "pw", "px", "py", "pgen", "ploc", "pfree", "nslots", "nfree", "bound",
     "pv", "lo", "wx", "wy", "sel"],
)  # fmt: skip


@njit(cache=True)
def new_pool(capacity):
    c = max(capacity, 16)
    return Pool(
        np.empty(c, np.int32),
        np.empty(c, np.int32),
        np.empty(c, np.float64),
        np.empty(c, np.float64),
        np.empty(c, np.float64),
        np.zeros(c, np.int32),
        np.zeros(c, np.int8),
        np.empty(c, np.int32),
        0,
        0,
        -np.inf,
        heap.new_heap(c),
        heap.new_lheap(c),
        heap.new_lheap(c),
        heap.new_lheap(c),
        np.empty(16, np.int32),
    )


@njit(cache=True)
def _to_window(P, s):
    P.ploc[s] = 1
    heap.lpush(P.wx, P.px[s], P.py[s], np.int64(s), P.pgen[s])
    heap.lpush(P.wy, P.py[s], P.px[s], np.int64(s), P.pgen[s])


@njit(cache=True)
def _to_outside(P, s):
    P.ploc[s] = 0
    heap.lpush(P.lo, P.px[s], P.py[s], np.int64(s), P.pgen[s])


@njit(cache=True)
def _dump_window(P):
    """Move every window member back outside; the window is rebuilt next time."""
    while P.wx.size > 0:
        x, y, s, g = heap.lpop(P.wx)
        if P.pgen[s] == g and P.ploc[s] == 1:
            _to_outside(P, np.int64(s))
    P.wy.size = 0
    P.bound = -np.inf


@njit(cache=True)
def _grow_pool(P):
    c = 2 * P.nslots
    P.pa = heap.grown(P.pa, c)
    P.pb = heap.grown(P.pb, c)
    P.pw = heap.grown(P.pw, c)
    P.px = heap.grown(P.px, c)
    P.py = heap.grown(P.py, c)
    P.pgen = heap.grown(P.pgen, c)  # a new slot's generation may start anywhere
    P.ploc = heap.grown(P.ploc, c)  # set when the slot is filed
    P.pfree = heap.grown(P.pfree, c)


@njit(cache=True)
def _pool_add(P, a, b, w, x, y, xtol):
    if P.nfree > 0:
        P.nfree -= 1
        s = P.pfree[P.nfree]
    else:
        s = P.nslots
        if s == P.pa.shape[0]:
            _grow_pool(P)
        P.nslots = s + 1
    P.pa[s] = a
    P.pb[s] = b
    P.pw[s] = w
    P.px[s] = x
    P.py[s] = y
    heap.push(P.pv, w, s, P.pgen[s])
    if x < P.bound - xtol:  # a new smallest x: the window must be rebuilt around it
        _dump_window(P)
        _to_outside(P, np.int64(s))
    elif x <= P.bound:
        _to_window(P, np.int64(s))
    else:
        _to_outside(P, np.int64(s))


@njit(cache=True)
def _pool_kill(P, s):
    P.pgen[s] += 1
    P.pfree[P.nfree] = s
    P.nfree += 1


@njit(cache=True)
def _revalidate(m, M, P, s, thr, xtol):
    """Is member s current and unchanged?  If dead it is dropped; if changed it is
    re-filed with its fresh values (in the pool if still >= thr, else in M)."""
    a, b = P.pa[s], P.pb[s]
    alive, w, x, y = _current(m, a, b, xtol)
    if alive and w == P.pw[s] and x == P.px[s] and y == P.py[s]:
        return True
    _pool_kill(P, np.int64(s))
    if alive:
        if w >= thr:
            _pool_add(P, a, b, w, x, y, xtol)
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
    while P.pv.size > 0:
        w, s, g = P.pv.keys[0], P.pv.pa[0], P.pv.pb[0]
        if P.pgen[s] != g:
            heap.pop(P.pv)
            continue
        if _revalidate(m, M, P, s, np.inf, xtol):
            W = w
            break
    while M.size > 0 and (W < 0.0 or heap.top_key(M) >= tied_above(W, m.wg)):
        key, a, b = heap.pop(M)
        alive, w, x, y = _current(m, a, b, xtol)
        if not alive:
            continue
        if w < key and (W < 0.0 or w < tied_above(W, m.wg)):
            heap.push(M, w, a, b)  # stale subsegment key; it may come back
            continue
        if W < 0.0 and P.nslots == P.nfree and heap.top_key(M) < tied_above(w, m.wg):
            return w, a, b, x, y  # alone in its tied group
        _pool_add(P, a, b, w, x, y, xtol)
        if w > W:
            W = w
    return W, -1, -1, 0.0, 0.0


@njit(cache=True)
def _lclean(m, M, P, L, loc, thr, xtol):
    """Drop stale or invalid entries from the top of L (an (x, y) heap whose members
    have ploc == loc); returns the top x, or inf when L is empty."""
    while L.size > 0:
        x, s, g = heap.ltop(L)
        if P.pgen[s] != g or P.ploc[s] != loc:
            heap.lpop(L)
            continue
        if _revalidate(m, M, P, s, thr, xtol):
            return x
    return np.inf


@njit(cache=True)
def _choose(m, M, P, W, xtol):
    """Step 2: the slot of the canonical candidate (or -1)."""
    thr = tied_above(W, m.wg)
    while True:
        xw = _lclean(m, M, P, P.wx, np.int64(1), thr, xtol)
        xo = _lclean(m, M, P, P.lo, np.int64(0), thr, xtol)
        if xw == np.inf and xo == np.inf:
            return -1
        if xo < xw and xw != np.inf:  # a smaller x outside: rebuild the window
            _dump_window(P)
            continue
        P.bound = min(xw, xo) + xtol
        restart = False
        while P.lo.size > 0:  # pull members with x <= B into the window
            x, s, g = heap.ltop(P.lo)
            if P.pgen[s] != g or P.ploc[s] != 0:
                heap.lpop(P.lo)
                continue
            if x > P.bound:
                break
            heap.lpop(P.lo)
            if not _revalidate(m, M, P, s, thr, xtol):
                restart = True  # a re-filed member may have moved the anchor
                break
            _to_window(P, np.int64(s))
        if restart:
            continue
        ymin = np.inf
        nsel = 0
        while P.wy.size > 0:  # window members with y <= y_min + xtol
            y, s, g = heap.ltop(P.wy)
            if P.pgen[s] != g or P.ploc[s] != 1:
                heap.lpop(P.wy)
                continue
            if nsel > 0 and y > ymin + xtol:
                break
            if not _revalidate(m, M, P, s, thr, xtol):
                restart = True
                break
            heap.lpop(P.wy)
            if nsel == 0:
                ymin = y
            if nsel == P.sel.shape[0]:
                P.sel = heap.grown(P.sel, 2 * nsel)
            P.sel[nsel] = s
            nsel += 1
        best = -1
        for i in range(nsel):  # put them back; the smallest x wins
            s = P.sel[i]
            heap.lpush(P.wy, P.py[s], P.px[s], np.int64(s), P.pgen[s])
            if best < 0 or P.px[s] < P.px[best]:
                best = s
        if restart:
            continue
        if best >= 0:
            return best
        if not restart:
            _dump_window(P)


@njit(cache=True)
def run(m, M, P, n, out_xy, out_w, out_b, xtol, snap_d):
    """Insert n points; returns n, or a negative status on failure.

    A circumcentre closer than ``snap_d`` to a boundary subsegment of its triangle
    is placed on that subsegment (it is numerically on the boundary; inside it
    would only make a sliver).  Every point is rounded to what the caller's
    coordinates hold (:func:`cdt.snap`) before it is located and inserted, so the
    exact predicates decide on the coordinates actually returned.  On failure ``out_*[j]`` describe the failing
    point and the status is ``code - 100 * j``.
    """
    for j in range(n):
        w, a, b, x, y = _gather(m, M, P, xtol)
        if w < 0.0:
            return ERR_EMPTY - 100 * j
        if a == -1 and b == -1:
            s = _choose(m, M, P, w, xtol)
            if s < 0:
                return ERR_EMPTY - 100 * j
            a, w, x, y = P.pa[s], P.pw[s], P.px[s], P.py[s]
            _pool_kill(P, np.int64(s))
        if a >= 0:
            x, y = snap(m, x, y)
            loc = locate(m, np.int64(a), x, y, np.int64(64))
            if loc < -(m.tv.shape[0] + 1):  # the walk gave up: look everywhere
                loc = locate_scan(m, x, y)
                if loc < 0:
                    return ERR_LOCATE - 100 * j
            if loc >= 0:
                t0 = loc
                hsplit = _near_boundary(m, loc, x, y, snap_d)
            else:
                hsplit = -loc - 1  # the rounded circumcentre crossed this boundary edge
                t0 = hsplit // 3
            if hsplit >= 0:
                x, y = _project(m, hsplit, x, y)
                x, y = snap(m, x, y)
        else:
            hsplit = m.vseg[-a - 1]
            t0 = hsplit // 3
            x, y = snap(m, x, y)
        out_xy[j, 0] = x
        out_xy[j, 1] = y
        out_w[j] = w * size_at(m, x, y)  # the distance (w is distance / size)
        out_b[j] = hsplit >= 0
        k = ERR_PRECISION
        if _between(m, hsplit, x, y):
            k = insert_point(m, x, y, np.int64(t0), np.int64(hsplit))
        if k < 0:
            k, x, y = _insert_nearby(m, x, y, t0, hsplit)
            if k < 0:
                return k - 100 * j
            out_xy[j, 0] = x
            out_xy[j, 1] = y
        push_new(m, M, k, hsplit >= 0)
    return n


@njit(cache=True)
def _between(m, h, x, y):
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


@njit(cache=True)
def _insert_nearby(m, x, y, t0, hs):
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
            if not _between(m, hs, xn, yn):
                continue
            k = insert_point(m, xn, yn, np.int64(t0), np.int64(hs))
            if k >= 0:
                return k, xn, yn
    return ERR_PRECISION, x, y


@njit(cache=True)
def _near_boundary(m, t, x, y, snap):
    """A boundary half-edge of t within distance ``snap`` of (x, y), or -1."""
    xy = m.xy
    for i in range(3):
        h = 3 * t + i
        if m.tw[h] >= 0:
            continue
        u = m.tv[h]
        v = m.tv[nxt(h)]
        if _seg_dist2(xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], x, y) <= snap * snap:
            return h
    return -1


@njit(cache=True)
def _project(m, h, x, y):
    xy = m.xy
    u = m.tv[h]
    v = m.tv[nxt(h)]
    dx, dy = xy[v, 0] - xy[u, 0], xy[v, 1] - xy[u, 1]
    s = ((x - xy[u, 0]) * dx + (y - xy[u, 1]) * dy) / (dx * dx + dy * dy)
    s = min(1.0 - 1e-12, max(1e-12, s))
    return xy[u, 0] + s * dx, xy[u, 1] + s * dy
