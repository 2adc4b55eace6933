"""A graded start in rows: points packed front by front from the boundary, following h.

:func:`frontal_seed` is the graded counterpart of the uniform path's boundary rows
(:mod:`uniform2d.optimize.rows`): starting from the boundary points, each round
puts a point on every edge of the front (the edges between the triangles
already small enough for h and the rest of the domain), at the apex of the
isosceles triangle whose sides are h at their own midpoints (so that a row
follows a steep size), and keeps those at least :data:`SPACING` times h from
every point and :data:`LINE_SPACING` times h from the boundary, in order, h the
smaller of the two sizes.  A ring of the front around a hole whose
circumference asks for more points than its apexes gets them
(:func:`_respace_rings`).  The result is rows parallel to the boundary that
thin out where h grows, with far fewer irregular vertices than farthest-point
insertion leaves.  The rows are not an exact count: :func:`rows_start` tops
them up with Algorithm INSERT or drops the most crowded, for exactly n points.
"""

from __future__ import annotations

import itertools

import numpy as np
import shapely
from scipy.spatial import Delaunay, QhullError, cKDTree

from .._kernel.cells import grid_sizes
from .._kernel.front import front_loops, greedy_kept, respace_chains
from ..geometry import polygon_edges
from ..insert import insert_on_edges
from ..polygon import Polygon
from ..sizefield import SizeField

__all__ = ["FILLED", "LINE_SPACING", "SPACING", "frontal_seed", "rows_start"]

#: A new point keeps at least this many h from every point (h the smaller of the
#: two points' sizes) ...
SPACING = 0.8
#: ... and this many h from the boundary: SPACING times an equilateral
#: triangle's height over its side (an apex on a boundary edge is that far from it).
LINE_SPACING = SPACING * 0.8660254037844386
#: A triangle whose circumradius is at most this many h is filled (an
#: equilateral triangle of side h has 1 / sqrt(3) = 0.577).
FILLED = 0.75
#: Fixed-point iterations for an apex's side: the side is h at its own midpoint,
#: not at the front edge's, so that a row follows a steep size gradient.
APEX_ITERATIONS = 2
#: Samples of the size per gap of a ring respaced by :func:`_respace_rings`.
RING_SAMPLES = 4
#: Rounds at most (a front advances about 0.87 h a round).
MAX_ROUNDS = 2000
#: Boundaries of at most this many edges get the candidates' distances to them from
#: numpy first (:func:`_far`), shapely only for those near.
FEW_EDGES = 32
#: Points added to a :class:`_Grown` set before its tree is built again, at least.
GROWN = 256


def _shape(polygon: Polygon):
    off = polygon.ring_offsets
    rings = [polygon.vertices[off[r]:off[r + 1]] for r in range(len(polygon.rings))]
    a, d, _ = polygon_edges(polygon, constraints=True)
    lines = shapely.multilinestrings([np.stack([a, a + d], axis=1)][0])
    return shapely.Polygon(rings[0], rings[1:]), lines


def _compiled(size):
    """``size`` evaluated by the kernel when it is a :class:`SizeField` (the same
    floats, see :func:`uniform2d._kernel.cells.grid_sizes`), else ``size``."""
    if not isinstance(size, SizeField):
        return size
    gx, gy, gv = size.x, size.y, size.values

    def h(points):
        return grid_sizes(gx, gy, gv, np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2))
    return h


def _front(P, act, tri, size, shape, n0: int = 0, closed=None):
    """Apexes on the front edges of the Delaunay triangulation ``tri`` of the
    points ``P[act]`` (the first ``n0`` of ``P`` the boundary's), rings respaced
    (:func:`_respace_rings`): (candidates (k, 2), their h, the points of ``act``
    on an open triangle).  ``closed(X, r, corners)``: whether a point left out
    of ``act`` (:func:`frontal_seed`) is closer than r[i] to X[i] (m, 2), the
    circumcentre of the triangle of ``corners[i]`` (indices into P), as
    :meth:`_Behind.closer`; or None; a triangle whose circumcircle holds one is
    not a triangle of all the points' Delaunay triangulation, and counts as
    filled."""
    S = act[tri.simplices]
    A, B, C = P[S[:, 0]], P[S[:, 1]], P[S[:, 2]]
    cen = (A + B + C) / 3.0
    inside = shapely.contains_xy(shape, cen[:, 0], cen[:, 1])
    a, b, c = np.linalg.norm(B - C, axis=1), np.linalg.norm(C - A, axis=1), np.linalg.norm(A - B, axis=1)
    area2 = np.abs((B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0]))
    R = a * b * c / np.maximum(2.0 * area2, 1e-300)
    filled = inside & (R <= FILLED * size(cen))
    if closed is not None:  # (a filled triangle stays filled)
        t = np.flatnonzero(inside & ~filled)
        filled[t] = closed(_circumcentres(A[t], B[t], C[t]), R[t], S[t])
    open_ = inside & ~filled
    # the edges opposite vertex k of the open triangles t next to no open one,
    # k = 0 first, then 1, then 2
    nb = tri.neighbors
    nbc = np.maximum(nb, 0)
    k, t = np.nonzero((open_[:, None] & ((nb < 0) | ~inside[nbc] | filled[nbc])).T)
    pi, qi = S[t, (k + 1) % 3], S[t, (k + 2) % 3]
    p, q = P[pi], P[qi]
    m = 0.5 * (p + q)
    d = q - p
    L = np.linalg.norm(d, axis=1)
    nrm = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.maximum(L, 1e-300)[:, None]
    side = np.sign(np.einsum("ij,ij->i", P[S[t, k]] - m, nrm))
    up = side[:, None] * nrm
    hs = size(m)
    for _ in range(APEX_ITERATIONS):
        height = np.sqrt(np.maximum(hs * hs - 0.25 * L * L, 0.25 * hs * hs))
        hs = size(m + (0.5 * height)[:, None] * up)
    height = np.sqrt(np.maximum(hs * hs - 0.25 * L * L, 0.25 * hs * hs))
    cand = m + height[:, None] * up
    # the edge's ends in the order that has its open side (the apex) on the left
    ends = np.where(side[:, None] > 0, np.stack([pi, qi], 1), np.stack([qi, pi], 1))
    if len(cand):
        cand = _respace_rings(cand, ends, size, n0)
    on_open = np.zeros(len(P), dtype=bool)
    on_open[S[open_]] = True
    return cand, size(cand), np.flatnonzero(on_open)


def _circumcentres(a, b, c) -> np.ndarray:
    """(k, 2) circumcentres of the triangles (a, b, c), each (k, 2)."""
    b, c = b - a, c - a
    d = 2.0 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    bb, cc = (b * b).sum(1), (c * c).sum(1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return a + np.column_stack([c[:, 1] * bb - b[:, 1] * cc, b[:, 0] * cc - c[:, 0] * bb]) / d[:, None]


def _clockwise(ends: np.ndarray, P: np.ndarray) -> tuple:
    """The closed chains of three or more front edges ``ends`` (k, 2) (each with its
    open side on the left; :func:`uniform2d._kernel.front.front_loops`) whose points
    ``P`` (one per edge) turn clockwise: (their edge indices one chain after the
    other, (c,) each chain's length)."""
    none = np.zeros(0, np.int64)
    if not len(ends):
        return none, none
    idx, lens = front_loops(np.ascontiguousarray(ends, dtype=np.int64), int(ends.max()) + 1)
    if not len(lens):
        return none, none
    first = np.cumsum(lens) - lens
    after = np.arange(1, len(idx) + 1)
    after[first + lens - 1] = first  # each loop's last point is followed by its first
    x, y = P[idx, 0], P[idx, 1]
    area2 = np.add.reduceat(x * y[after] - y * x[after], first)
    cw = area2 < 0
    return idx[np.repeat(cw, lens)], lens[cw]


def _respace_rings(cand: np.ndarray, ends: np.ndarray, size, n0: int = 0) -> np.ndarray:
    """``cand`` (the apexes of the front edges ``ends``, in order) with the apexes of
    every front ring growing outward around a hole (a closed chain turning
    clockwise, the open side outside) replaced by ``round(∮ ds / h)`` points
    along the ring through them, spaced by equal ``∫ ds / h``: one apex per edge
    keeps a ring's count from row to row, where h growing with the radius asks
    for more (or fewer).  The first ring, on the boundary points (indices below
    ``n0``), only gains points: with fewer, the polygon's vertices, which
    cannot move, would meet long edges (the spacing test drops apexes there).
    Clockwise loops around no hole count too: on the surface layer's charts
    respacing only those around a hole raised the CV of q (cylinder 0.059 to
    0.069).  The rings' integrals here, their respacing in the kernel
    (:func:`uniform2d._kernel.front.respace_chains`)."""
    idx, lens = _clockwise(ends, cand)
    if not len(lens):
        return cand
    first = np.cumsum(lens) - lens
    nxt = np.arange(1, len(idx) + 1)
    nxt[first + lens - 1] = first
    a = cand[idx]
    d = a[nxt] - a  # to the next point around the ring
    t = (np.arange(RING_SAMPLES) + 0.5) / RING_SAMPLES
    mids = a[:, None, :] + t[None, :, None] * d[:, None, :]
    inv = (1.0 / size(mids.reshape(-1, 2))).reshape(len(a), -1).mean(axis=1)
    inv *= np.hypot(d[:, 0], d[:, 1])
    boundary = np.logical_and.reduceat((ends[idx] < n0).all(axis=1), first)
    return respace_chains(np.ascontiguousarray(cand), idx, lens, inv, np.ascontiguousarray(d),
                          boundary)


def _clear(cand, hc, P, hP, lines, size, ball=None) -> np.ndarray:
    """(k,) bool: the candidates at least SPACING times the smaller of the two sizes
    from every point of ``P`` and LINE_SPACING times the smaller of theirs and the
    nearest boundary point's from the boundary.  The smaller size, not the
    candidate's: where h grows steeply the apex of a front edge has a larger size
    than the edge, and its own size would refuse the whole first row.  ``ball``:
    the pairs (i, j) of a ball query of the candidates i among the points j of
    ``P`` (:class:`_Grown`), if known."""
    ok = _far(cand, LINE_SPACING * hc, lines)
    s = np.flatnonzero(~ok)
    pc = shapely.points(cand[s])
    dist = shapely.distance(lines, pc)
    ok[s] = dist >= LINE_SPACING * hc[s]
    # the nearest boundary point's size matters only where the candidate's own does not clear it
    t = np.flatnonzero(~ok[s])
    near = shapely.get_coordinates(shapely.shortest_line(pc[t], lines))[1::2]
    ok[s[t]] = dist[t] >= LINE_SPACING * np.minimum(hc[s[t]], size(near))
    u = np.flatnonzero(ok)  # (those the boundary refused stay refused)
    i, j = (ball or _Grown(P).ball)(cand[u], SPACING * hc[u])
    d = np.hypot(*(P[j] - cand[u[i]]).T)
    ok[u[i[d < SPACING * np.minimum(hP[j], hc[u[i]])]]] = False
    return ok


def _far(X, r, lines) -> np.ndarray:
    """(k,) bool: the points X (k, 2) whose distance to the segments of ``lines``, as
    shapely measures it, is certainly at least r (k,); False where unsure, and for
    all if the segments are more than :data:`FEW_EDGES` (numpy's distances to each
    would cost more than shapely's).  Both distances are within a few roundings
    of (|x| + |a| + |b|) of the true one (a, b a segment's ends), so one larger
    than r by 2**-40 of that sum plus r settles it."""
    seg = shapely.get_coordinates(lines).reshape(-1, 2, 2)
    if len(seg) > FEW_EDGES or not len(X):
        return np.zeros(len(X), dtype=bool)
    a, d = seg[:, 0], seg[:, 1] - seg[:, 0]
    w = X[:, None, :] - a[None]
    dd = (d * d).sum(axis=1)
    t = np.clip((w * d).sum(axis=2) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    off = w - t[:, :, None] * d
    dist = np.sqrt((off * off).sum(axis=2))
    mag = np.abs(X).sum(axis=1)[:, None] + np.abs(seg).sum(axis=(1, 2))[None] + r[:, None]
    return np.all(dist - 2.0**-40 * mag >= r[:, None], axis=1)


class _Grown:
    """The KD-tree queries of points whose number only grows, without a tree over
    all of them built each time: one tree rebuilt when the points added since
    are more than a quarter of it (and GROWN), and one over those."""

    def __init__(self, P):
        self.P = np.asarray(P, dtype=np.float64).reshape(-1, 2)
        self.n = len(self.P)
        self.big = cKDTree(self.P) if self.n else None
        self.small = None

    def add(self, Q) -> None:
        if not len(Q):
            return
        self.P = np.concatenate([self.P, Q])
        if len(self.P) - self.n > max(GROWN, self.n // 4):
            self.n = len(self.P)
            self.big, self.small = cKDTree(self.P), None
        else:
            self.small = cKDTree(self.P[self.n:])

    def _trees(self):
        return [(t, k) for t, k in ((self.big, 0), (self.small, self.n)) if t is not None]

    def nearest(self, X) -> np.ndarray:
        """(m,) distance from each of the points X (m, 2) to the nearest point."""
        d = np.full(len(X), np.inf)
        for t, _ in self._trees():
            d = np.minimum(d, t.query(X)[0])
        return d

    def ball(self, X, r) -> tuple:
        """(i, j) int64: the points j within r[i] of X[i] (cKDTree.query_ball_point)."""
        pairs = [_within(t.query_ball_point(X, r)) for t, _ in self._trees()]
        if not pairs:
            return np.empty(0, np.int64), np.empty(0, np.int64)
        return (np.concatenate([i for i, _ in pairs]),
                np.concatenate([j + k for (_, j), (_, k) in zip(pairs, self._trees())]))


class _Behind:
    """The points left behind the front (a :class:`_Grown`), and for every point
    one of them that was its neighbour in a round's triangulation, whose
    distance answers most of :meth:`closer`'s questions without the tree."""

    def __init__(self):
        self.grown = _Grown(np.empty((0, 2)))
        self.near = np.zeros(0, np.int64)
        self.P = np.empty((0, 2))

    def add(self, P, act, tri, left) -> None:
        """The points ``act[left]`` (indices into P) leave the triangulation
        ``tri`` of ``P[act]``: behind for good, each their neighbours' known one."""
        self.grown.add(P[act[left]])
        self.P = P
        self.near = np.concatenate([self.near, np.full(len(P) - len(self.near), -1, np.int64)])
        gone = np.zeros(len(act), dtype=bool)
        gone[left] = True
        T = tri.simplices
        for k in range(3):  # the other two corners of a triangle at a point gone
            r = np.flatnonzero(gone[T[:, k]])
            for o in (1, 2):
                self.near[act[T[r, (k + o) % 3]]] = act[T[r, k]]

    def closer(self, X, r, corners) -> np.ndarray:
        """(m,) bool: whether a point behind is closer than r[i] to X[i] (m, 2):
        ``nearest < r``, the tree's nearest distance.  A corner's known point
        closer than r by a margin far above rounding makes that distance smaller
        than r whatever its last bits; the tree answers the others."""
        out = np.zeros(len(X), dtype=bool)
        known = len(self.near)  # points added since have none yet
        near = np.where(corners < known, self.near[np.minimum(corners, known - 1)], -1)
        for b in near.T:
            d = X - self.P[np.maximum(b, 0)]
            out |= (b >= 0) & ((d * d).sum(axis=1) < (1.0 - 2.0**-30) * (r * r))
        rest = np.flatnonzero(~out)
        out[rest] = self.grown.nearest(X[rest]) < r[rest]
        return out


def _within(lists) -> tuple:
    """(i, j) int64 arrays: the pairs of a KD-tree's ball query, j in lists[i]."""
    counts = np.fromiter(map(len, lists), dtype=np.int64, count=len(lists))
    i = np.repeat(np.arange(len(lists), dtype=np.int64), counts)
    j = np.fromiter(itertools.chain.from_iterable(lists), dtype=np.int64, count=int(counts.sum()))
    return i, j


def _greedy(C: np.ndarray, hC: np.ndarray) -> np.ndarray:
    """Indices of the points ``C`` kept in order, each unless an earlier kept one is
    closer than SPACING times the smaller of their sizes (the relation is
    symmetric, so a point close to none is kept)."""
    i, j = _within(cKDTree(C).query_ball_point(C, SPACING * hC))
    close = (i != j) & (np.hypot(*(C[j] - C[i]).T) < SPACING * np.minimum(hC[i], hC[j]))
    return np.flatnonzero(greedy_kept(len(C), i[close], j[close]))


def frontal_seed(polygon: Polygon, size, sites) -> np.ndarray:
    """Interior points packed in rows from the boundary and the ``sites``.

    Parameters
    ----------
    polygon : Polygon
    size : callable
        ``size(points (m, 2)) -> (m,)``, the absolute size (the field at its scale).
    sites : (k, 2) float64
        Points already placed (on the boundary and segments).

    Returns
    -------
    (m, 2) float64
        The new points, strictly inside, in the order they were placed.

    Examples
    --------
    >>> from uniform2d import Polygon, SizeField
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = SizeField.constant(sq.bounds, 0.25)
    >>> from uniform2d.graded import boundary_sites
    >>> b, _ = boundary_sites(sq, f, 1.0, 100)
    >>> len(b), len(frontal_seed(sq, f, b))
    (12, 6)
    """
    shape, lines = _shape(polygon)
    size = _compiled(size)
    P = np.concatenate([polygon.vertices, np.asarray(sites, dtype=np.float64).reshape(-1, 2)])
    hP = size(P)
    n0 = len(P)
    # a point on no open triangle is behind the front for good: the rounds
    # triangulate only the others (the front's triangles are the same; see _front)
    active = np.ones(n0, dtype=bool)
    every, behind = _Grown(P), _Behind()
    for _ in range(MAX_ROUNDS):
        act = np.flatnonzero(active)
        if len(act) < 3:
            break
        try:
            tri = Delaunay(P[act])
        except QhullError:  # the active points all on a line: no open triangle
            break
        closed = behind.closer if len(behind.grown.P) else None
        cand, hc, on_open = _front(P, act, tri, size, shape, n0, closed)
        active[act] = False
        active[on_open] = True
        behind.add(P, act, tri, np.flatnonzero(~active[act]))
        ok = shapely.contains_xy(shape, cand[:, 0], cand[:, 1])
        ok[ok] = _clear(cand[ok], hc[ok], P, hP, lines, size, every.ball)
        idx = np.flatnonzero(ok)
        if not len(idx):
            break
        keep = idx[_greedy(cand[idx], hc[idx])]
        every.add(cand[keep])
        P = every.P  # the points so far, as the trees have them
        hP = np.concatenate([hP, hc[keep]])
        active = np.concatenate([active, np.ones(len(keep), dtype=bool)])
    return P[n0:]


def rows_start(polygon: Polygon, n: int, field, scale: float, sites=None, edges=None):
    """Exactly ``n`` Steiner points for a graded mesh: the ``sites`` (on the boundary
    and segments), the rows of :func:`frontal_seed` for ``scale * field``, and
    INSERT's points with the field (:func:`uniform2d.insert`, its sites those
    before) where the rows leave room, or without the rows' most crowded points
    (smallest distance to a neighbour over h) where they are too many.

    Parameters
    ----------
    polygon : Polygon
    n : int
        Steiner points in all (sites included).
    field : SizeField
    scale : float
        The field's scale at which the rows are packed.
    sites : (k, 2) float64, optional
    edges : (k,) int64, optional
        The constraint edge of every site (``polygon.constraint_edges`` order), or -1.

    Returns
    -------
    points : (n, 2) float64
    fixed : (n,) bool
        The points on the boundary or on segments (the sites and any INSERT put there).

    Examples
    --------
    >>> from uniform2d import Polygon, SizeField
    >>> from uniform2d.graded import boundary_sites
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = SizeField.constant(sq.bounds, 1.0)
    >>> b, e = boundary_sites(sq, f, 0.25, 100)
    >>> pts, fixed = rows_start(sq, 30, f, 0.25, b, e)
    >>> pts.shape, int(fixed.sum())
    ((30, 2), 12)
    """
    sites = np.zeros((0, 2)) if sites is None else np.asarray(sites, dtype=np.float64).reshape(-1, 2)
    edges = np.zeros(0, np.int64) if edges is None else np.asarray(edges, dtype=np.int64)
    h = field.scaled(scale)
    rows = frontal_seed(polygon, h, sites)
    k = n - len(sites)
    if len(rows) > k:
        d, _ = cKDTree(np.concatenate([polygon.vertices, sites, rows])).query(rows, k=2)
        crowd = d[:, 1] / h(rows)
        rows = rows[np.sort(np.argsort(crowd, kind="stable")[len(rows) - k:])]
    pre = np.concatenate([sites, rows])
    fixed = np.concatenate([np.ones(len(sites), bool), np.zeros(len(rows), bool)])
    if len(rows) == k:
        return pre, fixed
    pre_e = np.concatenate([edges, np.full(len(rows), -1, np.int64)])
    start = insert_on_edges(polygon, k - len(rows), pre, pre_e, field)
    return np.concatenate([pre, start.points]), np.concatenate([fixed, start.on_boundary])
