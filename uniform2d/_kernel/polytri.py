"""An exact triangulation of a polygon with holes, for when GEOS's is not valid.

GEOS triangulates in floating point; on rings with exactly or nearly collinear
vertices it can cut a flat or inverted ear.  This one decides every sign with
the exact ``orient2d`` and ``incircle``, so it is correct for every simple
polygon with holes (the only input :class:`uniform2d.Polygon` accepts):

1. the Delaunay triangulation of the ring vertices inside a large enclosing
   triangle, by incremental insertion (:func:`.cavity.insert_sites`);
2. every ring edge recovered by flips (Sloan's method): the edges crossing it are
   queued, a crossing edge whose quadrilateral is strictly convex is flipped, one
   that is not waits for its turn; each flip removes a crossing or moves it on,
   and no vertex lies on an open ring edge, so this ends;
3. the triangles inside P kept: those reached from the left side of a ring edge
   (outer ring counter-clockwise, holes clockwise) without crossing a ring edge.

The result is a triangle list for :func:`.adjacency.build_adjacency`; it is not yet
Delaunay (the caller legalises).  Cost: O(V log V) for the Delaunay part and
O(V) per ring edge to find its start, so O(V^2) at worst -- it runs only when
GEOS's result fails the exact check.
"""

import numpy as np
from ._jit import njit
from .external import called_by_name

from ..errors import InternalError, PLEASE_REPORT
from .cavity import insert_sites
from .adjacency import build_adjacency
from .cdt import allocate, flip, nxt, prv, set_nv, triangle_list
from .lawson import legalize_all
from .predicates import orient2d

__all__ = ["triangulate", "recover_pieces"]

#: The enclosing triangle's half-size, in units of the (normalised) coordinates'
#: extent: far enough that it does not touch the polygon's hull.
FAR = 1e4


@njit(cache=True)
def _sign(xy, a, b, c):
    d = orient2d(xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1])
    return 1 if d > 0.0 else (-1 if d < 0.0 else 0)


@njit(cache=True)
def _first_out(m, a):
    """A half-edge leaving a to start a counter-clockwise turn from: its boundary
    half-edge if it has one (the turn then ends at -1), else any."""
    if m.vseg[a] >= 0:
        return m.vseg[a]
    for h in range(3 * m.nt):
        if m.tv[h] == a:
            return h
    return -1


@njit(cache=True)
def _out_edge(m, a, b):
    """The half-edge a -> b, or -1 (a turn around a)."""
    h0 = _first_out(m, a)
    h = h0
    while True:
        if m.tv[nxt(h)] == b:
            return h
        h = m.tw[prv(h)]
        if h < 0 or h == h0:
            return -1


@njit(cache=True)
def _crossings(m, u, v, ql, qr):
    """The edges crossing the open segment u-v as (left, right) vertex pairs into
    ql/qr (their count), 0 if u-v is an edge already, -1 if a vertex lies on it."""
    xy = m.xy
    if _out_edge(m, u, v) >= 0:
        return 0
    h0 = _first_out(m, u)
    h = h0
    e = -1
    while True:  # the triangle (u, b, c) at u that the segment enters
        b = m.tv[nxt(h)]
        c = m.tv[prv(h)]
        sb = _sign(xy, u, v, b)
        sc = _sign(xy, u, v, c)
        if sb == 0 and (xy[b, 0] - xy[u, 0]) * (xy[v, 0] - xy[u, 0]) + (xy[b, 1] - xy[u, 1]) * (xy[v, 1] - xy[u, 1]) > 0.0:
            return -1  # b on the segment
        if sb < 0 and sc > 0:
            e = nxt(h)  # b -> c, b right, c left
            break
        h = m.tw[prv(h)]
        if h < 0 or h == h0:
            return -1
    k = 0
    while True:
        ql[k] = m.tv[nxt(e)]
        qr[k] = m.tv[e]
        k += 1
        g = m.tw[e]
        if g < 0:
            return -1
        w = m.tv[prv(g)]
        if w == v:
            return k
        s = _sign(xy, u, v, w)
        if s == 0:
            return -1
        # g runs left -> right; the segment leaves through the edge joining w to
        # the end on w's other side: b -> w if w is left, w -> c if w is right
        e = nxt(g) if s > 0 else prv(g)


@njit(cache=True)
def _recover(m, u, v):
    """Make u-v an edge by flips (module docstring); False if that fails."""
    xy = m.xy
    n = m.nt
    ql = np.empty(3 * n + 4, np.int64)
    qr = np.empty(3 * n + 4, np.int64)
    k = _crossings(m, u, v, ql, qr)
    if k < 0:
        return False
    head = 0
    size = k
    cap = ql.shape[0]
    budget = 50 * (k + 4) * (k + 4)
    while size > 0:
        budget -= 1
        if budget < 0:
            return False
        a = ql[head]
        b = qr[head]
        head = (head + 1) % cap
        size -= 1
        h = _out_edge(m, a, b)
        if h < 0 or m.tw[h] < 0 or m.tc[h]:
            return False
        c = m.tv[prv(h)]
        d = m.tv[prv(m.tw[h])]
        if _sign(xy, c, d, a) * _sign(xy, c, d, b) < 0:
            flip(m, h)
            sc = _sign(xy, u, v, c)
            sd = _sign(xy, u, v, d)
            if sc * sd < 0:  # still crossing: queue it again
                tail = (head + size) % cap
                ql[tail] = c if sc > 0 else d
                qr[tail] = d if sc > 0 else c
                size += 1
        else:
            tail = (head + size) % cap
            ql[tail] = a
            qr[tail] = b
            size += 1
    return _out_edge(m, u, v) >= 0


@njit(cache=True)
def recover_pieces(m, us, vs):
    """Make every ``us[k] - vs[k]`` (interior constraint pieces, both ends vertices
    of the triangulation, no vertex strictly on them) an edge by flips, flag it
    constrained (both half-edges, :mod:`.cdt`), then legalise the rest.  Flips
    never cross a flagged edge, so pieces recovered earlier stay.  Returns 0, or
    -(k + 1) if piece k could not be recovered."""
    for k in range(us.shape[0]):
        u, v = us[k], vs[k]
        if not _recover_bn(m, u, v):
            return -(k + 1)
        h = _out_edge(m, u, v)
        g = m.tw[h]
        m.tc[h] = 1
        m.tc[g] = 1
        m.vcs[u] = h
        m.vcs[v] = g
    legalize_all(m)
    return 0


@njit(cache=True)
def _inside(m, ring_next, nV):
    """Triangles reached from the left of a ring edge without crossing one."""
    keep = np.zeros(m.nt, np.bool_)
    stack = np.empty(m.nt + 1, np.int64)
    sp = 0
    for u in range(nV):
        v = ring_next[u]
        if v < 0:
            continue
        h = _out_edge(m, u, v)
        t = h // 3
        if not keep[t]:
            keep[t] = True
            stack[sp] = t
            sp += 1
    while sp > 0:
        sp -= 1
        t = stack[sp]
        for i in range(3):
            h = 3 * t + i
            a = m.tv[h]
            b = m.tv[nxt(h)]
            if (a < nV and ring_next[a] == b) or (b < nV and ring_next[b] == a):
                continue
            g = m.tw[h]
            if g < 0:
                continue
            s = g // 3
            if not keep[s]:
                keep[s] = True
                stack[sp] = s
                sp += 1
    return keep


@njit(cache=True)
def _edges_ok(m, ring_next, nV):
    for u in range(nV):
        v = ring_next[u]
        if v >= 0 and not _recover_bn(m, u, v):
            return False
    return True


def triangulate(xy: np.ndarray, rings) -> np.ndarray:
    """(T, 3) counter-clockwise triangles of the polygon whose vertices ``xy``
    (N, 2) are joined by ``rings`` (lists of indices; outer ring counter-clockwise,
    holes clockwise), decided exactly; every ring vertex is a corner.  Raises
    InternalError if the rings are not a simple polygon with holes (P's rings
    are checked on construction: a bug)."""
    nV = len(xy)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    c = 0.5 * (lo + hi)
    r = FAR * max(float((hi - lo).max()), 1e-300)
    big = np.array([[c[0] - r, c[1] - r], [c[0] + r, c[1] - r], [c[0], c[1] + r]])
    m, buf = allocate(nV + 3, 2 * (nV + 3) + 8)
    buf[:nV] = xy
    buf[nV:] = big
    set_nv(m, nV + 3)
    build_adjacency(m, np.array([[nV, nV + 1, nV + 2]], np.int32))
    if insert_sites(m, np.lexsort((xy[:, 1], xy[:, 0])).astype(np.int64)) < 0:
        raise InternalError(f"exact triangulation: a vertex could not be inserted {PLEASE_REPORT}")
    ring_next = np.full(nV, -1, np.int64)
    for ring in rings:
        ring = np.asarray(ring, dtype=np.int64)
        ring_next[ring] = np.roll(ring, -1)
    if not _edges_ok(m, ring_next, nV):
        raise InternalError(
            f"exact triangulation: a ring edge could not be recovered {PLEASE_REPORT}")
    tris = triangle_list(m)
    return np.ascontiguousarray(tris[_inside(m, ring_next, nV)], dtype=np.int32)


_recover_bn = called_by_name(_recover)
