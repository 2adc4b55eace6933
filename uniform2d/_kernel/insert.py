"""Algorithm INSERT on the flat-array CDT: one loop, pop -> validate -> insert -> push.

Candidates (design notes §2) and their heap entries ``(key, a, b)``:

* a triangle ``t`` whose circumcentre lies in the closed triangle -- no obtuse
  angle, and no right angle facing a boundary edge (that circumcentre is the
  midpoint of a boundary subsegment and belongs to the subsegment's entry).
  Entry ``(R, t, tstamp[t])``.  Its value never changes while the triangle lives.
* a boundary subsegment ``u -> v``.  Entry ``(key, -(u + 1), v)``, where the key
  is an upper bound of its value (first |uv|/2); re-evaluated when popped.

Every value only decreases as sites are added, so keys are upper bounds and the
first popped entry whose value survives re-evaluation is a global maximum W.
Ties: every entry with key >= W (1 - REL_TIE) is popped and validated, and the
candidate with the lexicographically smallest (x, y) wins, x compared with the
tolerance ``xtol`` = REL_X times the polygon's size.  The kernel computes on the
caller's coordinates (not normalised ones), so that the exact predicates
certify the very coordinates returned; every tolerance is relative, which makes
the sequence invariant under scaling and translation all the same.
"""

import numpy as np
from numba import njit

from . import heap
from .cdt import ERR_ORIENT, circumcircle, insert_point, locate, new_tag, nxt, prv
from .predicates import dot2d, orient2d

REL_TIE = 1e-9
REL_X = 1e-9
DISK_SLACK = 1e-12  # inclusive slack when collecting sites near a subsegment (harmless)

ERR_EMPTY = -10  # no candidate left (cannot happen for a valid polygon)
ERR_LOCATE = -11  # a circumcentre could not be located (cannot happen)


@njit(cache=True)
def triangle_key(m, t):
    """Circumradius of t if its circumcentre is a candidate (see module doc), else -1."""
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
    return r


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
    """Largest visible distance on boundary subsegment h and where: (value, x, y).

    If the apex of the triangle on h is outside the open diametral disk of h, no
    visible site is inside that disk and the midpoint wins with |h|/2.
    Otherwise gather, by a search across unconstrained edges that meet the disk,
    the sites in it and the constrained edges around them; the maximum of the
    visible lower envelope is at a point of h equidistant from two of them.
    """
    xy = m.xy
    a = m.tv[h]
    b = m.tv[nxt(h)]
    c = m.tv[prv(h)]
    ax, ay, bx, by = xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1]
    dx, dy = bx - ax, by - ay
    half = 0.5 * np.sqrt(dx * dx + dy * dy)
    if dot2d(ax, ay, bx, by, xy[c, 0], xy[c, 1]) >= 0.0:
        return half, ax + 0.5 * dx, ay + 0.5 * dy
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
        sp -= 1
        t = m.stack[sp]
        for i in range(3):
            e = 3 * t + i
            w = m.tv[e]
            if m.vmark[w] != tag:
                m.vmark[w] = tag
                ddx, ddy = xy[w, 0] - mx, xy[w, 1] - my
                if ddx * ddx + ddy * ddy < r2:
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
    best = -1.0
    bx_, by_ = mx, my
    cand_v = np.empty(ns * (ns - 1) // 2, np.float64)
    cand_x = np.empty(ns * (ns - 1) // 2, np.float64)
    cand_y = np.empty(ns * (ns - 1) // 2, np.float64)
    nc = 0
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
                if d2 < wmin and (k < 2 or _visible(m, ne, x, y, z)):
                    wmin = d2
            val = np.sqrt(wmin)
            cand_v[nc] = val
            cand_x[nc] = x
            cand_y[nc] = y
            nc += 1
            if val > best:
                best = val
    if nc == 0:
        return half, mx, my
    k = choose(cand_v, cand_x, cand_y, nc, best, xtol)
    return cand_v[k], cand_x[k], cand_y[k]


@njit(cache=True)
def choose(vals, xs, ys, nc, best, xtol):
    """The canonical candidate among the first nc: weight >= best (1 - REL_TIE), then
    smallest x (within xtol), then smallest y, then smallest x."""
    thr = best * (1.0 - REL_TIE)
    xmin = np.inf
    for i in range(nc):
        if vals[i] >= thr and xs[i] < xmin:
            xmin = xs[i]
    k = -1
    for i in range(nc):
        if vals[i] >= thr and xs[i] <= xmin + xtol:
            if k < 0 or ys[i] < ys[k] or (ys[i] == ys[k] and xs[i] < xs[k]):
                k = i
    return k


@njit(cache=True)
def _validate(m, key, a, b, xtol):
    """(alive, value, x, y) of a popped entry; for a subsegment the value is fresh."""
    if a >= 0:
        if m.tstamp[a] != b:
            return False, 0.0, 0.0, 0.0
        cx, cy, r = circumcircle(m.xy, m.tv[3 * a], m.tv[3 * a + 1], m.tv[3 * a + 2])
        return True, key, cx, cy
    u = -a - 1
    h = m.vseg[u]
    if h < 0 or m.tv[nxt(h)] != b:
        return False, 0.0, 0.0, 0.0
    val, x, y = eval_segment(m, h, xtol)
    return True, val, x, y


@njit(cache=True)
def push_new(m, hk, ha, hb, hs, k, split_h, p):
    """Push the candidates created by an insertion: the k new triangles cav[:k] and,
    after a boundary split, the two new subsegments around vertex p."""
    for i in range(k):
        t = m.cav[i]
        r = triangle_key(m, t)
        if r > 0.0:
            hk, ha, hb = heap.push(hk, ha, hb, hs, r, t, m.tstamp[t])
    if split_h:
        h1 = np.int64(m.vseg[p])
        h0 = np.int64(_boundary_into(m, p))
        for h in (h0, h1):
            u = m.tv[h]
            v = m.tv[nxt(h)]
            ddx = m.xy[v, 0] - m.xy[u, 0]
            ddy = m.xy[v, 1] - m.xy[u, 1]
            hk, ha, hb = heap.push(hk, ha, hb, hs, 0.5 * np.sqrt(ddx * ddx + ddy * ddy), -(u + 1), v)
    return hk, ha, hb


@njit(cache=True)
def _boundary_into(m, p):
    """The boundary half-edge ending at boundary vertex p (walk around p)."""
    h = m.vseg[p]  # p -> v; rotate clockwise around p until no twin
    e = prv(h)  # w -> p in the same triangle
    while m.tw[e] >= 0:
        e = prv(m.tw[e])
    return e


@njit(cache=True)
def push_initial(m, hk, ha, hb, hs):
    """Entries for every candidate triangle and every boundary subsegment."""
    for t in range(m.st[1]):
        r = triangle_key(m, t)
        if r > 0.0:
            hk, ha, hb = heap.push(hk, ha, hb, hs, r, t, m.tstamp[t])
    for h in range(3 * m.st[1]):
        if m.tw[h] < 0:
            u = m.tv[h]
            v = m.tv[nxt(h)]
            ddx = m.xy[v, 0] - m.xy[u, 0]
            ddy = m.xy[v, 1] - m.xy[u, 1]
            hk, ha, hb = heap.push(hk, ha, hb, hs, 0.5 * np.sqrt(ddx * ddx + ddy * ddy), -(u + 1), v)
    return hk, ha, hb


@njit(cache=True)
def run(m, hk, ha, hb, hs, n, out_xy, out_w, out_b, xtol, snap):
    """Insert n points; returns (status, hk, ha, hb): status = points inserted, or < 0.

    ``xtol`` is the tie tolerance on x; a circumcentre closer than ``snap`` to a
    boundary subsegment of its triangle is placed on that subsegment (it is
    numerically on the boundary; inside it would only make a sliver).
    """
    cap = 16
    cv = np.empty(cap, np.float64)
    cx_ = np.empty(cap, np.float64)
    cy_ = np.empty(cap, np.float64)
    ca = np.empty(cap, np.int32)
    cb = np.empty(cap, np.int32)
    for j in range(n):
        # -- pop until the first entry that survives validation: the maximum W
        nc = 0
        best = -1.0
        while True:
            if hs[0] == 0:
                if nc > 0:
                    break
                return ERR_EMPTY, hk, ha, hb
            if nc > 0 and heap.top_key(hk, hs) < best * (1.0 - REL_TIE):
                break
            key, a, b = heap.pop(hk, ha, hb, hs)
            alive, val, x, y = _validate(m, key, a, b, xtol)
            if not alive:
                continue
            if a < 0 and val < key:
                # stale subsegment key: re-queue with the fresh value; it comes back
                # (and is accepted, value == key) if it is still the largest
                hk, ha, hb = heap.push(hk, ha, hb, hs, val, a, b)
                continue
            if nc == cap:
                cap *= 2
                cv = _grow_f(cv, cap)
                cx_ = _grow_f(cx_, cap)
                cy_ = _grow_f(cy_, cap)
                ca = _grow_i(ca, cap)
                cb = _grow_i(cb, cap)
            cv[nc] = val
            cx_[nc] = x
            cy_[nc] = y
            ca[nc] = a
            cb[nc] = b
            nc += 1
            if val > best:
                best = val
        k = choose(cv, cx_, cy_, nc, best, xtol)
        for i in range(nc):
            if i != k:
                hk, ha, hb = heap.push(hk, ha, hb, hs, cv[i], ca[i], cb[i])
        # -- insert the winner
        a = ca[k]
        x = cx_[k]
        y = cy_[k]
        if a >= 0:
            loc = locate(m, a, x, y, 64)
            if loc >= 0:
                t0 = loc
                hsplit = _near_boundary(m, loc, x, y, snap)
            elif loc > -(m.tv.shape[0] + 2):
                hsplit = -loc - 1  # the rounded circumcentre crossed this boundary edge
                t0 = hsplit // 3
            else:
                return ERR_LOCATE - 100 * j, hk, ha, hb
            if hsplit >= 0:
                x, y = _project(m, hsplit, x, y)
        else:
            hsplit = m.vseg[-a - 1]
            t0 = hsplit // 3
        p = m.st[0]
        out_xy[j, 0] = x
        out_xy[j, 1] = y
        out_w[j] = cv[k]
        out_b[j] = hsplit >= 0
        kk = insert_point(m, x, y, t0, hsplit)
        if kk < 0:  # out_*[j] describe the point that failed
            return kk - 100 * j, hk, ha, hb
        hk, ha, hb = push_new(m, hk, ha, hb, hs, kk, hsplit >= 0, p)
    return n, hk, ha, hb


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


@njit(cache=True)
def _grow_f(a, cap):
    out = np.empty(cap, np.float64)
    out[: a.shape[0]] = a
    return out


@njit(cache=True)
def _grow_i(a, cap):
    out = np.empty(cap, np.int32)
    out[: a.shape[0]] = a
    return out
