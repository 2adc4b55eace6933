"""Brute-force reference implementation of Algorithm INSERT (canonical Voronoi insertion).

This module is the slow, obviously-correct yardstick the fast kernel
(``uniform2d.insert``) is compared to.  It shares NO code with the kernel: it uses
only ``uniform2d.Polygon`` (for the validated, normalised rings), numpy, scipy and
shapely, and it recomputes everything from scratch at every step -- no
triangulation is maintained, no heap, no incremental state besides the list of
sites.

Definitions (paper Sections 2 and 5, design notes Sections 1-2)
--------------------------------------------------------------
* sites = polygon vertices V, the optional extra ``sites`` and the points inserted
  so far;
* w(x) = distance from x to the nearest site *visible* from x (segment inside the
  closed polygon; touching the boundary or passing through a vertex is visible;
  crossing an interior segment piece at a point inside both is not);
* on an interior segment piece, each side is a candidate place of its own, valued
  by the piece's ends and the sites strictly on that side (the limit of w there
  from that side): that is where w's supremum near the piece is attained;
* step j inserts p_j = argmax of w over the closed polygon.

Where the maximum can be -- the candidates:

(a) interior points equidistant from three visible sites with no visible site
    strictly closer (vertices of the visibility-constrained Voronoi diagram).  Only
    those lying in the closed triangle of their three sites (non-obtuse triangle,
    tested exactly) are local maxima of w; the others can never be the global
    maximum and are dropped so that near-ties are resolved among the same set of
    points the kernel considers.  A circumcentre on the boundary is left to (b).
(b) points on boundary subsegments (an edge split by the sites lying on it)
    equidistant from two visible sites with no visible site closer, and a local
    maximum of w along the edge (one of the two sites ahead, one behind).  Only
    sites in the diametral disk of the subsegment can beat its endpoints.

Two ways of finding them:

* ``method="voronoi"`` (convex polygons without holes): literally the paper's
  Step 3 -- ``scipy.spatial.Voronoi`` of the sites, its vertices inside P and the
  intersections of its edges (rays included) with the boundary of P.
* ``method="general"`` (any polygon): enumerate triples of sites (pruned with a
  KD-tree: weights never increase, so after the first step only triples whose
  pairwise distances are <= 2 w_{j-1} can matter), circumcentres, emptiness with
  respect to *visible* sites; and pairs of sites in each subsegment's diametral
  disk.  Visibility: the segment is split at every crossing with a polygon edge and
  at every polygon vertex it touches, and each piece's midpoint must lie in the
  closed polygon (tolerance 1e-12 x polygon size).

Numerics: the whole run happens in coordinates normalised by the bounding box, so a
scaled or translated polygon is computed exactly like the original; "on the
boundary" and "touching" mean within 1e-12 of the normalised polygon (an interior
circumcentre that close to an edge is represented by the boundary candidate at the
same place, so ``on_boundary`` is True there); the non-obtuse test is exact
(error-free products summed by ``math.fsum``); a site closer than
R (1 - 1e-10) invalidates a candidate of value R.  Expensive validation
(visibility, exact signs) is run lazily in order of decreasing value, only as far
as the tie rule needs -- that selects exactly the point full validation would.

Tie rule (identical in the kernel, ``uniform2d._kernel.insert``): in coordinates
normalised by the bounding box (centre subtracted, divided by max(width, height)),
let W be the largest candidate weight, C the candidates with weight >= W (1 - 1e-9),
x_min = min x over C, C' = members of C with x <= x_min + 1e-9, y_min = min y over
C', C'' = members of C' with y <= y_min + 1e-9; choose the member of C'' with the
smallest x.  The reported weight is the chosen
point's own visible distance.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy.spatial import Voronoi, cKDTree

from uniform2d import Polygon

__all__ = [
    "reference_insert",
    "ReferenceResult",
    "PolygonGeometry",
    "tie_break",
    "non_obtuse",
    "TIE_REL",
    "TIE_X",
]

TIE_REL = 1e-9  # relative weight tolerance of the tie rule
TIE_X = 1e-9  # absolute x tolerance of the tie rule, normalised units
EMPTY_REL = 1e-10  # a visible site closer than R (1 - EMPTY_REL) invalidates a candidate
GEOM_TOL = 1e-12  # "on the boundary" / "touching", relative to the polygon size
SITE_TOL = 1e-10  # an extra site this close (relative) to an edge lies on it
PRUNE_SLACK = 1e-6  # slack of the pruning radius 2 w_{j-1}
_CHUNK = 2048


# --------------------------------------------------------------------------------------
# exact helpers
# --------------------------------------------------------------------------------------
def _two_diff(a, b):
    """a - b = x + y exactly (Knuth/Shewchuk Two-Diff), elementwise."""
    x = a - b
    bv = a - x
    av = x + bv
    return x, (a - av) + (bv - b)


def _split(a):
    c = 134217729.0 * a  # 2^27 + 1 (Dekker)
    hi = c - (c - a)
    return hi, a - hi


def _two_prod(a, b):
    """a * b = x + y exactly (Dekker's Two-Product), elementwise."""
    x = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    y = al * bl - (((x - ah * bh) - al * bh) - ah * bl)
    return x, y


def exact_dot_sign(o: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Sign of (p - o) . (q - o) for rows of (M, 2) arrays, exact: the differences
    and products are expanded error-free into 16 doubles per row whose sum
    ``math.fsum`` rounds correctly (hence with the exact sign)."""
    terms = []
    for k in (0, 1):
        uh, ul = _two_diff(p[:, k], o[:, k])
        vh, vl = _two_diff(q[:, k], o[:, k])
        for a, b in ((uh, vh), (uh, vl), (ul, vh), (ul, vl)):
            terms += list(_two_prod(a, b))
    T = np.stack(terms, axis=1).tolist()
    return np.sign(np.array([math.fsum(r) for r in T], dtype=np.float64)).astype(np.int64)


def non_obtuse(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Triangles (rows of a, b, c) with no obtuse angle, i.e. whose closed triangle
    contains the circumcentre.  Decided exactly (float filter, then exact signs)."""
    a = np.atleast_2d(a)
    b = np.atleast_2d(b)
    c = np.atleast_2d(c)
    out = np.ones(len(a), dtype=bool)
    undecided = np.zeros(len(a), dtype=bool)
    for o, p, q in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = p - o, q - o
        d = (u * v).sum(1)
        # generous bound on the rounding error of the float dot product
        err = 1e-14 * (np.abs(u) * np.abs(v)).sum(1)
        out &= d >= -err
        undecided |= np.abs(d) <= err
    rows = np.flatnonzero(out & undecided)
    if rows.size:
        ok = np.ones(rows.size, dtype=bool)
        for o, p, q in ((a, b, c), (b, c, a), (c, a, b)):
            ok &= exact_dot_sign(o[rows], p[rows], q[rows]) >= 0
        out[rows] = ok
    return out


def circumcircles(a: np.ndarray, b: np.ndarray, c: np.ndarray):
    """Circumcentres (M,2) and radii (M,) of triangles; NaN for collinear triples."""
    bx, by = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    cx, cy = c[:, 0] - a[:, 0], c[:, 1] - a[:, 1]
    d = 2.0 * (bx * cy - by * cx)
    b2 = bx * bx + by * by
    c2 = cx * cx + cy * cy
    scale = np.sqrt(b2 * c2)
    with np.errstate(divide="ignore", invalid="ignore"):
        ok = np.abs(d) > 1e-14 * scale
        ux = np.where(ok, (cy * b2 - by * c2) / d, np.nan)
        uy = np.where(ok, (bx * c2 - cx * b2) / d, np.nan)
    centre = np.stack([a[:, 0] + ux, a[:, 1] + uy], axis=1)
    return centre, np.hypot(ux, uy)


# --------------------------------------------------------------------------------------
# polygon geometry: inside test, boundary distance, visibility
# --------------------------------------------------------------------------------------
def _intersections(P, d, A, E):
    """For segments P[i] + t d[i] and edges A[j] + s E[j]: (denominator, t, s) of
    their lines' intersection, (len(P), len(A)) each (denominator 0: parallel)."""
    wx = A[None, :, 0] - P[:, None, 0]
    wy = A[None, :, 1] - P[:, None, 1]
    denom = d[:, None, 0] * E[None, :, 1] - d[:, None, 1] * E[None, :, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (wx * E[None, :, 1] - wy * E[None, :, 0]) / denom
        s = (wx * d[:, None, 1] - wy * d[:, None, 0]) / denom
    return denom, t, s


class PolygonGeometry:
    """Closed-polygon predicates with a tolerance relative to the polygon size."""

    def __init__(self, polygon: Polygon, vertices=None, pieces=None):
        """``vertices`` (all polygon vertices, constraint vertices after the rings')
        and ``pieces`` (S, 2) indices into them: the interior segment pieces, when
        they are not ``polygon``'s own (the reference normalises coordinates)."""
        self.polygon = polygon
        self.V = np.asarray(polygon.vertices if vertices is None else vertices, dtype=np.float64)
        e = np.asarray(polygon.edges)
        self.edge_idx = e
        self.A = self.V[e[:, 0]]
        self.B = self.V[e[:, 1]]
        self.E = self.B - self.A
        self.elen = np.hypot(self.E[:, 0], self.E[:, 1])
        # interior segment pieces: they block visibility (a proper crossing) and
        # carry candidates like ring edges; constraint edge k < len(A) is ring edge k
        sp = polygon.segment_edges if pieces is None else pieces
        sp = np.asarray(sp, np.int64).reshape(-1, 2)
        self.piece_idx = sp
        self.SA = self.V[sp[:, 0]]
        self.SE = self.V[sp[:, 1]] - self.SA
        self.slen = np.hypot(self.SE[:, 0], self.SE[:, 1])
        self.CA = np.concatenate([self.A, self.SA])
        self.CE = np.concatenate([self.E, self.SE])
        self.clen = np.concatenate([self.elen, self.slen])
        x0, y0, x1, y1 = polygon.bounds
        self.centre = np.array([(x0 + x1) / 2.0, (y0 + y1) / 2.0])
        self.size = max(x1 - x0, y1 - y0)
        # tolerance of "on the boundary" / "touching": relative to the polygon size,
        # but never below ~100 ulps of the coordinates (polygons far from the origin)
        self.tol = max(GEOM_TOL * self.size, 1e-14 * float(np.abs(self.V).max()))
        self.shp = polygon.to_shapely()
        shapely.prepare(self.shp)
        angles = polygon.interior_angles()
        self.convex = (
            polygon.n_holes == 0 and len(sp) == 0 and bool((angles <= np.pi + 1e-12).all())
        )

    # -- point predicates -----------------------------------------------------------
    def boundary_distance(self, X: np.ndarray, pieces: bool = False):
        """Distance of each point to the boundary (with ``pieces``: to the boundary
        and the segment pieces) and the index of the nearest constraint edge."""
        X = np.atleast_2d(X)
        if len(X) == 0:
            return np.zeros(0), np.zeros(0, dtype=np.int64)
        dist = np.empty(len(X))
        arg = np.empty(len(X), dtype=np.int64)
        A, E = (self.CA, self.CE) if pieces else (self.A, self.E)
        ee = (self.clen if pieces else self.elen) ** 2
        for s in range(0, len(X), _CHUNK):
            P = X[s : s + _CHUNK]
            wx = P[:, None, 0] - A[None, :, 0]
            wy = P[:, None, 1] - A[None, :, 1]
            t = np.clip((wx * E[None, :, 0] + wy * E[None, :, 1]) / ee, 0.0, 1.0)
            dx = wx - t * E[None, :, 0]
            dy = wy - t * E[None, :, 1]
            d = np.hypot(dx, dy)
            arg[s : s + _CHUNK] = d.argmin(1)
            dist[s : s + _CHUNK] = d.min(1)
        return dist, arg

    def inside_closed(self, X: np.ndarray, tol: float | None = None) -> np.ndarray:
        """Points in the closed polygon (within ``tol`` of it counts as inside)."""
        X = np.atleast_2d(X)
        if len(X) == 0:
            return np.zeros(0, dtype=bool)
        tol = self.tol if tol is None else tol
        ins = shapely.contains_xy(self.shp, X[:, 0], X[:, 1])
        rest = np.flatnonzero(~ins)
        if rest.size:
            ins[rest] = self.boundary_distance(X[rest])[0] <= tol
        return ins

    # -- visibility -----------------------------------------------------------------
    def visible(self, P: np.ndarray, Q: np.ndarray) -> np.ndarray:
        """For each row, is the segment P[i]-Q[i] inside the closed polygon?

        Both endpoints are assumed to lie in the closed polygon.  The segment is cut
        at its crossings with polygon edges and at the polygon vertices it touches;
        it is visible iff the midpoint of every piece is in the closed polygon.
        """
        P = np.atleast_2d(np.asarray(P, dtype=np.float64))
        Q = np.atleast_2d(np.asarray(Q, dtype=np.float64))
        out = np.ones(len(P), dtype=bool)
        if self.convex or len(P) == 0:
            return out
        for s in range(0, len(P), _CHUNK):
            out[s : s + _CHUNK] = self._visible_chunk(P[s : s + _CHUNK], Q[s : s + _CHUNK])
        return out

    def _visible_chunk(self, P, Q):
        d = Q - P
        dd = (d * d).sum(1)
        L = np.sqrt(dd)
        out = np.ones(len(P), dtype=bool)
        live = L > 0
        if not live.any():
            return out
        P, d, dd, L = P[live], d[live], dd[live], L[live]
        eps = (self.tol / L)[:, None]
        denom, t, s = _intersections(P, d, self.A, self.E)
        cross_ok = np.abs(denom) > 1e-14 * L[:, None] * self.elen[None, :]
        hit = cross_ok & (s >= 0.0) & (s <= 1.0) & (t > eps) & (t < 1.0 - eps)
        # polygon vertices lying on the segment (touching, or collinear overlaps)
        ux = self.V[None, :, 0] - P[:, None, 0]
        uy = self.V[None, :, 1] - P[:, None, 1]
        tv = (ux * d[:, None, 0] + uy * d[:, None, 1]) / dd[:, None]
        perp = np.abs(ux * d[:, None, 1] - uy * d[:, None, 0]) / L[:, None]
        vhit = (perp <= self.tol) & (tv > eps) & (tv < 1.0 - eps)

        res = np.ones(len(P), dtype=bool)
        brk = hit.any(1) | vhit.any(1)
        plain = np.flatnonzero(~brk)
        if plain.size:
            res[plain] = self.inside_closed(P[plain] + 0.5 * d[plain])
        rows = np.flatnonzero(brk)
        if rows.size:
            T = np.concatenate(
                [
                    np.zeros((rows.size, 1)),
                    np.where(hit[rows], t[rows], np.nan),
                    np.where(vhit[rows], tv[rows], np.nan),
                    np.ones((rows.size, 1)),
                ],
                axis=1,
            )
            T.sort(axis=1)  # NaN last
            width = int(np.isfinite(T).sum(1).max())
            T = T[:, :width]
            mids = 0.5 * (T[:, :-1] + T[:, 1:])
            valid = np.isfinite(mids)
            rr, cc = np.nonzero(valid)
            pts = P[rows[rr]] + mids[rr, cc, None] * d[rows[rr]]
            ok = self.inside_closed(pts)
            bad = np.zeros(rows.size, dtype=bool)
            np.logical_or.at(bad, rr, ~ok)
            res[rows] = ~bad
        if len(self.SA):
            res &= ~self._crosses_piece(P, d, L)
        out[live] = res
        return out

    def _crosses_piece(self, P, d, L):
        """Whether each segment P[i] + [0, 1] d[i] properly crosses a segment piece:
        at one point strictly inside both (touching a piece, running along it or
        passing through its end is not crossing; a point on a piece sees both
        sides)."""
        denom, t, s = _intersections(P, d, self.SA, self.SE)
        et = (self.tol / L)[:, None]
        es = (self.tol / self.slen)[None, :]
        ok = np.abs(denom) > 1e-14 * L[:, None] * self.slen[None, :]
        return (ok & (t > et) & (t < 1.0 - et) & (s > es) & (s < 1.0 - es)).any(1)

    def visible_distance(self, X: np.ndarray, S: np.ndarray, tree: cKDTree, k0: int = 8):
        """Distance from each point of X to its nearest visible site (and that site)."""
        X = np.atleast_2d(X)
        M, N = len(X), len(S)
        k = min(k0, N)
        d, idx = tree.query(X, k=k)
        d = d.reshape(M, k)
        idx = idx.reshape(M, k)
        res = np.full(M, np.inf)
        arg = np.full(M, -1, dtype=np.int64)
        if self.convex:
            return d[:, 0].copy(), idx[:, 0].copy()
        todo = np.arange(M)
        for col in range(k):
            if todo.size == 0:
                break
            vis = self.visible(X[todo], S[idx[todo, col]])
            res[todo[vis]] = d[todo[vis], col]
            arg[todo[vis]] = idx[todo[vis], col]
            todo = todo[~vis]
        for r in todo:  # slow path: the k nearest sites are all hidden
            order = np.argsort(np.hypot(*(S - X[r]).T), kind="stable")
            for s in range(k, N, 64):
                cand = order[s : s + 64]
                vis = self.visible(np.repeat(X[r : r + 1], len(cand), 0), S[cand])
                if vis.any():
                    j = cand[np.flatnonzero(vis)[0]]
                    res[r] = float(np.hypot(*(S[j] - X[r])))
                    arg[r] = j
                    break
        return res, arg

    def no_visible_closer(self, X, R, S, tree) -> np.ndarray:
        """True where no site visible from X[i] is closer than R[i] (1 - EMPTY_REL)."""
        X = np.atleast_2d(X)
        if len(X) == 0:
            return np.zeros(0, dtype=bool)
        lim = R * (1.0 - EMPTY_REL)
        d1, i1 = tree.query(X, k=1)
        ok = d1 >= lim
        bad = np.flatnonzero(~ok)
        if bad.size == 0 or self.convex:
            return ok
        # nearest site first: usually visible, which settles it
        vis = self.visible(X[bad], S[i1[bad]])
        rest = bad[~vis]
        if rest.size == 0:
            return ok
        lists = tree.query_ball_point(X[rest], lim[rest])
        rows = np.repeat(rest, [len(li) for li in lists])
        cols = np.fromiter(itertools.chain.from_iterable(lists), dtype=np.int64, count=rows.size)
        vis = self.visible(X[rows], S[cols])
        any_vis = np.zeros(len(X), dtype=bool)
        np.logical_or.at(any_vis, rows, vis)
        ok[rest] = ~any_vis[rest]
        return ok


# --------------------------------------------------------------------------------------
# the algorithm
# --------------------------------------------------------------------------------------
@dataclass
class ReferenceResult:
    points: np.ndarray
    weights: np.ndarray
    on_boundary: np.ndarray
    n_candidates: list = field(default_factory=list)  # raw candidates per step
    n_tied: list = field(default_factory=list)  # distinct points in the tied set C
    gap: list = field(default_factory=list)  # 1 - (best weight outside C) / W (diagnostics)

    def __iter__(self):  # points, weights, on_boundary = reference_insert(...)
        return iter((self.points, self.weights, self.on_boundary))


class _State:
    """Sites and which boundary edge each boundary site lies on (parameter along it)."""

    def __init__(self, geom: PolygonGeometry, extra):
        self.geom = geom
        V = geom.V
        self.sites = [tuple(p) for p in V]
        # boundary sites per edge: list of (param, site index)
        self.on_edge: list[list[tuple[float, int]]] = [[] for _ in range(len(geom.CA))]
        for ei, (i, j) in enumerate(np.concatenate([geom.edge_idx, geom.piece_idx])):
            self.on_edge[ei] += [(0.0, int(i)), (1.0, int(j))]
        if extra is not None:
            extra = np.asarray(extra, dtype=np.float64).reshape(-1, 2)
            if len(extra):
                if not geom.inside_closed(extra, tol=max(SITE_TOL * geom.size, geom.tol)).all():
                    raise ValueError("every extra site must lie in the closed polygon")
                allp = np.concatenate([V, extra])
                if len(np.unique(allp, axis=0)) != len(allp):
                    raise ValueError("extra sites must be distinct from each other and from V")
                for p in extra:
                    idx = len(self.sites)
                    self.sites.append(tuple(p))
                    d, e = geom.boundary_distance(p[None], pieces=True)
                    if d[0] <= max(SITE_TOL * geom.size, geom.tol):
                        self._add_boundary(int(e[0]), idx)

    def _add_boundary(self, ei: int, idx: int):
        g = self.geom
        p = np.array(self.sites[idx])
        t = float(np.dot(p - g.CA[ei], g.CE[ei]) / g.clen[ei] ** 2)
        self.on_edge[ei].append((t, idx))

    def add(self, p, edge: int | None):
        idx = len(self.sites)
        self.sites.append((float(p[0]), float(p[1])))
        if edge is not None:
            self._add_boundary(edge, idx)

    def subsegments(self):
        """(edge, site a, site b, side) for consecutive sites along every constraint
        edge: side 0 on a ring edge; a segment piece's subsegment comes twice, side
        +1 (sites on the left of a -> b) and -1 (on the right)."""
        out = []
        nE = len(self.geom.A)
        for ei, lst in enumerate(self.on_edge):
            lst = sorted(lst)
            for sd in (0,) if ei < nE else (1, -1):
                out += [(ei, lst[k][1], lst[k + 1][1], sd) for k in range(len(lst) - 1)]
        return out


def _triples_within(tree: cKDTree, r: float, N: int):
    pairs = tree.query_pairs(r, output_type="ndarray")
    if len(pairs) == 0:
        z = np.zeros(0, dtype=np.int64)
        return z, z, z
    pairs = np.sort(pairs, axis=1)
    pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
    adj = np.zeros((N, N), dtype=bool)
    adj[pairs[:, 0], pairs[:, 1]] = True
    cnt = np.bincount(pairs[:, 0], minlength=N)
    ptr = np.concatenate([[0], np.cumsum(cnt)])
    i, j = pairs[:, 0], pairs[:, 1]
    deg = cnt[j]
    rep = np.repeat(np.arange(len(pairs)), deg)
    offs = np.arange(deg.sum()) - np.repeat(np.cumsum(deg) - deg, deg)
    kk = pairs[ptr[j][rep] + offs, 1]
    ii, jj = i[rep], j[rep]
    m = adj[ii, kk]
    return ii[m], jj[m], kk[m]


def _all_triples(N: int):
    if N < 3:
        z = np.zeros(0, dtype=np.int64)
        return z, z, z
    t = np.array(list(itertools.combinations(range(N), 3)), dtype=np.int64)
    return t[:, 0], t[:, 1], t[:, 2]


class _Candidates:
    """Raw candidates (cheap geometric filters applied) plus a validator for the
    expensive tests (visibility, exact non-obtuse test), which only needs to run on
    candidates that can still reach the tied set: they are validated lazily in
    order of decreasing weight, which selects exactly the same point as validating
    everything."""

    def __init__(self):
        self.parts = []  # (points, values, validator(idx) -> bool mask, edges or None)

    def add(self, pts, vals, validator, edges=None):
        self.parts.append((np.asarray(pts).reshape(-1, 2), np.asarray(vals, float), validator, edges))

    def select(self, g: PolygonGeometry, diagnostics: bool = False):
        """Apply the tie rule to the valid candidates.  Returns (point, is_boundary,
        edge, number of raw candidates, distinct points in the tied set, relative gap
        to the best valid candidate outside it -- NaN unless ``diagnostics``)."""
        pts = np.concatenate([p[0] for p in self.parts])
        vals = np.concatenate([p[1] for p in self.parts])
        part = np.concatenate([np.full(len(p[1]), k) for k, p in enumerate(self.parts)])
        local = np.concatenate([np.arange(len(p[1])) for p in self.parts])
        order = np.argsort(-vals, kind="stable")
        status = np.zeros(len(vals), dtype=np.int8)  # 0 unknown, 1 valid, -1 invalid

        def validate(idx):
            idx = idx[status[idx] == 0]
            for k, (_, _, fn, _) in enumerate(self.parts):
                sel = idx[part[idx] == k]
                if sel.size:
                    ok = fn(local[sel])
                    status[sel] = np.where(ok, 1, -1)

        if diagnostics:
            validate(order)
        pos, batch = 0, 32
        while pos < len(order) and not (status == 1).any():
            validate(order[pos : pos + batch])
            pos += batch
            batch *= 2
        if not (status == 1).any():
            raise RuntimeError("no valid candidate")  # pragma: no cover
        W = vals[status == 1].max()
        validate(order[vals[order] >= W * (1.0 - TIE_REL)])
        good = np.flatnonzero(status == 1)
        k = good[tie_break(g, pts[good], vals[good])]
        edges = self.parts[part[k]][3]
        edge = None if edges is None else int(edges[local[k]])
        tied = good[vals[good] >= W * (1.0 - TIE_REL)]
        ntied = len(np.unique(np.round((pts[tied] - g.centre) / g.size / TIE_X), axis=0))
        gap = np.nan
        if diagnostics:
            rest = vals[good[vals[good] < W * (1.0 - TIE_REL)]]
            gap = float(1.0 - rest.max() / W) if rest.size else np.inf
        return pts[k], edge is not None, edge, len(vals), ntied, gap


def _interior_general(g: PolygonGeometry, S, tree, w_prev, prune, out: _Candidates):
    N = len(S)
    if prune and np.isfinite(w_prev):
        I, J, K = _triples_within(tree, 2.0 * w_prev * (1.0 + PRUNE_SLACK), N)
    else:
        I, J, K = _all_triples(N)
    C, R = circumcircles(S[I], S[J], S[K])
    keep = np.isfinite(R)
    if prune and np.isfinite(w_prev):
        keep &= R <= w_prev * (1.0 + PRUNE_SLACK)
    # float non-obtuse filter with a margin (the exact decision is in the validator)
    for o, p, q in ((I, J, K), (J, K, I), (K, I, J)):
        u, v = S[p] - S[o], S[q] - S[o]
        keep &= (u * v).sum(1) >= -1e-9 * np.hypot(*u.T) * np.hypot(*v.T)
    idx = np.flatnonzero(keep)
    idx = idx[g.inside_closed(C[idx])]
    # a circumcentre on the boundary (or a segment) belongs to the boundary candidates
    idx = idx[g.boundary_distance(C[idx], pieces=True)[0] > g.tol]
    I, J, K, C = I[idx], J[idx], K[idx], C[idx]
    val = np.min(
        [np.hypot(*(C - S[I]).T), np.hypot(*(C - S[J]).T), np.hypot(*(C - S[K]).T)], axis=0
    )

    def validator(sel):
        ok = g.no_visible_closer(C[sel], val[sel], S, tree)
        if not g.convex and ok.any():
            s2 = sel[ok]
            c3 = np.repeat(C[s2], 3, axis=0)
            s3 = S[np.stack([I[s2], J[s2], K[s2]], axis=1).ravel()]
            ok[ok] = g.visible(c3, s3).reshape(-1, 3).all(1)
        if ok.any():
            s2 = sel[ok]
            ok[ok] = non_obtuse(S[I[s2]], S[J[s2]], S[K[s2]])
        return ok

    out.add(C, val, validator)
    return float(val.max()) if val.size else 0.0


def _straddles(g, xs, u, qa, qb):
    """Local maximum along the edge direction u: one site ahead, one behind."""
    sa = ((qa - xs) * u).sum(1)
    sb = ((qb - xs) * u).sum(1)
    return (np.minimum(sa, sb) <= g.tol) & (np.maximum(sa, sb) >= -g.tol)


def _boundary_general(g: PolygonGeometry, S, tree, subsegs, out: _Candidates):
    if not subsegs:
        return
    ea = np.array(subsegs, dtype=np.int64)
    a, b = S[ea[:, 1]], S[ea[:, 2]]
    L = np.hypot(*(b - a).T)
    lists = tree.query_ball_point(0.5 * (a + b), 0.5 * L * (1 + 1e-9))
    # every pair of sites among {a, b} and the sites in the diametral disk
    rows, p1, p2 = [], [], []
    for k, (_, ia, ib, sd) in enumerate(subsegs):
        q = sorted(set(lists[k]) | {ia, ib})
        if sd:
            q = [x for x in q if x in (ia, ib) or _on_side(g, S[ia], S[ib], sd, S[x])]
        for x, y in itertools.combinations(q, 2):
            rows.append(k)
            p1.append(x)
            p2.append(y)
    rows, Q1, Q2 = (np.array(v, dtype=np.int64) for v in (rows, p1, p2))
    u = (b - a) / L[:, None]
    A0, U, LL = a[rows], u[rows], L[rows]
    q1, q2 = S[Q1], S[Q2]
    den = 2.0 * ((q2 - q1) * U).sum(1)
    num = ((A0 - q2) ** 2).sum(1) - ((A0 - q1) ** 2).sum(1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = num / den
    ok = (np.abs(den) > 1e-14 * LL) & (t > g.tol) & (t < LL - g.tol)
    X = A0 + np.where(ok, t, 0.0)[:, None] * U
    ok[ok] = _straddles(g, X[ok], U[ok], q1[ok], q2[ok])
    X, Q1, Q2, EDGE = X[ok], Q1[ok], Q2[ok], ea[rows[ok], 0]
    SIDE, IA, IB = ea[rows[ok], 3], ea[rows[ok], 1], ea[rows[ok], 2]
    val = np.minimum(np.hypot(*(X - S[Q1]).T), np.hypot(*(X - S[Q2]).T))

    def validator(sel):
        ring = SIDE[sel] == 0
        ok = np.zeros(len(sel), bool)
        ok[ring] = g.no_visible_closer(X[sel[ring]], val[sel[ring]], S, tree)
        for r in np.flatnonzero(~ring):
            k = sel[r]
            d, _ = side_distance(g, X[k], S, tree, IA[k], IB[k], SIDE[k])
            ok[r] = d >= val[k] * (1.0 - EMPTY_REL)
        if not g.convex and ok.any():
            s2 = sel[ok]
            ok[ok] = g.visible(X[s2], S[Q1[s2]]) & g.visible(X[s2], S[Q2[s2]])
        return ok

    # a piece's sides are told apart by the code edge + (1 or 2) * (number of edges)
    out.add(X, val, validator, EDGE + np.where(SIDE > 0, 1, np.where(SIDE < 0, 2, 0)) * len(g.CA))


def _on_side(g, a, b, sd, q) -> bool:
    """Whether q lies strictly (beyond the tolerance) on side sd of the line a -> b
    (+1 left, -1 right)."""
    d = b - a
    return sd * float(d[0] * (q - a)[1] - d[1] * (q - a)[0]) / float(np.hypot(*d)) > g.tol


def side_distance(g, x, S, tree, ia, ib, sd):
    """The visible distance at x on a segment piece from its side sd, the limit
    approaching it from there: to the nearest of the piece's ends a, b and the
    sites strictly on that side seen from x.  Returns (distance, site)."""
    d = np.hypot(*(S - x).T)
    order = np.argsort(d, kind="stable")
    for k in order:
        if k in (ia, ib):
            return float(d[k]), int(k)
        if _on_side(g, S[ia], S[ib], sd, S[k]) and g.visible(x[None], S[k][None])[0]:
            return float(d[k]), int(k)
    raise RuntimeError("a piece sees its own ends")  # pragma: no cover


def _candidates_voronoi(g: PolygonGeometry, S, tree, out: _Candidates):
    """The paper's Step 3: Voronoi vertices inside P, Voronoi edges cut with the boundary."""
    vor = Voronoi(S)
    VV = vor.vertices
    # ---- Voronoi vertices inside P (local maxima only; on-boundary ones go to the edges)
    defining: list[list[int]] = [[] for _ in range(len(VV))]
    for site, reg in enumerate(vor.point_region):
        for v in vor.regions[reg]:
            if v >= 0:
                defining[v].append(site)
    cand = np.flatnonzero(g.inside_closed(VV))
    cand = cand[g.boundary_distance(VV[cand])[0] > g.tol]
    ivals = tree.query(VV[cand], k=1)[0] if cand.size else np.zeros(0)

    def local_max(sel):
        # any triangle of its defining sites (several when cocircular) non-obtuse
        grp, tris = [], []
        for r, v in enumerate(cand[sel]):
            for tri in itertools.combinations(defining[v], 3):
                grp.append(r)
                tris.append(tri)
        tri = np.array(tris, dtype=np.int64).reshape(-1, 3)
        ok = non_obtuse(S[tri[:, 0]], S[tri[:, 1]], S[tri[:, 2]])
        res = np.zeros(len(sel), dtype=bool)
        np.logical_or.at(res, np.array(grp, dtype=np.int64), ok)
        return res

    out.add(VV[cand], ivals, local_max)
    # ---- Voronoi edges (finite segments and infinite rays) against the boundary
    rp = np.asarray(vor.ridge_points)
    rv = np.asarray(vor.ridge_vertices)
    centre = S.mean(axis=0)
    O = np.empty((len(rp), 2))
    D = np.empty((len(rp), 2))
    tmax = np.empty(len(rp))
    fin = (rv >= 0).all(1)
    O[fin] = VV[rv[fin, 0]]
    D[fin] = VV[rv[fin, 1]] - VV[rv[fin, 0]]
    tmax[fin] = 1.0
    inf = np.flatnonzero(~fin)
    tt = S[rp[inf, 1]] - S[rp[inf, 0]]
    tt /= np.hypot(*tt.T)[:, None]
    nn = np.stack([-tt[:, 1], tt[:, 0]], axis=1)
    mid = 0.5 * (S[rp[inf, 0]] + S[rp[inf, 1]])
    sign = np.sign(((mid - centre) * nn).sum(1))
    O[inf] = VV[rv[inf].max(1)]
    D[inf] = sign[:, None] * nn
    tmax[inf] = np.inf
    A, E = g.A, g.E
    denom, t, s = _intersections(O, D, A, E)
    eps_s = 1e-12
    Dn = np.hypot(*D.T)
    eps_t = (g.tol / np.where(Dn > 0, Dn, 1.0))[:, None]
    hit = (
        (denom != 0)
        & (s >= -eps_s)
        & (s <= 1 + eps_s)
        & (t >= -eps_t)
        & (t <= tmax[:, None] + eps_t)
    )
    r_i, e_i = np.nonzero(hit)
    s_h = np.clip(s[r_i, e_i], 0.0, 1.0)
    X = A[e_i] + s_h[:, None] * E[e_i]
    u = E[e_i] / g.elen[e_i, None]
    st = _straddles(g, X, u, S[rp[r_i, 0]], S[rp[r_i, 1]])
    X, e_i = X[st], e_i[st]
    bval = tree.query(X, k=1)[0] if len(X) else np.zeros(0)
    # the boundary vertices themselves are sites (weight 0): drop intersections there
    nz = bval > g.tol
    out.add(X[nz], bval[nz], lambda sel: np.ones(len(sel), dtype=bool), e_i[nz])


def tie_break(g: PolygonGeometry, pts, vals) -> int:
    """The tie rule (module docstring); returns the index of the chosen point."""
    W = vals.max()
    C = np.flatnonzero(vals >= W * (1.0 - TIE_REL))
    xn = (pts[C, 0] - g.centre[0]) / g.size
    yn = (pts[C, 1] - g.centre[1]) / g.size
    C2 = np.flatnonzero(xn <= xn.min() + TIE_X)
    C3 = C2[yn[C2] <= yn[C2].min() + TIE_X]
    return int(C[C3[np.argmin(xn[C3])]])


def reference_insert(
    polygon: Polygon,
    n: int,
    sites=None,
    *,
    method: str = "auto",
    prune: bool = True,
    diagnostics: bool = False,
) -> ReferenceResult:
    """Run Algorithm INSERT by brute force for ``n`` steps.

    Returns a :class:`ReferenceResult` (unpacks as ``points, weights, on_boundary``):
    ``points`` (n, 2), ``weights`` (n,) -- w_{j-1}(p_j), the visible distance of p_j
    to the sites before it was inserted -- and ``on_boundary`` (n,) bool.

    ``method``: ``"voronoi"`` (paper's Step 3 with scipy's Voronoi; convex polygons
    without holes only), ``"general"`` (brute-force triples and pairs, any polygon)
    or ``"auto"`` (voronoi when the polygon is convex without holes).  ``prune``:
    restrict the triples to pairwise distances <= 2 w_{j-1} (exact because the
    weights never increase; switch off to check exactly that).  ``diagnostics``:
    validate every candidate to record, per step, the relative gap between the
    chosen weight and the best candidate outside the tied set (``result.gap``).
    """
    # Work in normalised coordinates (bounding-box centre at the origin, size 1) so
    # that a translated or scaled polygon is computed exactly like the original one.
    x0, y0, x1, y1 = polygon.bounds
    centre = np.array([(x0 + x1) / 2.0, (y0 + y1) / 2.0])
    size = max(x1 - x0, y1 - y0)
    poly_n = Polygon((polygon.outer - centre) / size, [(h - centre) / size for h in polygon.holes])
    if sites is not None:
        sites = (np.asarray(sites, dtype=np.float64).reshape(-1, 2) - centre) / size
    # segment vertices and fixed points are sites from the start (they follow the
    # ring vertices); the pieces keep their indices
    g = PolygonGeometry(poly_n, (polygon.vertices - centre) / size, polygon.segment_edges)
    if method == "auto":
        method = "voronoi" if g.convex else "general"
    if method == "voronoi" and not g.convex:
        raise ValueError("the Voronoi method needs a convex polygon without holes")
    if method not in ("voronoi", "general"):
        raise ValueError(f"unknown method {method!r}")
    state = _State(g, sites)
    pts = np.zeros((n, 2))
    wts = np.zeros(n)
    onb = np.zeros(n, dtype=bool)
    res = ReferenceResult(pts, wts, onb)
    w_prev = np.inf
    for j in range(n):
        S = np.array(state.sites, dtype=np.float64)
        tree = cKDTree(S)
        cands = _Candidates()
        if method == "voronoi":
            _candidates_voronoi(g, S, tree, cands)
        else:
            _interior_general(g, S, tree, w_prev, prune, cands)
            _boundary_general(g, S, tree, state.subsegments(), cands)
        p, boundary, edge, nraw, ntied, gap = cands.select(g, diagnostics)
        w, _ = g.visible_distance(p[None], S, tree)
        if edge is not None and edge >= len(g.CA):  # one side of a segment piece
            edge, code = edge % len(g.CA), edge // len(g.CA)
            lst = sorted(state.on_edge[edge])
            ts = float(np.dot(p - g.CA[edge], g.CE[edge]) / g.clen[edge] ** 2)
            k = max(i for i in range(len(lst)) if lst[i][0] < ts)
            w = [side_distance(g, p, S, tree, lst[k][1], lst[k + 1][1], 1 if code == 1 else -1)[0]]
        pts[j] = p
        wts[j] = w[0]
        onb[j] = boundary
        res.n_candidates.append(nraw)
        res.n_tied.append(ntied)
        res.gap.append(gap)
        state.add(p, edge)
        w_prev = wts[j]
    pts[:] = pts * size + centre
    wts *= size
    return res
