"""Inserting a point into the flat-array CDT (:mod:`.cdt`), always validly.

Insertion (Bowyer-Watson, cavity stopped at constraints)
--------------------------------------------------------
To insert ``p`` lying in triangle ``t0`` (or on its boundary subsegment ``hs``)::

        before: the cavity C              after: a fan around p
         c ________ d                     c ________ d
          |\\      /|                       |\\      /|
          | \\ t1 / |     every t with p     | \\    / |    each edge u->v of the
          |  \\  /  |     inside its         |  \\  /  |    cavity boundary gets
          | p.\\/   |     circumcircle,      |---p----|    the new triangle
          |   /\\   |     reachable from t0  |  /  \\  |    (u, v, p), re-using
          | t0 \\   |     without crossing   | /    \\ |    the cavity's slots
          |/    \\ t2|     a constraint      |/      \\|
         a -------- b                     a -------- b

The cavity grows from ``t0`` across an unconstrained edge ``u->v`` only when
``p`` sees that edge from inside (``orient2d(u, v, p) >= 0``) and lies strictly
inside the neighbour's circumcircle.  The visibility condition keeps the
cavity star-shaped from ``p`` even when a hole sits inside some circumcircle,
where plain Bowyer-Watson would capture triangles hidden behind the hole.  For a
boundary point the subsegment ``hs`` is left out of the fan and becomes the two
boundary half-edges ``a->p`` and ``p->b``.  Every new triangle is checked to be
strictly counter-clockwise with the exact predicate before anything is written.

Robustness.  A rounded point (a circumcentre, a boundary point a few ulps off its
edge's line) can leave the cavity not star-shaped: an edge of its boundary no
longer strictly visible from the point.  Then the point is inserted into ``t0``
alone -- with the neighbour across an edge of ``t0`` the point lies on -- and
Lawson flips restore the Delaunay property (:func:`_split_and_flip`).  That needs
only the point strictly inside ``t0``'s fan, which holds for any point in ``t0``
or on ``hs`` away from ``t0``'s corners, wherever rounding has put it.  Boundary
sites known to lie on a polygon edge split that edge's constraint by index
(:func:`split_sites`), not by where their rounded coordinates fall.
"""

import numpy as np
from ._jit import njit
from .external import called_by_name

from .cdt import (
    ERR_ORIENT, _orient_v, _set_triangle, link_on, locate, locate_scan, new_tag, nxt, prv, reserve,
)  # fmt: skip
from .lawson import _lawson
from .predicates import incircle

__all__ = ["insert_point", "insert_sites", "split_sites"]


@njit(cache=True)
def insert_point(m, x, y, t0, hs):
    """Insert (x, y) lying in triangle t0, or on its boundary half-edge hs (else hs = -1).

    The new vertex gets index ``nv``.  On success returns the number k of new or
    rewritten triangles, whose slots are ``cav[:k]``; on failure a negative status
    and the triangulation is unchanged.

    First the Bowyer-Watson cavity (module docstring).  Its seed t0 joins the
    cavity even when a point rounded across hs is just outside t0's circle; then
    Lawson flips from the fan make the result Delaunay (:func:`_flip_fan`).  If a
    rounded point makes the cavity not star-shaped (an edge of its boundary not
    strictly visible from the point), the point is inserted into t0 alone instead -- with the neighbour
    across an edge of t0 the point lies on -- and Lawson flips restore the
    Delaunay property (:func:`_split_and_flip`).  That only needs the point
    strictly inside t0's fan, which holds for any point in t0 or on hs away from
    t0's corners, wherever rounding has put it.
    """
    xy, tv = m.xy, m.tv
    a, b, c = tv[3 * t0], tv[3 * t0 + 1], tv[3 * t0 + 2]
    seeded = incircle(xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1], x, y) > 0.0
    piece = hs >= 0 and m.tw[hs] >= 0
    ea = tv[hs] if piece else -1
    eb = tv[nxt(hs)] if piece else -1
    tag = new_tag(m)
    ncav = _grow_cavity(m, x, y, t0, hs, tag)
    nb = _cavity_boundary(m, x, y, ncav, hs, tag)
    if nb < 0:
        return _split_and_flip(m, x, y, t0, hs)
    _write_fan(m, x, y, ncav, nb, tag)
    if piece:
        _flag_split(m, ea, eb, nb)
    if not seeded:  # t0 joined the cavity without p in its circle: flips mend that
        return _flip_fan(m, nb)
    return nb


@njit(cache=True, inline="always")
def _grow_cavity(m, x, y, t0, hs, tag):
    """Triangles whose circumcircle holds (x, y), reached from t0 across edges the
    point sees and that are not constraints; ``cav[:k]``, marked with ``tag``."""
    xy, tv, tw = m.xy, m.tv, m.tw
    ncav = 1
    m.cav[0] = t0
    m.tmark[t0] = tag
    sp = 1
    m.stack[0] = t0
    if hs >= 0 and tw[hs] >= 0:  # on an interior piece: both sides from the start
        n = tw[hs] // 3
        m.cav[1] = n
        m.tmark[n] = tag
        m.stack[1] = n
        ncav = 2
        sp = 2
    while sp > 0:
        sp -= 1
        t = m.stack[sp]
        for i in range(3):
            h = 3 * t + i
            if h == hs:
                continue
            g = tw[h]
            if g < 0 or m.tc[h]:
                continue
            n = g // 3
            if m.tmark[n] == tag:
                continue
            u = tv[h]
            v = tv[nxt(h)]
            if _orient_v(xy, u, v, x, y) < 0.0:
                continue
            w = tv[prv(g)]
            if incircle(xy[v, 0], xy[v, 1], xy[u, 0], xy[u, 1], xy[w, 0], xy[w, 1], x, y) > 0.0:
                if ncav + 3 > m.stack.shape[0]:  # (a call costs more than the test)
                    reserve(m, ncav + 3)
                m.tmark[n] = tag
                m.cav[ncav] = n
                ncav += 1
                m.stack[sp] = n
                sp += 1
    return ncav


@njit(cache=True)
def _cavity_boundary(m, x, y, ncav, hs, tag):
    """The cavity's boundary half-edges into ``bh`` (their count), or ERR_ORIENT if
    the point does not see one of them strictly (checked before anything is written)."""
    xy, tv, tw = m.xy, m.tv, m.tw
    nb = 0
    for k in range(ncav):
        t = m.cav[k]
        for i in range(3):
            h = 3 * t + i
            if h == hs:
                continue
            g = tw[h]
            # a flagged edge stays unless it is the piece being split (the
            # cavity then holds both its sides); with both sides of another
            # piece in the cavity, p cannot see both and the check below fails
            if g >= 0 and m.tmark[g // 3] == tag and (m.tc[h] == 0 or g == hs):
                continue
            if _orient_v(xy, tv[h], tv[nxt(h)], x, y) <= 0.0:
                return ERR_ORIENT
            if nb + 1 > m.stack.shape[0]:
                reserve(m, nb + 1)
            m.bh[nb] = h
            nb += 1
    return nb


@njit(cache=True)
def _write_fan(m, x, y, ncav, nb, tag):
    """Replace the cavity ``cav[:ncav]`` by the fan of new triangles (u, v, p) over
    its boundary ``bh[:nb]``, p the new vertex; the slots used end up in ``cav[:nb]``."""
    xy, tv, tw = m.xy, m.tv, m.tw
    if nb + 1 > m.stack.shape[0]:
        reserve(m, nb + 1)
    # read every boundary edge before slots are overwritten
    p = m.nv
    xy[p, 0] = x
    xy[p, 1] = y
    m.vseg[p] = -1
    m.vcs[p] = -1
    m.nv = p + 1
    nt = m.nt
    bu = m.vbuf  # reused as scratch: u, v, outer twin of each boundary edge
    for k in range(nb):
        h = m.bh[k]
        m.stack[k] = tw[h]
        bu[k] = tv[h]
        m.ebuf[k] = tv[nxt(h)]
    for k in range(ncav, nb):
        m.cav[k] = nt + (k - ncav)
    if nb > ncav:
        m.nt = nt + (nb - ncav)
    for k in range(nb):
        s = m.cav[k]
        u = bu[k]
        _set_triangle(m, np.int64(s), np.int64(u), np.int64(m.ebuf[k]), np.int64(p))
        link_on(tw, m.tc, tv, m.vcs, m.vseg, 3 * s, m.stack[k])
        tw[3 * s + 1] = -1
        tw[3 * s + 2] = -1
        m.tc[3 * s + 1] = 0
        m.tc[3 * s + 2] = 0
        m.vmark[u] = tag
        m.vmap[u] = k
    for k in range(nb):
        s = m.cav[k]
        v = m.ebuf[k]
        if m.vmark[v] == tag:
            j = m.cav[m.vmap[v]]
            tw[3 * s + 1] = 3 * j + 2
            tw[3 * j + 2] = 3 * s + 1
    for k in range(nb):
        s = m.cav[k]
        if tw[3 * s + 1] < 0:
            m.vseg[tv[3 * s + 1]] = 3 * s + 1  # v -> p is a new boundary half-edge
        if tw[3 * s + 2] < 0:
            m.vseg[p] = 3 * s + 2  # p -> u


@njit(cache=True)
def _flag_split(m, a, b, nb):
    """After splitting the interior piece a-b at the new vertex p: flag both
    halves a-p and p-b (spokes of the fan ``cav[:nb]``, both half-edges)."""
    tv, tw = m.tv, m.tw
    p = m.nv - 1
    for k in range(nb):
        s = m.cav[k]
        h = 3 * s + 1  # v -> p
        v = tv[h]
        if v == a or v == b:
            g = tw[h]
            m.tc[h] = 1
            m.tc[g] = 1
            m.vcs[v] = h
            m.vcs[p] = g


@njit(cache=True, inline="always")
def _split_and_flip(m, x, y, t0, hs):
    """Insert (x, y) into t0 (and the neighbour across an unconstrained edge of t0
    it lies on), then Lawson-flip from the new triangles' outer edges.

    Valid for any point strictly inside the fan of t0 (see :func:`insert_point`);
    flips only replace edges whose quadrilateral is strictly convex (an illegal
    edge's always is), so every triangle stays strictly counter-clockwise.
    Returns the number of new or rewritten slots (``cav[:k]``), or ERR_ORIENT.
    """
    xy, tv, tw = m.xy, m.tv, m.tw
    tag = new_tag(m)
    m.cav[0] = t0
    m.tmark[t0] = tag
    ncav = np.int64(1)
    piece = hs >= 0 and tw[hs] >= 0
    for i in range(3):
        h = 3 * t0 + i
        g = tw[h]
        if g >= 0 and (h == hs or (m.tc[h] == 0 and _orient_v(xy, tv[h], tv[nxt(h)], x, y) == 0.0)):
            reserve(m, ncav + 2)
            m.cav[ncav] = g // 3
            m.tmark[g // 3] = tag
            ncav += 1
    nb = _cavity_boundary(m, x, y, ncav, hs, tag)
    if nb < 0:
        return ERR_ORIENT
    ea = tv[hs] if piece else -1
    eb = tv[nxt(hs)] if piece else -1
    _write_fan(m, x, y, ncav, nb, tag)
    if piece:
        _flag_split(m, ea, eb, nb)
    return _flip_fan(m, nb)


@njit(cache=True, inline="always")
def _flip_fan(m, nb):
    """Lawson flips from every edge of the fan ``cav[:nb]``, spokes included (with
    the point not in its first triangle's circle, a spoke need not be Delaunay);
    every rewritten slot joins ``cav``.  Returns their count."""
    tw = m.tw
    tag = new_tag(m)
    todo = np.empty(3 * nb + 16, np.int32)
    sp = 0
    for k in range(nb):
        s = m.cav[k]
        m.tmark[s] = tag
        for i in range(3):
            if tw[3 * s + i] >= 0:
                todo[sp] = 3 * s + i
                sp += 1
    return _lawson(m, todo, np.int64(sp), tag, nb)


@njit(cache=True)
def insert_sites(m, idx):
    """Insert the vertices ``idx`` (coordinates already in ``xy``) in the given order,
    each keeping its own index.  Walks from the last new triangle, so a spatially
    coherent order makes each location O(1).  Returns 0, or -(k + 1) if site k
    could not be inserted."""
    nv = m.nv
    t = 0
    for k in range(idx.shape[0]):
        v = idx[k]
        x = m.xy[v, 0]
        y = m.xy[v, 1]
        loc = locate(m, np.int64(t), x, y, np.int64(4096), np.bool_(False))
        if loc < 0:
            loc = locate_scan(m, x, y)
            if loc < 0:
                m.nv = nv
                return -(k + 1)
        m.nv = v
        if _insert_point(m, x, y, np.int64(loc), np.int64(-1)) < 0:
            m.nv = nv
            return -(k + 1)
        t = m.cav[0]
    m.nv = nv
    return 0


@njit(cache=True)
def split_sites(m, idx, first):
    """Put the boundary vertices ``idx`` (coordinates already in ``xy``) on their
    constraints by index, not by geometry: ``idx`` lists the sites of each polygon
    edge in order along it, and ``first[k]`` is the vertex the chain of ``idx[k]``
    starts from (the edge's start vertex, or the site before it on the edge), so
    site k splits the boundary half-edge leaving ``first[k]``.  Where rounding
    put the site a little off its edge, the split is still valid when every new
    triangle is strictly counter-clockwise, which :func:`insert_point` checks.
    Returns 0, or -(k + 1) if site k could not be put there."""
    nv = m.nv
    for k in range(idx.shape[0]):
        v = idx[k]
        hs = m.vseg[first[k]]
        m.nv = v
        if hs < 0 or insert_point(m, m.xy[v, 0], m.xy[v, 1], np.int64(hs // 3), np.int64(hs)) < 0:
            m.nv = nv
            return -(k + 1)
    m.nv = nv
    return 0


_insert_point = called_by_name(insert_point)
