"""Constrained Delaunay triangulation of a polygon with holes, in flat arrays.

Layout (as in delaunator and Triangle)
--------------------------------------
Triangle ``t`` owns the three half-edges ``h = 3*t + i`` (i = 0, 1, 2)::

                 tv[3t+2]
                   /\\
        h = 3t+2  /  \\  h = 3t+1         half-edge h runs from tv[h] to tv[nxt(h)],
                 /    \\                   the triangle is on its left (CCW order);
        tv[3t] ------- tv[3t+1]           nxt(h) = 3t + (i+1) % 3, prv(h) = 3t + (i+2) % 3;
                 h = 3t                   tw[h] = the opposite half-edge, or -1.

Only the inside of P is triangulated.  Its boundary edges are the half-edges
with no twin (``tw[h] == -1``): every place that means "boundary, no neighbour"
reads that.  An interior constraint piece (a segment of the polygon, split at
the points on it) is a pair of twins like any interior edge, with the flag
``tc[h] = tc[tw[h]] = 1``: a point on it sees both sides, its triangles are
neighbours for walks and turns around a vertex, but flips, Bowyer-Watson
cavities, searches and visibility stop at it as at the boundary.  So **a
half-edge is constrained exactly when ``tw[h] < 0 or tc[h]``**.  A flag lives
with the edge, not the slot: whoever links a half-edge to an existing twin
copies the twin's flag (:func:`link_on`), new inner edges are unflagged, and only
splitting a piece (:mod:`.cavity`) and loading the segments
(:mod:`.polytri`) set flags.  ``vseg[v]`` is the boundary half-edge leaving
boundary vertex ``v`` (each boundary vertex has exactly one: rings are disjoint
and simple), -1 inside; ``vcs[v]`` is some flagged half-edge leaving ``v``, -1
for a vertex on no interior piece.
``tstamp[t]`` counts rewrites of slot ``t``, so a stored ``(t, stamp)`` pair tells
whether a triangle still exists.  Everything is preallocated to its final size and
held by one mutable ``Tri`` structref (a numba record passed by reference: one
reference count per call, where a tuple of arrays costs one per array).

Invariants that keep the triangulation valid
--------------------------------------------
Every triangle is strictly counter-clockwise (exact ``orient2d``), twins run in
opposite directions, and the twinless half-edges are exactly the rings' edges
split at their boundary vertices.  Each operation keeps this by construction:

* the initial triangulation is accepted only after :func:`count_not_ccw` and
  :func:`boundary_is` say so (GEOS decides in floating point and can cut a flat
  or inverted ear where a boundary site is rounded a few ulps off a rotated
  edge); otherwise the caller triangulates the polygon's own rings and
  :func:`.cavity.split_sites` puts each boundary site on its constraint by index;
* insertion (:mod:`.cavity`) writes nothing until every new triangle is checked
  strictly counter-clockwise, and falls back to split-and-flip where a rounded
  point leaves the Bowyer-Watson cavity not star-shaped;
* a flip is made only for an illegal edge, whose quadrilateral is strictly
  convex, and never across a constraint;
* new points are rounded to the caller's coordinates (:func:`snap`) before any
  of this, so every decision is made on the coordinates actually returned.

The initial triangulation comes from ``shapely.constrained_delaunay_triangles``
(loaded by :func:`.adjacency.build_adjacency`) and is then made exactly
(constrained) Delaunay by Lawson flips (:mod:`.lawson`) decided with our own
exact ``incircle``: a flip (:func:`flip`) replaces the diagonal of the
quadrilateral (a, d, b, c)::

           c                 c
          /|\\              /   \\
         / | \\    flip     /  t  \\
        a t|t' b   --->   a-------b      t = (c, a, d), t' = (d, b, c)
         \\ | /             \\  t' /
          \\|/               \\   /
           d                 d
"""

import math

import numpy as np
from numba import types
from numba.experimental import structref

from ._jit import njit
from .heap import grown
from .predicates import orient2d

__all__ = [
    "Tri", "allocate", "copied", "counts", "set_nv",
    "locate", "locate_scan", "reserve", "triangle_list", "circumcircle",
    "snap", "boundary_is", "count_not_ccw", "constrained",
]  # fmt: skip

#: Initial size of the scratch buffers; cavities and searches are small in practice,
#: and the buffers double when one is not.
SCRATCH = 256

# Status codes returned by cavity.insert_point (>= 0 means success: number of new triangles).
ERR_ORIENT = -1  # a new triangle would not be strictly counter-clockwise


@structref.register
class TriType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Tri(structref.StructRefProxy):
    """The triangulation state (fields listed in ``_FIELDS``)."""


_FIELDS = [
    "xy",  # (nmax, 2) float64 vertex coordinates (normalised)
    "tv",  # (3*tmax,) int32 origin vertex of each half-edge
    "tw",  # (3*tmax,) int32 twin half-edge or -1 (constrained)
    "tstamp",  # (tmax,) int32 rewrite counter of each triangle slot
    "vseg",  # (nmax,) int32 boundary half-edge leaving each vertex, or -1
    "tmark",  # (tmax,) int32 scratch tags (cavity / search membership)
    "vmark",  # (nmax,) int32 scratch tags on vertices
    "vmap",  # (nmax,) int32 scratch map vertex -> local index
    "stack",  # int32 scratch stack of triangles (grows on demand)
    "cav",  # int32 cavity triangles / new triangle slots (grows on demand)
    "bh",  # int32 cavity boundary half-edges (grows on demand)
    "vbuf",  # int32 collected vertices (subsegment search; grows on demand)
    "ebuf",  # int32 collected constrained half-edges (grows on demand)
    "nv",  # int64 number of vertices
    "nt",  # int64 number of triangles
    "tag",  # int64 last scratch tag handed out
    "sgx",  # (nx,) float64 size-field grid abscissae (normalised)
    "sgy",  # (ny,) float64 size-field grid ordinates
    "sgv",  # (ny, nx) float64 size-field values
    "hmin",  # float64 smallest size value (1.0 without a field)
    "sized",  # int64 1 when a size field is in use
    "gc",  # (2,) float64 the caller's origin in these coordinates' units (see snap)
    "gs",  # float64 the caller's units per unit here (a power of two)
    "wg",  # float64 how far rounding to the caller's coordinates can move a distance
    "tc",  # (3*tmax,) int8 1 on both half-edges of an interior constraint piece
    "vcs",  # (nmax,) int32 a flagged half-edge leaving each vertex, or -1
]
structref.define_proxy(Tri, TriType, _FIELDS)


@njit(cache=True)
def _new_tri(xy, tv, tw, tstamp, vseg, tmark, vmark, vmap, stack, cav, bh, vbuf, ebuf,
             sgx, sgy, sgv, sized, gc, gs, wg, tc, vcs):  # fmt: skip
    hmin = 1.0
    if sized:  # a loop: the generic array min costs more to compile
        hmin = np.inf
        for j in range(sgv.shape[0]):
            for i in range(sgv.shape[1]):
                hmin = min(hmin, sgv[j, i])
    return Tri(xy, tv, tw, tstamp, vseg, tmark, vmark, vmap, stack, cav, bh, vbuf, ebuf,
               0, 0, 0, sgx, sgy, sgv, hmin, sized, gc, gs, wg, tc, vcs)  # fmt: skip


@njit(cache=True)
def copied(m):
    """A copy of the triangulation ``m``, every array its own: (the copy, its
    coordinate array).  A load starts from a kept copy of the rings'
    triangulation (:func:`uniform2d.triangulation.load`)."""
    c = Tri(m.xy.copy(), m.tv.copy(), m.tw.copy(), m.tstamp.copy(), m.vseg.copy(),
            m.tmark.copy(), m.vmark.copy(), m.vmap.copy(), m.stack.copy(), m.cav.copy(),
            m.bh.copy(), m.vbuf.copy(), m.ebuf.copy(), m.nv, m.nt, m.tag, m.sgx.copy(),
            m.sgy.copy(), m.sgv.copy(), m.hmin, m.sized, m.gc.copy(), m.gs, m.wg, m.tc.copy(),
            m.vcs.copy())
    return c, c.xy


@njit(cache=True)
def counts(m):
    """(number of vertices, number of triangles)."""
    return m.nv, m.nt


@njit(cache=True)
def set_nv(m, nv):
    m.nv = nv


def allocate(nmax, tmax, size_grid=None, grid=None):
    """Preallocate a triangulation for at most ``nmax`` vertices and ``tmax`` triangles.

    ``size_grid`` is an optional ``(x (nx,), y (ny,), values (ny, nx))`` size field in
    the kernel's coordinates.  ``grid`` is ``(centre, scale)`` of the map to the
    caller's coordinates, X = x * scale + centre (default: the identity), which
    :func:`snap` rounds new points to, optionally with a third entry: how far that
    rounding can move a distance (here; 0 by default).  Returns ``(m, xy)``: the state and its
    coordinate array (shared, for filling).
    """
    gc, gs, wg = (np.zeros(2), 1.0, 0.0) if grid is None else (tuple(grid) + (0.0,))[:3]
    if size_grid is None:
        size_grid = (np.array([0.0, 1.0]), np.array([0.0, 1.0]), np.ones((2, 2)))
        sized = 0
    else:
        sized = 1
    gx, gy, gv = (np.ascontiguousarray(a, dtype=np.float64) for a in size_grid)
    xy = np.zeros((nmax, 2), np.float64)
    m = _new_tri(
        xy,
        np.full(3 * tmax, -1, np.int32),
        np.full(3 * tmax, -1, np.int32),
        np.zeros(tmax, np.int32),
        np.full(nmax, -1, np.int32),
        np.zeros(tmax, np.int32),
        np.zeros(nmax, np.int32),
        np.zeros(nmax, np.int32),
        np.zeros(SCRATCH, np.int32),
        np.zeros(SCRATCH, np.int32),
        np.zeros(SCRATCH, np.int32),
        np.zeros(SCRATCH, np.int32),
        np.zeros(SCRATCH, np.int32),
        gx,
        gy,
        gv,
        sized,
        np.ascontiguousarray(gc, dtype=np.float64),
        float(gs),
        float(wg),
        np.zeros(3 * tmax, np.int8),
        np.full(nmax, -1, np.int32),
    )
    return m, xy


@njit(cache=True)
def reserve(m, k):
    """Room for k entries in every scratch buffer."""
    if k > m.stack.shape[0]:
        m.stack = grown(m.stack, k)
        m.cav = grown(m.cav, k)
        m.bh = grown(m.bh, k)
        m.vbuf = grown(m.vbuf, k)
        m.ebuf = grown(m.ebuf, k)


@njit(cache=True, borrowed=True)
def nxt(h):
    return h - 2 if h % 3 == 2 else h + 1


@njit(cache=True, borrowed=True)
def prv(h):
    return h + 2 if h % 3 == 0 else h - 1


@njit(cache=True, borrowed=True)
def _orient_v(xy, u, v, x, y):
    return orient2d(xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], x, y)


@njit(cache=True)
def snap(m, x, y):
    """(x, y) rounded to the nearest point the caller's coordinates can hold.

    New points (circumcentres, boundary points, moved points) are rounded before
    any decision is made on them, so the mesh the predicates certify is exactly
    the one the caller gets.  With ``scale`` a power of two and each component of
    ``centre`` either 0 or at least twice the polygon's size from 0 (Sterbenz:
    X - centre is then exact for every X in the polygon's box), X - centre and the
    division are exact; near the origin (centre 0) this is the identity.
    """
    return snap_to(m.gs, m.gc[0], m.gc[1], x, y)


@njit(cache=True, borrowed=True)
def snap_to(s, cx, cy, x, y):
    """:func:`snap` with the triangulation's grid ``(m.gs, m.gc[0], m.gc[1])``
    read once by the caller: the loops that snap every trial place would
    otherwise pass the structref, and count a reference to it, each time."""
    return ((x * s + cx) - cx) / s, ((y * s + cy) - cy) / s


@njit(cache=True, borrowed=True)
def snap_times(s, r, cx, cy, x, y):
    """:func:`snap_to` with ``r`` from :func:`snap_reciprocal`: the division
    by s, a power of two, made as the multiplication by its exact reciprocal
    (both round the same real number once: the same bits, for a fraction of
    a division's time; the line search snaps every trial place); r = 0:
    divided."""
    if r != 0.0:
        return ((x * s + cx) - cx) * r, ((y * s + cy) - cy) * r
    return snap_to(s, cx, cy, x, y)


@njit(cache=True, borrowed=True)
def snap_reciprocal(s):
    """1 / s if that is exact (s a power of two whose reciprocal is a float:
    the grids of :func:`allocate`), else 0 (:func:`snap_times` then divides)."""
    if math.frexp(s)[0] != 0.5:
        return 0.0
    r = 1.0 / s
    return r if r * s == 1.0 else 0.0


@njit(cache=True, inline="always")
def constrained(m, h):
    """Whether half-edge h is a constraint: a boundary edge or a flagged piece."""
    return m.tw[h] < 0 or m.tc[h] != 0


@njit(cache=True)
def new_tag(m):
    m.tag += 1
    return np.int32(m.tag)


@njit(cache=True, borrowed=True)
def circumcircle(xy, a, b, c):
    """Circumcentre (x, y) and radius of triangle (a, b, c), computed relative to a."""
    ax, ay = xy[a, 0], xy[a, 1]
    bx, by = xy[b, 0] - ax, xy[b, 1] - ay
    cx, cy = xy[c, 0] - ax, xy[c, 1] - ay
    d = 2.0 * (bx * cy - by * cx)
    b2 = bx * bx + by * by
    c2 = cx * cx + cy * cy
    ux = (cy * b2 - by * c2) / d
    uy = (bx * c2 - cx * b2) / d
    return ax + ux, ay + uy, np.sqrt(ux * ux + uy * uy)


# --------------------------------------------------------------------------------------
# Writing triangles and flipping (the loading: .adjacency; the flips' order: .lawson).
# --------------------------------------------------------------------------------------
@njit(cache=True)
def _set_triangle(m, t, a, b, c):
    m.tv[3 * t] = a
    m.tv[3 * t + 1] = b
    m.tv[3 * t + 2] = c
    m.tstamp[t] += 1


@njit(cache=True, borrowed=True)
def link_on(tw, tc, tv, vcs, vseg, h, g):
    """Make h and g twins (g may be -1: then h is a boundary half-edge); h takes
    g's constrained flag, g being the side that stays.  On the triangulation's
    arrays (``m.tw, m.tc, m.tv, m.vcs, m.vseg``): the flips and the cavity's fan
    link edges in their loops, where passing the structref would count a
    reference at every call."""
    tw[h] = g
    if g >= 0:
        tw[g] = h
        tc[h] = tc[g]
        if tc[g]:
            vcs[tv[h]] = h
    else:
        tc[h] = 0
        vseg[tv[h]] = h


@njit(cache=True)
def flip(m, h):
    """Flip the unconstrained edge h (see the module diagram)."""
    flip_on(m.tv, m.tw, m.tc, m.tstamp, m.vseg, m.vcs, h)


@njit(cache=True, borrowed=True)
def flip_on(tv, tw, tc, tstamp, vseg, vcs, h):
    """:func:`flip` on the triangulation's arrays (``m.tv, m.tw, m.tc,
    m.tstamp, m.vseg, m.vcs``), for the Lawson loop, which would otherwise
    pass the structref, and count references to it and its arrays, at every
    flip.  :func:`_set_triangle` on those arrays, then :func:`link_on`."""
    g = np.int64(tw[h])  # an int64 half-edge: nxt/prv compile for one type
    t = h // 3
    u = g // 3
    a = tv[h]
    b = tv[nxt(h)]
    c = tv[prv(h)]
    d = tv[prv(g)]
    n_bc = tw[nxt(h)]
    n_ca = tw[prv(h)]
    n_ad = tw[nxt(g)]
    n_db = tw[prv(g)]
    for s, p, q, r in ((np.int64(t), np.int64(c), np.int64(a), np.int64(d)),
                       (np.int64(u), np.int64(d), np.int64(b), np.int64(c))):
        tv[3 * s] = p
        tv[3 * s + 1] = q
        tv[3 * s + 2] = r
        tstamp[s] += 1
    for e, f in ((3 * t, n_ca), (3 * t + 1, n_ad), (3 * u, n_db), (3 * u + 1, n_bc)):
        link_on(tw, tc, tv, vcs, vseg, e, f)
    tw[3 * t + 2] = 3 * u + 2
    tw[3 * u + 2] = 3 * t + 2
    tc[3 * t + 2] = 0
    tc[3 * u + 2] = 0


# --------------------------------------------------------------------------------------
# Point location
# --------------------------------------------------------------------------------------
@njit(cache=True)
def locate(m, t, x, y, max_steps, pieces):
    """Walk from triangle t towards (x, y).

    Returns the triangle containing the point (closed), or ``-(h + 1)`` when the
    walk must cross the boundary half-edge h (with ``pieces``, any constrained
    half-edge h: INSERT puts a point on the side of a piece its candidate is
    on), or ``-(3*tmax + 2)`` when it gives up.
    """
    xy = m.xy
    for _ in range(max_steps):
        moved = False
        for i in range(3):
            h = 3 * t + i
            if _orient_v(xy, m.tv[h], m.tv[nxt(h)], x, y) < 0.0:
                g = m.tw[h]
                if g < 0 or (pieces and constrained(m, h)):
                    return -(h + 1)
                t = g // 3
                moved = True
                break
        if not moved:
            return t
    return -(m.tv.shape[0] + 2)


@njit(cache=True)
def locate_scan(m, x, y):
    """Brute-force location: the first triangle containing (x, y) (closed), or -1."""
    xy = m.xy
    for t in range(m.nt):
        inside = True
        for i in range(3):
            h = 3 * t + i
            if _orient_v(xy, m.tv[h], m.tv[nxt(h)], x, y) < 0.0:
                inside = False
                break
        if inside:
            return t
    return -1


@njit(cache=True)
def boundary_is(m, ring_next):
    """Whether the triangles are glued consistently and bounded by the rings: every
    paired half-edge runs opposite to its twin, and the unpaired ones are exactly
    ``u -> ring_next[u]`` for the ring vertices u (``ring_next`` -1 elsewhere),
    each once.  With every triangle strictly counter-clockwise
    (:func:`count_not_ccw`) the triangles then cover the region the rings bound
    exactly once: the covering count at a point is the rings' winding number."""
    seen = np.zeros(ring_next.shape[0], np.int8)
    for h in range(3 * m.nt):
        g = np.int64(m.tw[h])  # an int64 half-edge: nxt compiles for one type
        if g >= 0:
            if m.tv[g] != m.tv[nxt(h)] or m.tv[nxt(g)] != m.tv[h]:
                return False
            continue
        u = m.tv[h]
        if ring_next[u] != m.tv[nxt(h)] or seen[u]:
            return False
        seen[u] = 1
    for u in range(ring_next.shape[0]):
        if ring_next[u] >= 0 and not seen[u]:
            return False
    return True


@njit(cache=True)
def count_not_ccw(m):
    """Number of triangles that are not strictly counter-clockwise (exact)."""
    xy, tv = m.xy, m.tv
    bad = 0
    for t in range(m.nt):
        a, b, c = tv[3 * t], tv[3 * t + 1], tv[3 * t + 2]
        if orient2d(xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1]) <= 0.0:
            bad += 1
    return bad


@njit(cache=True)
def triangle_list(m):
    """(T, 3) int64 vertex indices of all triangles."""
    nt = m.nt
    out = np.empty((nt, 3), np.int64)
    for t in range(nt):
        out[t, 0] = m.tv[3 * t]
        out[t, 1] = m.tv[3 * t + 1]
        out[t, 2] = m.tv[3 * t + 2]
    return out
