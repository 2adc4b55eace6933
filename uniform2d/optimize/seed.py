"""Starting points for the optimiser: boundary pieces and a hexagonal lattice.

Boundary counts, lattice orientation and the seed's first layer fix the mesh's
structure, which moving points cannot change; :func:`variants` lists the
starts the pipeline tries.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .._kernel.distance import to_segments
from ..geometry import polygon_edges, size_for_count
from ..polygon import Polygon
from ..triangulation import triangulate
from . import schedule

__all__ = ["target_size", "lattice_seed", "variants", "boundary_counts", "boundary_points"]

#: Corner fan points sit at most FAN_CAP target sizes from their corner.
FAN_CAP = 1.5


def target_size(polygon: Polygon, n: int) -> float:
    """Side h of an equilateral mesh of P with |V| + n vertices.

    The inverse of :func:`uniform2d.steiner_count_for_size`."""
    return size_for_count(polygon.area, polygon.perimeter, n + len(polygon.vertices), polygon.n_holes)


def boundary_counts(L: np.ndarray, h: float, n: int) -> np.ndarray:
    """Pieces per polygon edge: round(L/h), at least 1, at most n extra points in total."""
    m = np.maximum(1, np.rint(L / h)).astype(np.int64)
    while (m - 1).sum() > n:
        e = int(np.argmin(np.where(m > 1, L / m, np.inf)))  # merge on the shortest pieces
        m[e] -= 1
    return m


def boundary_points(a, d, m):
    """The points splitting polygon edge e (start a[e], vector d[e]) into m[e]
    equal pieces: (points, their edge, their parameter on it)."""
    pts, eid, t = [], [], []
    for e in range(len(m)):
        s = np.arange(1, m[e]) / m[e]
        pts.append(a[e] + d[e] * s[:, None])
        eid.append(np.full(len(s), e, dtype=np.int64))
        t.append(s)
    if not pts:
        return np.empty((0, 2)), np.empty(0, np.int64), np.empty(0)
    return np.concatenate(pts), np.concatenate(eid), np.concatenate(t)


#: Rows of :func:`_hex_lattice` made at a time: a dozen full-size temporaries of
#: the lattice over the polygon's box cost hundreds of MB at 1e6 points; row
#: blocks keep those to a few MB, the result unchanged.
LATTICE_ROWS = 64


def _hex_lattice(bounds, spacing: float, angle: float, origin) -> np.ndarray:
    """The points of a hexagonal lattice (anchored at ``origin``, rows at ``angle``)
    within ``bounds`` = (xmin, ymin, xmax, ymax): the only ones that can lie inside
    a shape with those bounds.  Row by row, in a fixed order."""
    xmin, ymin, xmax, ymax = bounds
    dy = spacing * math.sqrt(3.0) / 2
    c, s = math.cos(angle), math.sin(angle)
    # the rows and columns that can reach the box (a margin of two steps for
    # the half-step shift of odd rows and for rounding), in lattice coordinates
    X = np.array([xmin, xmax, xmax, xmin]) - origin[0]
    Y = np.array([ymin, ymin, ymax, ymax]) - origin[1]
    U, V = c * X + s * Y, -s * X + c * Y
    j0, j1 = math.floor(V.min() / dy) - 2, math.ceil(V.max() / dy) + 2
    i0, i1 = math.floor(U.min() / spacing) - 2, math.ceil(U.max() / spacing) + 2
    out = []
    for jb in range(j0, j1 + 1, LATTICE_ROWS):
        j, i = np.meshgrid(np.arange(jb, min(jb + LATTICE_ROWS, j1 + 1)), np.arange(i0, i1 + 1),
                           indexing="ij")
        u = (i + 0.5 * (j & 1)) * spacing
        v = j * dy
        x = origin[0] + c * u - s * v
        y = origin[1] + s * u + c * v
        keep = (x >= xmin) & (x <= xmax) & (y >= ymin) & (y <= ymax)
        out.append(np.stack([x[keep], y[keep]], axis=1))
    return np.concatenate(out, axis=0)


def lattice_seed(polygon: Polygon, count: int, *, rows: bool = True) -> np.ndarray:
    """Exactly ``count`` points of a hexagonal lattice inside P, away from its boundary.

    With ``rows`` (default), the first layer is a fan at every corner of
    90 degrees or more that is not within 30 degrees of straight (points one
    edge length from the corner that split its angle into near-60-degree
    parts), then one point above the middle of every polygon edge, at the apex
    of the equilateral triangle on it (those crowding a point before them
    dropped): the boundary's own spacing, wherever it is.  Interior segments
    count as boundary on both sides (a free end is a corner of 360 degrees).
    The lattice, aligned with P's longest edge, fills the rest; its spacing is
    chosen so that the count comes out (the last few are dropped near the
    boundary or added in the largest gaps).  Where segments split P into
    regions, each region gets its share of the count and a lattice of its own.
    A structured start for :func:`uniform2d.optimize.improve`: relaxing a
    lattice ends far more uniform than relaxing scattered points.

    Parameters
    ----------
    polygon : Polygon
    count : int
    rows : bool

    Returns
    -------
    ndarray, shape (count, 2)

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> from uniform2d.optimize import lattice_seed
    >>> lattice_seed(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), 9).shape
    (9, 2)
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    count = int(count)
    h = target_size(polygon, count)
    pieces = np.ones(len(polygon.constraint_edges), np.int64)
    first = boundary_rows(polygon, pieces, h) if rows else None
    return seed_interior(polygon, count, h, np.empty((0, 2)), None, first)


def boundary_rows(polygon: Polygon, m: np.ndarray, h: float) -> np.ndarray:
    """One row of points along every polygon edge and segment piece (m[e] pieces
    of each of :attr:`~uniform2d.Polygon.constraint_edges`): above the middle of
    each piece, at the apex of the equilateral triangle on it, inside P for a
    ring edge and on both sides for a segment piece (P is on both), after the
    corners' fans (:func:`corner_fans`), keeping only those clear of the
    constraint edges and fixed points and of the points before them (the fans
    win at corners)."""
    a, d, L = polygon_edges(polygon, constraints=True)
    rows, gaps = corner_fans(polygon, L / m, h)
    n_ring = len(polygon.edges)
    for e in range(len(L)):
        g = L[e] / m[e]
        nrm = np.array([-d[e, 1], d[e, 0]]) / L[e]  # left normal: into P on every ring
        s = (np.arange(m[e]) + 0.5) / m[e]
        mid = a[e] + d[e] * s[:, None]
        for side in (1.0,) if e < n_ring else (1.0, -1.0):
            rows.append(mid + side * nrm * g * math.sqrt(3) / 2)
            gaps.append(np.full(m[e], g))
    R, G = np.concatenate(rows), np.concatenate(gaps)
    shp = polygon.to_shapely()
    ok = shapely.contains_xy(shp, R[:, 0], R[:, 1])
    a, b = _keep_clear(polygon)
    ok &= to_segments(R, a, b, 0.6 * G.max()) >= 0.6 * G
    R, G = R[ok], G[ok]
    keep = []
    tree = cKDTree(R)
    taken = np.zeros(len(R), bool)
    for i in range(len(R)):  # greedy, in ring order: the first of two crowded points stays
        if taken[i]:
            continue
        keep.append(i)
        taken[tree.query_ball_point(R[i], 0.75 * G[i])] = True
    return R[keep]


def _keep_clear(polygon: Polygon):
    """(starts, ends) of what seed points keep clear of: the rings' edges, the
    segment pieces and, as segments of length zero, the fixed points."""
    a, d, _ = polygon_edges(polygon, constraints=True)
    if not len(polygon.fixed):
        return a, a + d
    f = polygon.vertices[polygon.fixed]
    return np.concatenate([a, f]), np.concatenate([a + d, f])


def corner_fans(polygon: Polygon, piece: np.ndarray, h: float):
    """Points that split every polygon corner of angle theta into
    k = round(theta / 60 degrees) equal angles, one boundary piece away from the
    corner (at most :data:`FAN_CAP` h: a polygon edge left whole is no guide):
    the corner's fan of near-equilateral triangles.  Only for k = 2 and k >= 4:
    below 90 degrees there is nothing to split, and a vertex within 30 degrees
    of straight (k = 3) is split into three by the apexes of
    :func:`boundary_rows` already (on the surface layer's domains, those are
    the vertices that are not corners).  At a vertex that segment pieces
    touch, the corners are the angles between its consecutive constraint edges
    (:func:`_sectors`): a free end of a segment is a corner of 360 degrees.
    ``piece`` holds the piece length of every constraint edge.

    Returns lists of (1, 2) points and of their (1,) spacings."""
    E = polygon.edges
    V = polygon.vertices
    theta = polygon.interior_angles()
    _, d, L = polygon_edges(polygon)
    e_in = np.empty(len(V), np.int64)
    e_in[E[:, 1]] = np.arange(len(E))
    joined = np.zeros(len(V), bool)
    joined[polygon.segment_edges.ravel()] = True
    out, gaps = [], []
    for e in range(len(E)):  # e leaves vertex v: the interior is on its left
        v = E[e, 0]
        if joined[v]:
            continue
        _fan(out, gaps, V[v], d[e] / L[e], theta[v], 0.5 * (piece[e] + piece[e_in[v]]), h)
    for v, u, phi, c1, c2 in _sectors(polygon, np.flatnonzero(joined)):
        _fan(out, gaps, V[v], u, phi, 0.5 * (piece[c1] + piece[c2]), h)
    return out, gaps


def _fan(out: list, gaps: list, v, u, theta: float, piece: float, h: float) -> None:
    """Append the fan of the corner at ``v`` that opens counter-clockwise from
    unit direction ``u`` by ``theta``: see :func:`corner_fans`."""
    k = int(math.floor(theta / (math.pi / 3) + 0.5))
    if k < 2 or k == 3:  # k = 3: a near-straight vertex, the rows' apexes split it
        return
    g = min(piece, FAN_CAP * h)
    for j in range(1, k):
        phi = j * theta / k
        c, s = math.cos(phi), math.sin(phi)
        out.append(v + g * np.array([[c * u[0] - s * u[1], s * u[0] + c * u[1]]]))
        gaps.append(np.full(1, g))


def _sectors(polygon: Polygon, vertices):
    """The corners inside P at each of ``vertices`` between consecutive
    constraint edges (counter-clockwise): (vertex, unit direction of the first
    edge, angle, constraint edge of the first and of the second side)."""
    C = polygon.constraint_edges
    V = polygon.vertices
    ring_in = np.full(len(V), -1, np.int64)
    ring_in[polygon.edges[:, 1]] = np.arange(len(polygon.edges))
    out = []
    for v in vertices:
        cs = np.flatnonzero((C[:, 0] == v) | (C[:, 1] == v))
        w = np.where(C[cs, 0] == v, C[cs, 1], C[cs, 0])
        u = V[w] - V[v]
        u /= np.hypot(u[:, 0], u[:, 1])[:, None]
        ang = np.arctan2(u[:, 1], u[:, 0])
        order = np.lexsort((cs, ang))
        cs, u, ang = cs[order], u[order], ang[order]
        gap = np.diff(np.append(ang, ang[0] + 2 * math.pi))
        for i in range(len(cs)):
            if cs[i] == ring_in[v]:  # from the incoming ring edge on: outside P
                continue
            j = (i + 1) % len(cs)
            out.append((v, u[i], float(gap[i]), int(cs[i]), int(cs[j])))
    return out


class _Candidates:
    """Lattice points of a given spacing inside P (or inside ``face``, one of its
    regions, anchored at ``origin``), clear of its boundary and of the first rows
    (when given): the candidates :func:`seed_interior` counts."""

    def __init__(self, polygon: Polygon, h: float, edge: int | None, rows, face=None, origin=None):
        a, d, L = polygon_edges(polygon)
        e = int(np.argmax(L)) if edge is None else int(edge)
        self.angle = math.atan2(d[e, 1], d[e, 0])
        # anchor a lattice row at distance h·√3/2 inside the chosen edge
        nrm = np.array([-d[e, 1], d[e, 0]]) / L[e]  # left normal: inside for the CCW outer ring
        self.origin = a[e] + nrm * h * math.sqrt(3) / 2 + d[e] / L[e] * (h / 2)
        if origin is not None:
            self.origin = origin
        self.shape = polygon.to_shapely() if face is None else face
        self.bounds = polygon.bounds if face is None else face.bounds
        shapely.prepare(self.shape)
        self.sa, self.sb = _keep_clear(polygon)  # clear of the segments and fixed points too
        self.rows = rows
        if rows is not None:
            self.rtree = cKDTree(rows)
            self.band = h * math.sqrt(3) / 2

    def __call__(self, sp):
        P = _hex_lattice(self.bounds, sp, self.angle, self.origin)
        inside = shapely.contains_xy(self.shape, P[:, 0], P[:, 1])
        P = P[inside]
        rows = self.rows is not None
        # only distances below the cap matter, here and in the drop below
        cap = (2.0 * self.band + 2.0 * sp) if rows else 2.0 * sp
        dist = to_segments(P, self.sa, self.sb, cap)
        ok = dist >= 0.5 * sp
        if rows:  # rows lie within ~band of the boundary: test only near ones
            ok &= dist >= self.band + 0.5 * sp
            near = np.flatnonzero(ok & (dist < 2.0 * self.band + sp))
            ok[near] = self.rtree.query(P[near])[0] >= 0.75 * sp
        return P[ok], dist[ok]


def _closest_count(cand: _Candidates, count: int, h: float, over: bool = False, under: bool = False):
    """Search on the lattice spacing for ``count`` candidates (the count
    decreases with the spacing); the best (points, distances) found.

    Bisection, stopping within ``count // 500`` of the count.  With ``over``
    (the optimiser's starts) it stops only at up to that many candidates too
    many (the fix-up, :func:`_drop_nearest`, drops the extra ones nearest to
    the boundary), not too few: filling those (:func:`_fill_largest_gaps`)
    triangulates the whole seed.  With ``over`` and a tolerance (count >= 500)
    each step also aims where the count, about proportional to 1/spacing**2,
    says the target is (:func:`_aim`), bisecting only where that would not
    halve the bracket, and gives up where the bracket is 1e-4 h wide (the
    count jumps there: a row of an aligned lattice enters at once): 9 lattices
    a start instead of 14 on the benchmark polygons at n = 1000.  Below 500
    the count must come out exactly, and the plain bisection's lattice (which
    can sit a hair from such a jump) gave better minimum angles at n = 200.
    ``under`` (the optimiser's large starts) is ``over``'s search stopping at
    up to ``count // 500`` candidates too few instead, which
    :func:`_fill_band_gaps` adds where the lattice meets the boundary: points
    dropped from that layer leave holes there that the short schedule of a
    large mesh does not close (its longest edges and largest triangles)."""
    lo, hi = 0.5 * h, 1.5 * h
    best = None
    mid = 0.5 * (lo + hi)
    fast = (over or under) and count // 500 > 0
    aimed = False
    for _ in range(30):
        P, dist = cand(mid)
        if best is None or abs(len(P) - count) < abs(len(best[0]) - count) or (
            abs(len(P) - count) == abs(len(best[0]) - count) and len(P) >= count
        ):
            best = (P, dist)
        if over and 0 <= len(P) - count <= count // 500:
            return P, dist
        if under and 0 <= count - len(P) <= count // 500:
            return P, dist
        if not (over or under) and abs(len(P) - count) <= count // 500:  # the fix-up after it is exact
            break
        width = hi - lo
        if len(P) > count:
            lo = mid
        else:
            hi = mid
        if fast and hi - lo < 1e-4 * h:
            break
        # aim, unless the last aim left more than half the bracket (then bisect)
        aimed = fast and not (aimed and hi - lo > 0.5 * width)
        mid = _aim(mid, len(P), count, lo, hi, under) if aimed else 0.5 * (lo + hi)
    return best


def _aim(sp: float, got: int, count: int, lo: float, hi: float, under: bool = False) -> float:
    """The next spacing to try after ``got`` candidates at ``sp``: where the
    count would be ``count`` (plus a quarter of the tolerance, to land above
    it; minus, ``under``, to land below) if it went as 1/spacing**2, strictly
    inside the bracket (lo, hi)."""
    want = count + (-1.0 if under else 1.0) * (0.25 * (count // 500) + 0.5)
    x = sp * math.sqrt(max(got, 1) / want)
    margin = 1e-3 * (hi - lo)
    return min(max(x, lo + margin), hi - margin)


def _fill_largest_gaps(polygon: Polygon, bpts, P, count: int, face=None, bedges=None) -> np.ndarray:
    """Add the centroids of the largest triangles (of those inside ``face``, if
    given) until there are ``count`` points.  ``bedges``: the polygon edge of
    each of ``bpts``, known by construction (default: judged by distance)."""
    while len(P) < count:
        allp = np.concatenate([polygon.vertices, bpts, P])
        edges = None if bedges is None else np.concatenate([bedges, np.full(len(P), -1, np.int64)])
        _, tri = triangulate(polygon, allp[len(polygon.vertices):], edges)
        area = np.empty(len(tri))
        for lo in range(0, len(tri), GAP_BLOCK):  # (K, 3, 2) corners a block at a time
            q = allp[tri[lo:lo + GAP_BLOCK]]
            u, v = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]
            area[lo:lo + len(q)] = 0.5 * np.abs(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
            if face is not None:
                c = q.mean(axis=1)
                area[lo:lo + len(q)][~shapely.contains_xy(face, c[:, 0], c[:, 1])] = -1.0
        need = min(count - len(P), int(np.count_nonzero(area >= 0)))
        if need == 0:
            break
        order = np.lexsort((np.arange(len(tri)), -area))[:need]
        P = np.concatenate([P, allp[tri[order]].mean(axis=1)])
    return P


#: Triangles measured at a time by :func:`_fill_largest_gaps`.
GAP_BLOCK = 1 << 16


def _fill_band_gaps(polygon: Polygon, bpts, P, count: int, h: float, sa, sb, bedges=None):
    """:func:`_fill_largest_gaps` for a start with a few points too few, whose
    gaps are where the lattice meets the boundary (or its rows): only the points
    within BAND_FILL * h of the boundary are triangulated (not the whole seed,
    ~2 s at 1e6 points), and only triangles whose centroid is within
    (BAND_FILL - 2) * h count, not those across the empty interior."""
    far = BAND_FILL * h
    while len(P) < count:
        near = np.flatnonzero(to_segments(P, sa, sb, far) < far)
        allp = np.concatenate([polygon.vertices, bpts, P[near]])
        edges = None if bedges is None else np.concatenate([bedges, np.full(len(near), -1, np.int64)])
        _, tri = triangulate(polygon, allp[len(polygon.vertices):], edges)
        q = allp[tri]
        u, v = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]
        area = 0.5 * np.abs(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
        c = q.mean(axis=1)
        area[to_segments(c, sa, sb, far) >= far - 2.0 * h] = -1.0
        need = min(count - len(P), int(np.count_nonzero(area >= 0)))
        if need == 0:
            break
        P = np.concatenate([P, c[_largest_spread(area, c, need)]])
    return P


def _largest_spread(area, c, need: int) -> np.ndarray:
    """The indices of ``need`` of the largest ``area``s.  Along a straight edge
    many gaps have the same area (to rounding): of those at the cut, evenly
    spaced ones in the order of their centroids ``c``, not a run of neighbours
    (two points in adjacent gaps crowd each other, and the rest stay open)."""
    key = np.round(area / area.max(), 9)
    order = np.lexsort((np.arange(len(key)), -key))
    cut = key[order[need - 1]]
    above = order[key[order] > cut]
    tied = np.flatnonzero(key == cut)
    tied = tied[np.lexsort((tied, c[tied, 1], c[tied, 0]))]
    k = need - len(above)
    return np.concatenate([above, tied[(np.arange(k) * len(tied)) // k]])


#: Depth (in sizes h) of the band :func:`_fill_band_gaps` triangulates: past
#: the boundary rows (~0.9 h) and the lattice's first layers.
BAND_FILL = 6.0


def _drop_nearest(cand: _Candidates, P, dist, count: int) -> np.ndarray:
    """The ``count`` of the lattice points P farthest from the boundary (in
    their order)."""
    if len(P) <= count:
        return P
    if np.count_nonzero(dist < dist.max()) < len(P) - count:  # capped ones would go
        dist = to_segments(P, cand.sa, cand.sb, np.inf)
    order = np.lexsort((np.arange(len(P)), dist))
    return P[np.sort(order[len(P) - count :])]


def seed_interior(
    polygon: Polygon, count: int, h: float, bpts: np.ndarray, edge: int | None = None,
    rows: np.ndarray | None = None, bedges: np.ndarray | None = None, over: bool = False,
    under: bool = False,
) -> np.ndarray:
    """``count`` interior points on a hexagonal lattice aligned with polygon edge
    ``edge`` (default: the longest), deterministic.  With ``rows`` (from
    :func:`boundary_rows`) those come first and the lattice fills the rest,
    clear of them.  Where the segments split P into regions, each region gets
    its own share of the points (:func:`_region_shares`): points cannot cross
    a segment afterwards, so a region seeded too densely stays so.  ``bedges``
    (optional): the polygon edge of each boundary point ``bpts``, as the caller
    placed them, so that gaps are found without judging them by distance.
    ``over``: as :func:`_closest_count`'s (the optimiser's starts; the default
    keeps :func:`lattice_seed`'s points as they were); ``under``: also as
    its, where the lattice is not split into regions."""
    if count <= 0:
        return np.empty((0, 2))
    if rows is not None and len(rows) >= count:
        rows = None
    if rows is not None and len(polygon.segment_edges) and len(polygon.regions) > 1:
        return _seed_regions(polygon, count, h, bpts, edge, rows, bedges, over)
    cand = _Candidates(polygon, h, edge, rows)
    total = count
    if rows is not None:
        count = total - len(rows)
    P, dist = _closest_count(cand, count, h, over and not under, under)
    P = _drop_nearest(cand, P, dist, count)
    if rows is not None:
        P = np.concatenate([rows, P])
        count = total
    if under:
        return _fill_band_gaps(polygon, bpts, P, count, h, cand.sa, cand.sb, bedges)
    return _fill_largest_gaps(polygon, bpts, P, count, bedges=bedges)


def _seed_regions(
    polygon: Polygon, count: int, h: float, bpts, edge, rows, bedges=None, over=False
) -> np.ndarray:
    """:func:`seed_interior` region by region: the rows, then in each region a
    lattice (of its own spacing, see :func:`_anchor`) topped up to the region's
    share."""
    faces = polygon.regions.faces
    sides = _sides(polygon, faces)
    share = _region_shares(polygon, faces, sides, h, count)
    P = np.empty((0, 2)) if rows is None else rows
    angle = _Candidates(polygon, h, edge, None).angle
    for r, face in enumerate(faces):
        have = int(np.count_nonzero(shapely.contains_xy(face, P[:, 0], P[:, 1])))
        need = share[r] - have
        if need <= 0:
            continue
        cand = _Candidates(polygon, h, edge, rows, face, _anchor(polygon, sides, r, angle, h))
        Q, dist = _closest_count(cand, need, h, over)
        P = np.concatenate([P, _drop_nearest(cand, Q, dist, need)])
        P = _fill_largest_gaps(polygon, bpts, P, len(P) + need - min(need, len(Q)), face, bedges)
    if len(P) > count:  # rows beyond some region's share: drop lattice points instead
        first = 0 if rows is None else len(rows)
        dist = to_segments(P[first:], *_keep_clear(polygon), np.inf)
        order = np.lexsort((np.arange(len(dist)), dist))
        P = np.concatenate([P[:first], P[first:][np.sort(order[len(P) - count:])]])
    return _fill_largest_gaps(polygon, bpts, P, count, bedges=bedges)[:count]


def _sides(polygon: Polygon, faces) -> np.ndarray:
    """(E + S, 2): the region on the left and on the right of every constraint
    edge (-1 for none: outside P).

    Matched exactly: the faces are closed from the constraint edges themselves,
    so an edge on a face's boundary is a pair of consecutive vertices of one of
    its rings, which has the face on its left where it runs counter-clockwise
    round the face (a probe a small step off the edge can land in the wrong
    region where the region is thinner than the step).  An edge on no face's
    boundary (a free piece, a bridge) lies inside one face, on both sides."""
    left = {}
    for r, f in enumerate(faces):
        for k, ring in enumerate((f.exterior, *f.interiors)):
            xy = [tuple(c) for c in np.asarray(ring.coords)]
            if ring.is_ccw != (k == 0):  # the face's side first
                xy.reverse()
            left.update({(p, q): r for p, q in zip(xy[:-1], xy[1:])})
    V = [tuple(v) for v in polygon.vertices.tolist()]
    E = polygon.constraint_edges
    out = np.array([[left.get((V[u], V[v]), -1), left.get((V[v], V[u]), -1)] for u, v in E],
                   dtype=np.int64).reshape(-1, 2)
    a, d, _ = polygon_edges(polygon, constraints=True)
    for e in np.flatnonzero((out == -1).all(axis=1) & (np.arange(len(E)) >= len(polygon.edges))):
        mid = a[e] + 0.5 * d[e]
        inside = [r for r, f in enumerate(faces) if shapely.contains_xy(f, *mid)]
        out[e] = inside[0] if inside else -1
    return out


def _anchor(polygon: Polygon, sides: np.ndarray, r: int, angle: float, h: float) -> np.ndarray:
    """Where a lattice at ``angle`` starts in region r: at the apex, inside the
    region, of the piece on its boundary nearest to that angle (modulo 60
    degrees; the longest of those within a degree), so that the lattice meets
    that piece's row of :func:`boundary_rows` in step."""
    a, d, L = polygon_edges(polygon, constraints=True)
    on = np.flatnonzero((sides == r).any(axis=1))
    ang = np.arctan2(d[on, 1], d[on, 0])
    off = np.abs((ang - angle + math.pi / 6) % (math.pi / 3) - math.pi / 6)
    near = off <= max(off.min(), math.radians(1.0))
    e = on[np.lexsort((on, -L[on], ~near))[0]]
    side = 1.0 if sides[e, 0] == r else -1.0
    return a[e] + 0.5 * d[e] + side * np.array([-d[e, 1], d[e, 0]]) / L[e] * h * math.sqrt(3) / 2


def _region_shares(polygon: Polygon, faces, sides, h: float, count: int) -> np.ndarray:
    """How many of ``count`` interior points each region gets: in proportion to
    the interior vertices of an equilateral mesh of side h of it (Euler's
    formula: 2A/(sqrt(3) h^2) - B/(2h) + 1 - holes, a free segment inside it
    counting as boundary on both sides, a fixed point off the segments as one
    vertex), by largest remainders."""
    _, _, L = polygon_edges(polygon, constraints=True)
    on_seg = np.zeros(len(polygon.vertices), bool)
    on_seg[polygon.segment_edges.ravel()] = True
    lone = polygon.vertices[polygon.fixed[~on_seg[polygon.fixed]]]
    want = np.empty(len(faces))
    for r, f in enumerate(faces):
        free = L[(sides[:, 0] == r) & (sides[:, 1] == r)].sum()
        n_lone = np.count_nonzero(shapely.contains_xy(f, lone[:, 0], lone[:, 1]))
        want[r] = (2.0 * f.area / (math.sqrt(3.0) * h * h) - (f.length + 2.0 * free) / (2.0 * h)
                   + 1.0 - len(f.interiors) - n_lone)
    want = np.maximum(want, 0.0) + 1e-12
    exact = count * want / want.sum()
    share = np.floor(exact).astype(np.int64)
    extra = np.lexsort((np.arange(len(faces)), share - exact))[: count - int(share.sum())]
    share[extra] += 1
    return share


def variants(polygon: Polygon, n: int):
    """The starts tried: (boundary spacing / h, lattice edge, boundary rows).

    Boundary counts, lattice orientation and the seed's first layer decide the
    mesh's structure, which the point moves cannot change, and the best choice
    depends on the polygon.  Small meshes (up to ``schedule.SMALL`` points) try
    the lattice aligned with the longest edge and with the longest one at
    another angle (modulo 60 degrees), each with every boundary spacing of
    ``schedule.SPACINGS``, with and without a row of points on every edge
    (:func:`boundary_rows`); up to ``schedule.LARGE`` points the
    ``schedule.SPACINGS_MEDIUM`` with rows; beyond, where a start costs most,
    one start.
    """
    _, d, L = polygon_edges(polygon)
    first = int(np.argmax(L))
    if n + len(polygon.vertices) > schedule.LARGE:
        return [(1.0, first, schedule.LAYERED_LARGE)]
    ang = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
    off = np.abs((ang - ang[first] + 30.0) % 60.0 - 30.0)
    other = [e for e in np.lexsort((np.arange(len(L)), -L)) if off[e] > 5.0]
    edges = [first] + ([int(other[0])] if other else [])
    if n + len(polygon.vertices) <= schedule.SMALL:
        spacings, layers = schedule.SPACINGS, schedule.LAYERED
    else:
        spacings, layers = schedule.SPACINGS_MEDIUM, schedule.LAYERED_MEDIUM
    return [(c, e, lay) for lay in layers for e in edges for c in spacings]
