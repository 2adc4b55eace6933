"""Beyond the paper: the most uniform mesh uniform2d can make with exactly n Steiner points.

Pipeline (:func:`optimize_mesh`):

1. **Target size.**  h solves "an equilateral mesh of side h has |V| + n vertices"
   (the count of :func:`uniform2d.uniform.steiner_count_for_size`, inverted).
2. **Starts.**  Boundary: every polygon edge of length L gets
   m = max(1, round(L / (c h))) equal pieces (k = sum(m - 1) boundary points; fewer
   if k would exceed n).  Interior: n - k points of a hexagonal lattice aligned
   with one polygon edge, at least half a spacing inside P, optionally after a
   first row at the apex of the equilateral triangle over every boundary piece
   (:func:`_boundary_rows`, :func:`lattice_seed`), which begins with a fan at
   every corner of 90 degrees or more (not near-straight) that splits it into
   angles near 60 degrees (:func:`_corner_fans`).  Boundary counts, lattice
   orientation and the first row fix the mesh's structure, which moving points
   cannot change, and the best choice depends on the polygon: small meshes try
   several (:func:`_variants`), rank them by a short :data:`TRIAL` run (on the
   objective; ``"balanced"`` also weighs the edge CV, :data:`CV_WEIGHT`) and
   give the best the full schedule.  Lattice points deeper than :data:`BAND`
   sizes inside P are uniform already and stay put.
3. **Moving points** (:func:`improve`, kernel :mod:`uniform2d._kernel.relax`).
   The constrained Delaunay triangulation of the points is built once and kept
   valid and Delaunay by exact predicates and flips while the points move:
   polygon vertices fixed, boundary points sliding along their edges in order,
   interior points free.  First spring rounds (least squares towards equal
   edges), then Gauss-Seidel descent on the p-norm energy of the objective for
   p = 16 ... 256 (4 ... 64 with a size field; ``"ratio"``: sum l^p + l^-p;
   ``"max_edge"``: sum l^p; ``"max_perimeter"``: sum over triangles of
   perimeter^p; ``"balanced"``: all, each sum weighted by its exponent in the
   objective over its present value, so that none drowns the others), keeping
   the best state by the true objective; last, sweeps that lower the spread of
   the edge lengths (the CV) with the objective's extremes held.
   Meshes of up to :data:`RELOCATE_MAX` points then try relocation moves
   (:func:`_relocate`): a point from where the edges are shortest to the middle
   of the longest edge, kept if the objective improves after a local
   re-relaxation; the one change of structure that point moves cannot make.
4. **Certification.**  The final points are triangulated afresh by
   :func:`uniform2d.insert` (exact CDT); the quality is compared with the paper's
   T+ on the objective and the better mesh is returned, with its certificates
   (when n is too small for T+, the optimised one).

With a size field (:func:`improve` ``size=``, used by the surface layer) every
length is measured against the local target size, so the same moves make a
graded mesh uniform in the field's metric.
"""

from __future__ import annotations

import logging
import math
import numbers
from typing import NamedTuple

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ._kernel import cdt, relax
from ._kernel.distance import to_segments
from .errors import InsufficientPointsError
from .insert import _grain, _normaliser, _size_grid, boundary_tol, insert, insert_on_edges
from .mesh import Mesh
from .polygon import Polygon
from .quality import edge_lengths

__all__ = ["optimize_mesh", "improve", "lattice_seed", "OBJECTIVES", "objective_value"]

log = logging.getLogger(__name__)

OBJECTIVES = ("balanced", "ratio", "max_edge", "max_perimeter")


# ----------------------------------------------------------------------------- sizes
def target_size(polygon: Polygon, n: int) -> float:
    """Side h of an equilateral mesh of P with |V| + n vertices.

    The inverse of :func:`uniform2d.uniform.steiner_count_for_size`."""
    A, B, H = polygon.area, polygon.perimeter, polygon.n_holes
    N = n + len(polygon.vertices)
    a = 4.0 * A / math.sqrt(3.0)
    c = 2.0 * N - 2.0 + 2.0 * H
    x = (-B + math.sqrt(B * B + 4.0 * a * c)) / (2.0 * a)  # x = 1/h
    return 1.0 / x


def _edge_geometry(polygon: Polygon):
    V = polygon.vertices
    E = polygon.edges
    a = V[E[:, 0]]
    d = V[E[:, 1]] - a
    L = np.hypot(d[:, 0], d[:, 1])
    return a, d, L


def _boundary_counts(L: np.ndarray, h: float, n: int) -> np.ndarray:
    """Pieces per polygon edge: round(L/h), at least 1, at most n extra points in total."""
    m = np.maximum(1, np.rint(L / h)).astype(np.int64)
    while (m - 1).sum() > n:
        e = int(np.argmin(np.where(m > 1, L / m, np.inf)))  # merge on the shortest pieces
        m[e] -= 1
    return m


def _boundary_points(a, d, m):
    pts, eid, t = [], [], []
    for e in range(len(m)):
        s = np.arange(1, m[e]) / m[e]
        pts.append(a[e] + d[e] * s[:, None])
        eid.append(np.full(len(s), e, dtype=np.int64))
        t.append(s)
    if not pts:
        return np.empty((0, 2)), np.empty(0, np.int64), np.empty(0)
    return np.concatenate(pts), np.concatenate(eid), np.concatenate(t)


# ----------------------------------------------------------------------------- seed
def _hex_lattice(polygon: Polygon, spacing: float, angle: float, origin) -> np.ndarray:
    xmin, ymin, xmax, ymax = polygon.bounds
    cx, cy = (xmin + xmax) / 2, (ymin + ymax) / 2
    R0 = math.hypot(xmax - xmin, ymax - ymin) / 2 + 2 * spacing
    R = R0 + math.hypot(origin[0] - cx, origin[1] - cy)
    dy = spacing * math.sqrt(3.0) / 2
    nr = int(math.ceil(R / dy)) + 1
    nc = int(math.ceil(R / spacing)) + 2
    j, i = np.meshgrid(np.arange(-nr, nr + 1), np.arange(-nc, nc + 1), indexing="ij")
    u = (i + 0.5 * (j & 1)) * spacing
    v = j * dy
    c, s = math.cos(angle), math.sin(angle)
    # lattice anchored at ``origin`` (a polygon vertex), rotated by ``angle``
    x = origin[0] + c * u - s * v
    y = origin[1] + s * u + c * v
    keep = (np.abs(x - cx) <= R0) & (np.abs(y - cy) <= R0)
    return np.stack([x[keep], y[keep]], axis=1)


def lattice_seed(polygon: Polygon, count: int, *, rows: bool = True) -> np.ndarray:
    """Exactly ``count`` points of a hexagonal lattice inside P, away from its boundary.

    With ``rows`` (default), the first layer is a fan at every corner of
    90 degrees or more that is not within 30 degrees of straight (points one
    edge length from the corner that split its angle into near-60-degree
    parts), then one point above the middle of every polygon edge, at the apex
    of the equilateral triangle on it (those crowding a point before them
    dropped): the boundary's own spacing, wherever it is.  The lattice, aligned with P's longest edge, fills the rest; its spacing is chosen
    so that the count comes out (the last few are dropped near the boundary or
    added in the largest gaps).  A structured start for :func:`improve`:
    relaxing a lattice ends far more uniform than relaxing scattered points.

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
    first = _boundary_rows(polygon, np.ones(len(polygon.edges), np.int64), h) if rows else None
    return _seed_interior(polygon, count, h, np.empty((0, 2)), None, first)


def _boundary_rows(polygon: Polygon, m: np.ndarray, h: float) -> np.ndarray:
    """One row of points along every polygon edge: above the middle of each of its
    m[e] pieces, at the apex of the equilateral triangle on it (inside P), after
    the corners' fans (:func:`_corner_fans`), keeping only those clear of the
    other edges and of the points before them (the fans win at corners)."""
    a, d, L = _edge_geometry(polygon)
    rows, gaps = _corner_fans(polygon, L / m, h)
    for e in range(len(L)):
        g = L[e] / m[e]
        nrm = np.array([-d[e, 1], d[e, 0]]) / L[e]  # left normal: into P on every ring
        s = (np.arange(m[e]) + 0.5) / m[e]
        rows.append(a[e] + d[e] * s[:, None] + nrm * g * math.sqrt(3) / 2)
        gaps.append(np.full(m[e], g))
    R, G = np.concatenate(rows), np.concatenate(gaps)
    shp = polygon.to_shapely()
    ok = shapely.contains_xy(shp, R[:, 0], R[:, 1])
    ok &= to_segments(R, a, a + d, 0.6 * G.max()) >= 0.6 * G
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


def _corner_fans(polygon: Polygon, piece: np.ndarray, h: float):
    """Points that split every polygon corner of angle theta into
    k = round(theta / 60 degrees) equal angles, one boundary piece away from the
    corner (at most :data:`FAN_CAP` h: a polygon edge left whole is no guide):
    the corner's fan of near-equilateral triangles.  Only for k = 2 and k >= 4:
    below 90 degrees there is nothing to split, and a vertex within 30 degrees
    of straight (k = 3) is split into three by the apexes of
    :func:`_boundary_rows` already (on the surface layer's domains, those are
    the vertices that are not corners).

    Returns lists of (1, 2) points and of their (1,) spacings."""
    E = polygon.edges
    V = polygon.vertices
    theta = polygon.interior_angles()
    _, d, L = _edge_geometry(polygon)
    e_in = np.empty(len(V), np.int64)
    e_in[E[:, 1]] = np.arange(len(E))
    out, gaps = [], []
    for e in range(len(E)):  # e leaves vertex v: the interior is on its left
        v = E[e, 0]
        k = int(math.floor(theta[v] / (math.pi / 3) + 0.5))
        if k < 2 or k == 3:  # k = 3: a near-straight vertex, the rows' apexes split it
            continue
        g = min(0.5 * (piece[e] + piece[e_in[v]]), FAN_CAP * h)
        u = d[e] / L[e]
        for j in range(1, k):
            phi = j * theta[v] / k
            c, s = math.cos(phi), math.sin(phi)
            out.append(V[v] + g * np.array([[c * u[0] - s * u[1], s * u[0] + c * u[1]]]))
            gaps.append(np.full(1, g))
    return out, gaps


def _seed_interior(
    polygon: Polygon, count: int, h: float, bpts: np.ndarray, edge: int | None = None,
    rows: np.ndarray | None = None,
) -> np.ndarray:
    """``count`` interior points on a hexagonal lattice aligned with polygon edge
    ``edge`` (default: the longest), deterministic.  With ``rows`` (from
    :func:`_boundary_rows`) those come first and the lattice fills the rest,
    clear of them."""
    if count <= 0:
        return np.empty((0, 2))
    if rows is not None and len(rows) < count:
        rtree = cKDTree(rows)
        band = h * math.sqrt(3) / 2
    else:
        rows = None
    a, d, L = _edge_geometry(polygon)
    e = int(np.argmax(L)) if edge is None else int(edge)
    angle = math.atan2(d[e, 1], d[e, 0])
    # anchor a lattice row at distance h·√3/2 inside the longest edge
    nrm = np.array([-d[e, 1], d[e, 0]]) / L[e]  # left normal: inside for the CCW outer ring
    origin = a[e] + nrm * h * math.sqrt(3) / 2 + d[e] / L[e] * (h / 2)
    shp = polygon.to_shapely()
    shapely.prepare(shp)
    sa, sd, _ = _edge_geometry(polygon)
    sb = sa + sd

    def cand(sp):
        P = _hex_lattice(polygon, sp, angle, origin)
        inside = shapely.contains_xy(shp, P[:, 0], P[:, 1])
        P = P[inside]
        # only distances below the cap matter, here and in the drop below
        cap = (2.0 * band + 2.0 * sp) if rows is not None else 2.0 * sp
        dist = to_segments(P, sa, sb, cap)
        ok = dist >= 0.5 * sp
        if rows is not None:  # rows lie within ~band of the boundary: test only near ones
            ok &= dist >= band + 0.5 * sp
            near = np.flatnonzero(ok & (dist < 2.0 * band + sp))
            ok[near] = rtree.query(P[near])[0] >= 0.75 * sp
        return P[ok], dist[ok]

    total = count
    if rows is not None:
        count = total - len(rows)

    lo, hi = 0.5 * h, 1.5 * h  # count(sp) decreases with sp
    best = None
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        P, dist = cand(mid)
        if best is None or abs(len(P) - count) < abs(len(best[0]) - count) or (
            abs(len(P) - count) == abs(len(best[0]) - count) and len(P) >= count
        ):
            best = (P, dist)
        if abs(len(P) - count) <= count // 500:  # close: the fix-up below is exact
            break
        if len(P) > count:
            lo = mid
        else:
            hi = mid
    P, dist = best
    if len(P) > count:  # drop the points nearest to the boundary
        if np.count_nonzero(dist < dist.max()) < len(P) - count:  # capped ones would go
            dist = to_segments(P, sa, sb, np.inf)
        order = np.lexsort((np.arange(len(P)), dist))
        P = P[np.sort(order[len(P) - count :])]
    if rows is not None:
        P = np.concatenate([rows, P])
        count = total
    while len(P) < count:  # add centroids of the largest triangles
        allp = np.concatenate([polygon.vertices, bpts, P])
        tri = _cdt(polygon, allp)
        q = allp[tri]
        area = 0.5 * np.abs(_cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]))
        need = count - len(P)
        order = np.lexsort((np.arange(len(tri)), -area))[:need]
        P = np.concatenate([P, q[order].mean(axis=1)])
    return P


# ----------------------------------------------------------------------------- triangulation
def _cdt(polygon: Polygon, points: np.ndarray) -> np.ndarray:
    """The exact constrained Delaunay triangulation of ``points`` (the polygon's
    vertices first, then boundary and interior points), CCW, restricted to P."""
    nV = len(polygon.vertices)
    return np.asarray(insert(polygon, 0, sites=points[nV:]).triangles)


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


# ----------------------------------------------------------------------------- objectives
def objective_value(objective: str, longest: float, shortest: float, perimeter: float, h: float):
    """Scalar the objective pass minimises (lower is better); h makes it scale-free."""
    if objective == "ratio":
        return longest / shortest
    if objective == "max_edge":
        return longest / h
    if objective == "max_perimeter":
        return perimeter / (3 * h)
    # balanced: geometric mean of the three
    return ((longest / shortest) * (longest / h) * (perimeter / (3 * h))) ** (1.0 / 3.0)


def _extremes(points, tri):
    """(longest edge, shortest edge, largest perimeter) of a triangle mesh."""
    q = points[tri]
    L = np.linalg.norm(q - q[:, [1, 2, 0]], axis=2)
    return L.max(), L.min(), L.sum(axis=1).max()


def _variants(polygon: Polygon, n: int):
    """The starts tried: (boundary spacing / h, lattice edge, boundary rows).

    Boundary counts, lattice orientation and the seed's first layer decide the
    mesh's structure, which the point moves cannot change, and the best choice
    depends on the polygon.  Small meshes (up to SMALL points) try the lattice
    aligned with the longest edge and with the longest one at another angle
    (modulo 60 degrees), each with every boundary spacing of :data:`SPACINGS`,
    with and without a row of points on every edge (:func:`_boundary_rows`);
    up to LARGE points the :data:`SPACINGS_MEDIUM` with rows; beyond, where a
    start costs most, one start.
    """
    _, d, L = _edge_geometry(polygon)
    first = int(np.argmax(L))
    if n + len(polygon.vertices) > LARGE:
        return [(1.0, first, LAYERED_LARGE)]
    ang = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
    off = np.abs((ang - ang[first] + 30.0) % 60.0 - 30.0)
    other = [e for e in np.lexsort((np.arange(len(L)), -L)) if off[e] > 5.0]
    edges = [first] + ([int(other[0])] if other else [])
    small = n + len(polygon.vertices) <= SMALL
    spacings, layers = (SPACINGS, LAYERED) if small else (SPACINGS_MEDIUM, LAYERED_MEDIUM)
    return [(c, e, lay) for lay in layers for e in edges for c in spacings]


def _quality_objective(objective, q, h):
    return objective_value(objective, q.longest_edge, q.shortest_edge, q.max_perimeter, h)


# ----------------------------------------------------------------------------- moving points
#: (spring rounds, descent sweeps per stage, stage exponents k with p = 2**k,
#: spread sweeps) for meshes up to LARGE points, and above it (where the work is
#: kept near linear).  Measured at n = 1000 on the benchmark polygons (geometric
#: means of longest edge / bound and largest perimeter / bound): p up to 64 gave
#: 1.162 / 1.101, up to 256 gives 1.142 / 1.075; starting the stages at p = 4
#: instead of 16 changed nothing.  Beyond 256 the gain is small (1.138 / 1.067 at
#: 1024) and the powers would overflow for edges off their target by 2x.
SCHEDULE = (60, 40, (4, 5, 6, 7, 8), 20)
SCHEDULE_LARGE = (30, 25, (4, 5), 5)
#: With a size field (the surface layer) the stages stop at p = 64: the higher
#: ones trade the bulk of the grading for the extremes (measured on cap60 at 600
#: and 2000 vertices: 3-D edge CV 0.060 / 0.056 against 0.066 / 0.059, size
#: trend -0.15 / -0.17 against -0.18 / -0.20), and the surface's targets are
#: about the spread (CV) more than the extremes.  Its stages are 25 sweeps long,
#: and its spread stage 30: against 40 and 20, the benchmark caps' 3-D edge CV
#: at 2000 vertices is 0.0746 / 0.0438 against 0.0732 / 0.0434 (cap60 / cap30),
#: for 45 fewer descent sweeps and 10 more spread sweeps (the planar step of a
#: cap's remesh measured 0.29 -> 0.21 s on cap30, 0.35 -> 0.30 s on cap60).
SCHEDULE_GRADED = (60, 25, (2, 3, 4, 5, 6), 30)
#: Point counts (|V| + n) above which fewer starts are tried (:func:`_variants`)
#: and SCHEDULE_LARGE is used.
LARGE = 20000
SMALL = 5000
#: Quality guard of the moves: a triangle whose doubled area is below
#: FLAT * target**2 may not get flatter (an equilateral one has 0.87 * target**2).
FLAT = 0.1
#: Boundary spacings (relative to h) tried for small meshes (see :func:`_variants`).
SPACINGS = (1.0, 0.95, 1.05)
SPACINGS_MEDIUM = (1.0, 1.05)
#: Seeds tried: the plain lattice (False) and boundary rows + lattice (True).
LAYERED = (False, True)
LAYERED_MEDIUM = (True,)
LAYERED_LARGE = True
#: The short schedule that ranks the starts (the best one then gets the full one).
TRIAL = {"spring_rounds": 40, "sweeps": 10, "exponents": (3, 5), "spread_sweeps": 0}
#: With ``"balanced"``, the short run ranks the starts by its objective value
#: times the edge CV to this power: the start fixes the mesh's structure, and
#: with it the CV the moves can reach (on a rectangle, a lattice aligned with a
#: short side meets the long sides along a row of 5-7 pairs), which the
#: extremes alone do not see.  Measured (geometric means over the benchmark
#: polygons; ratio / longest edge / bound / largest perimeter / bound / CV):
#: at n = 1000, 1.327 / 1.142 / 1.075 / 0.0501 with 0 against
#: 1.336 / 1.154 / 1.074 / 0.0457 with 0.5 (1.353 / 1.166 / 1.073 / 0.0455 with
#: 1); at n = 10000, 1.329 / 1.134 / 1.074 / 0.0286 against
#: 1.351 / 1.135 / 1.072 / 0.0257; at n = 200 the same starts win.
CV_WEIGHT = 0.5
#: Corner fan points sit at most FAN_CAP target sizes from their corner.
FAN_CAP = 1.5
#: Lattice seed points farther than BAND target sizes from the boundary stay put.
BAND = 8.0
#: Relocation moves (:func:`_relocate`), for meshes up to RELOCATE_MAX points:
#: tries, the radius (in target sizes) re-relaxed around a move, and its schedule.
#: A try costs a CDT of the whole mesh and moves one point, so it pays where one
#: point matters (measured at n = 200: largest perimeter / bound 1.185 -> 1.166 in
#: the geometric mean; at n = 1000, 1.123 -> 1.119 for 40 % more time).
RELOCATE_MAX = 1000
RELOCATE_TRIES = 15
RELOCATE_RADIUS = 4.0
RELOCATE = {"spring_rounds": 20, "sweeps": 20, "exponents": (3, 4, 5, 6), "spread_sweeps": 10}


def improve(
    polygon: Polygon,
    sites,
    *,
    size=None,
    objective: str = "balanced",
    href: float | None = None,
    frozen=None,
    spring_rounds: int | None = None,
    sweeps: int | None = None,
    exponents=None,
    spread_sweeps: int | None = None,
    edges=None,
):
    """Move the Steiner points of a mesh of P to make it more uniform, exactly n kept.

    The mesh is the constrained Delaunay triangulation of P with ``sites``; the
    polygon's vertices stay, sites on its boundary slide along their edges,
    interior sites move freely, and the triangulation is kept valid and
    constrained Delaunay throughout (exact predicates; see
    :mod:`uniform2d._kernel.relax`).  First spring rounds towards equal
    (size-normalised) edge lengths, then descent on the p-norm energy of
    ``objective`` for each exponent in ``exponents``, keeping the best state.

    Parameters
    ----------
    polygon : Polygon
    sites : array_like, shape (k, 2)
        Steiner points inside P or on its boundary.  Not modified.
    size : SizeField, optional
        Target sizes (relative: the overall scale follows the point count).
        None for a uniform mesh.
    objective : {"balanced", "ratio", "max_edge", "max_perimeter"}
    href : float, optional
        The uniform target edge length (default: from the point count, as
        :func:`target_size`); ignored with a ``size`` field.
    frozen : array_like of bool, shape (k,), optional
        Sites that must not move (e.g. the deep interior of a lattice that is
        already uniform: the work then scales with the boundary band).
    spring_rounds, sweeps : int, optional
        Iteration limits (spring rounds; descent sweeps per stage).
    exponents : sequence of int, optional
        Descent stage k minimises the p-norm energy with p = 2**k.  The four
        defaults come from :data:`SCHEDULE` (:data:`SCHEDULE_GRADED` with a
        ``size`` field, :data:`SCHEDULE_LARGE` above :data:`LARGE` points).
    spread_sweeps : int, optional
        Sweeps of the final stage that lowers the spread of the (normalised) edge
        lengths while the objective's extremes are held
        (:func:`uniform2d._kernel.relax.spread`).
    edges : array_like of int, shape (k,), optional
        The polygon edge each site lies on, -1 for an interior site (the
        optimiser's own sites: placed by index, not judged by distance).
        Default: found by distance, as :func:`uniform2d.insert` does.

    Returns
    -------
    points : ndarray, shape (|V| + k, 2)
        The polygon's vertices exactly, then the moved sites (same order).
    triangles : ndarray, shape (M, 3), int64
        The exact constrained Delaunay triangulation of ``points`` (CCW).
    info : dict
        Spring rounds and sweeps made, the objective value reached, and
        ``edges``: the polygon edge of each returned site (-1 inside).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.optimize import improve
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> pts, tri, info = improve(sq, [(0.3, 0.4), (0.5, 0.0), (0.6, 0.7)])
    >>> pts.shape, np.allclose(pts[5, 1], 0.0)   # the boundary site stayed on y = 0
    ((7, 2), True)
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    if objective not in OBJECTIVES:
        raise ValueError(f"objective must be one of {OBJECTIVES}, got {objective!r}")
    if edges is None:
        res = insert(polygon, 0, sites=sites)
    else:
        res = insert_on_edges(polygon, 0, np.asarray(sites, dtype=np.float64).reshape(-1, 2), edges)
    nV = len(polygon.vertices)
    if len(res.mesh_points) == nV:
        info = {"spring_rounds": 0, "sweeps": 0, "edges": np.empty(0, np.int64)}
        return np.array(res.mesh_points), np.array(res.triangles), info
    st = _load(polygon, res, size, href, frozen, edges)
    N = len(st.xy)
    sched = SCHEDULE_LARGE if N > LARGE else SCHEDULE if size is None else SCHEDULE_GRADED
    spring_rounds = sched[0] if spring_rounds is None else spring_rounds
    sweeps = sched[1] if sweeps is None else sweeps
    exponents = sched[2] if exponents is None else exponents
    spread_sweeps = sched[3] if spread_sweeps is None else spread_sweeps
    obj = OBJECTIVES.index(objective)
    m, xy, t = st.m, st.xy, st.t
    args = (m, st.role, st.eid, t, st.ea, st.ed, st.hv, st.href)

    rounds = relax.spring(*args, spring_rounds, 0.2, 1.02, 1e-4, 0.3, FLAT)
    done = 0
    value = None
    for k in exponents:
        best_xy = xy.copy()
        best_t = t.copy()
        best_tv = cdt.triangle_list(m).astype(np.int32).ravel()
        made, value = relax.descend(
            *args, obj, sweeps, int(k), 0.05, best_xy, best_t, best_tv, FLAT
        )
        done += made
        # continue from the best state of this stage
        xy[:] = best_xy
        t[:] = best_t
        cdt.build_adjacency(m, best_tv.reshape(-1, 3))
        cdt.legalize_all(m)

    if spread_sweeps:
        best_xy = xy.copy()
        best_t = t.copy()
        best_tv = cdt.triangle_list(m).astype(np.int32).ravel()
        relax.spread(*args, obj, spread_sweeps, 0.05, best_xy, best_t, best_tv, FLAT)
        xy[:] = best_xy
        t[:] = best_t

    fin = insert_on_edges(polygon, 0, _unload(polygon, st)[nV:], st.eid[nV:])
    info = {
        "spring_rounds": int(rounds),
        "sweeps": int(done),
        "objective_value": value,
        "edges": st.eid[nV:].copy(),
    }
    return np.array(fin.mesh_points), np.array(fin.triangles), info


class _Loaded(NamedTuple):
    """A mesh loaded into the kernel (normalised coordinates; see :func:`_load`)."""

    m: object  # cdt.Tri
    xy: np.ndarray  # (N, 2) its coordinate array
    role: np.ndarray  # (N,) int8 relax.FIXED / FREE / SLIDE
    eid: np.ndarray  # (N,) polygon edge of each SLIDE vertex
    t: np.ndarray  # (N,) its parameter on that edge
    ea: np.ndarray  # (E, 2) polygon edge starts, normalised
    ed: np.ndarray  # (E, 2) polygon edge vectors, normalised
    hv: np.ndarray  # (N,) size at each vertex (1 without a field)
    href: float  # target length (uniform) or field scale (graded), normalised
    centre: np.ndarray
    scale: float


def _load(polygon: Polygon, res, size, href, frozen, edges=None) -> _Loaded:
    """Load an :class:`~uniform2d.insert.InsertResult` (polygon + sites) into a Tri;
    ``edges`` as :func:`improve`'s (None: found by distance)."""
    from .insert import _classify_sites, edge_parameters

    nV = len(polygon.vertices)
    P0 = np.array(res.mesh_points, dtype=np.float64)
    T0 = np.array(res.triangles, dtype=np.int32)
    N = len(P0)
    if edges is None:
        _, boundary = _classify_sites(polygon, P0[nV:], boundary_tol(polygon))
    else:
        edges = np.asarray(edges, dtype=np.int64)
        on = np.flatnonzero(edges >= 0)
        tb = edge_parameters(polygon, P0[nV:], edges)
        boundary = [(int(i), int(edges[i]), float(tb[i])) for i in on]
    a, d, _ = _edge_geometry(polygon)
    centre, scale = _normaliser(polygon)

    role = np.full(N, relax.FREE, np.int8)
    role[:nV] = relax.FIXED
    eid = np.full(N, -1, np.int64)
    t = np.zeros(N)
    if frozen is not None:
        role[nV:][np.asarray(frozen, dtype=bool)] = relax.FIXED
    for i, e, ti in boundary:
        role[nV + i] = relax.SLIDE
        eid[nV + i] = e
        t[nV + i] = ti

    grid = _size_grid(size, centre, scale)
    m, xy = cdt.allocate(N, len(T0), grid, (centre, scale, _grain(polygon, centre) / scale))
    xy[:] = (P0 - centre) / scale
    cdt.set_nv(m, N)
    cdt.build_adjacency(m, T0)
    cdt.legalize_all(m)
    hv = np.ones(N)
    relax.refresh_sizes(m, hv, np.ones(N, np.bool_))
    if grid is not None:  # the field's shape, scaled to the edges present
        E = np.concatenate([T0[:, [0, 1]], T0[:, [1, 2]], T0[:, [2, 0]]])
        Ls = np.hypot(*(xy[E[:, 1]] - xy[E[:, 0]]).T)
        hs = 0.5 * (hv[E[:, 0]] + hv[E[:, 1]])
        href_n = float(np.sqrt((Ls**2).mean() / (hs**2).mean()))
    else:
        href_n = (target_size(polygon, N - nV) if href is None else href) / scale
    return _Loaded(m, xy, role, eid, t, (a - centre) / scale, d / scale, hv, href_n, centre, scale)


def _unload(polygon: Polygon, st: _Loaded) -> np.ndarray:
    """The kernel's points in the caller's coordinates, exactly: the kernel rounds
    every place to what these coordinates hold (:func:`uniform2d._kernel.cdt.snap`)."""
    out = st.xy * st.scale + st.centre
    out[: len(polygon.vertices)] = polygon.vertices
    return out


def _relocate(polygon: Polygon, pts, tri, frozen, objective: str, h: float, options, edges):
    """Relocation moves: the one change of structure point moves cannot make.

    Each try takes the interior point whose edges are shortest on average (away
    from the target) and moves it to the midpoint of the longest edge, then
    re-relaxes the points within :data:`RELOCATE_RADIUS` sizes of either place
    (:data:`RELOCATE` schedule); the move is kept if the objective improves.  A
    failed edge is not tried again until a move succeeds; at most
    :data:`RELOCATE_TRIES` tries.  The count of points never changes.
    ``edges`` (as :func:`improve`'s) says which sites are on the boundary.

    Returns (points, triangles, moves kept).
    """
    nV = len(polygon.vertices)
    value = objective_value(objective, *_extremes(pts, tri), h)
    fixed = np.asarray(frozen, dtype=bool).copy()
    failed = set()
    kept = 0
    for _ in range(RELOCATE_TRIES):
        E, L = edge_lengths(pts, tri)
        target = next((E[j] for j in np.lexsort((np.arange(len(L)), -L)) if tuple(E[j]) not in failed), None)
        if target is None:
            break
        failed.add(tuple(target))
        new = 0.5 * (pts[target[0]] + pts[target[1]])  # on P's boundary if the edge is
        new_edge = _common_edge(polygon, edges, *target)
        total = np.zeros(len(pts))
        count = np.zeros(len(pts))
        np.add.at(total, E.ravel(), np.repeat(L, 2))
        np.add.at(count, E.ravel(), 1.0)
        sites = pts[nV:]
        free = (edges < 0) & ~fixed
        free &= np.hypot(*(sites - new).T) > RELOCATE_RADIUS * h
        if not free.any():
            break
        mean = np.where(free, total[nV:] / np.maximum(count[nV:], 1.0), np.inf)
        r = int(np.argmin(mean))
        old = sites[r].copy()
        trial = sites.copy()
        trial[r] = new
        trial_edges = edges.copy()
        trial_edges[r] = new_edge
        near = np.minimum(np.hypot(*(trial - new).T), np.hypot(*(trial - old).T))
        local = fixed | (near > RELOCATE_RADIUS * h)
        p2, t2, info2 = improve(
            polygon, trial, objective=objective, href=h, frozen=local, edges=trial_edges,
            **{**options, **RELOCATE},
        )
        v2 = objective_value(objective, *_extremes(p2, t2), h)
        if v2 < value:
            pts, tri, value, edges = p2, t2, v2, info2["edges"]
            kept += 1
            failed.clear()
    return pts, tri, kept


def _common_edge(polygon: Polygon, edges, u: int, v: int) -> int:
    """The polygon edge both mesh points u and v lie on, or -1: the polygon edge
    of the midpoint of mesh edge u-v (a mesh edge joining two points of one polygon
    edge runs along it).  ``edges`` as :func:`improve`'s, for the points after
    the polygon's vertices (a vertex lies on the two edges that meet there)."""
    nV = len(polygon.vertices)
    E = polygon.edges

    def on(w):
        if w >= nV:
            return {int(edges[w - nV])} - {-1}
        return {int(e) for e in np.flatnonzero((E[:, 0] == w) | (E[:, 1] == w))}

    both = on(int(u)) & on(int(v))
    return min(both) if both else -1


# ----------------------------------------------------------------------------- driver
def optimize_mesh(
    polygon: Polygon,
    n: int,
    *,
    objective: str = "balanced",
    start: Mesh | None = None,
    **options,
) -> Mesh:
    """The most uniform mesh with exactly ``n`` Steiner points (see module docstring).

    ``start`` is the T+ mesh to beat (computed if not given); ``options`` go to
    :func:`improve`.  If n is too small for T+ (:func:`uniform2d.tplus` raises
    :class:`~uniform2d.errors.InsufficientPointsError`), there is nothing to
    compare with: the optimised mesh is returned with ``info["start"]`` None, and
    d_n for its certificates comes from :func:`uniform2d.insert`.
    """
    from .quality import quality
    from .tplus import tplus

    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InsufficientPointsError(f"n must be a positive integer, got {n!r}")
    if objective not in OBJECTIVES:
        raise ValueError(f"objective must be one of {OBJECTIVES}, got {objective!r}")
    n = int(n)
    nV = len(polygon.vertices)

    tp = start
    if tp is None:
        try:
            tp = tplus(polygon, n)
        except InsufficientPointsError as exc:  # too few points for T+, not for this method
            log.info("uniform: no T+ to compare with (%s)", exc)
    if tp is not None:
        d_n = tp.info.get("d_n")
        q_tp = tp.quality(d_n=d_n if d_n is not None else False)
    else:  # d_n for the certificates comes from INSERT alone
        d_n = insert(polygon, n).min_distance()
        q_tp = None

    h = target_size(polygon, n)
    a, d, L = _edge_geometry(polygon)
    variants = _variants(polygon, n)
    best = None
    for spacing, edge, layered in variants:
        m = _boundary_counts(L, spacing * h, n)
        bpts, beid, _ = _boundary_points(a, d, m)
        rows = _boundary_rows(polygon, m, spacing * h) if layered else None
        ipts = _seed_interior(polygon, n - len(bpts), h, bpts, edge, rows)
        # the lattice deeper than BAND sizes inside P is uniform already: it stays
        deep = to_segments(ipts, a, a + d, 2.0 * BAND * h) > BAND * h
        frozen = np.concatenate([np.zeros(len(bpts), bool), deep])
        sites = np.concatenate([bpts, ipts])
        edges = np.concatenate([beid, np.full(len(ipts), -1, np.int64)])
        val = 0.0
        if len(variants) > 1:  # a short trial run ranks the starts
            trial = {**options, **TRIAL}
            pts, tri, tinfo = improve(
                polygon, sites, objective=objective, href=h, frozen=frozen, edges=edges, **trial
            )
            sites, edges = pts[nV:], tinfo["edges"]
            val = objective_value(objective, *_extremes(pts, tri), h)
            if objective == "balanced" and CV_WEIGHT:
                _, Ls = edge_lengths(pts, tri)
                val *= (Ls.std() / Ls.mean()) ** CV_WEIGHT
        if best is None or val < best[0]:
            best = (val, sites, edges, frozen, len(bpts), spacing, edge, layered)
    _, sites, edges, frozen, k, spacing, edge, layered = best
    pts, tri, run = improve(
        polygon, sites, objective=objective, href=h, frozen=frozen, edges=edges, **options
    )
    moved = 0
    if n + nV <= RELOCATE_MAX:
        pts, tri, moved = _relocate(
            polygon, pts, tri, frozen, objective, h, options, run["edges"]
        )
    q_new = quality(pts, tri, polygon, n_steiner=n, d_n=d_n if d_n is not None else False)
    v_new = _quality_objective(objective, q_new, h)
    v_tp = _quality_objective(objective, q_tp, h) if q_tp is not None else math.inf

    def summary(q):
        if q is None:
            return None
        return {
            "edge_ratio": q.edge_ratio,
            "longest_edge": q.longest_edge,
            "max_perimeter": q.max_perimeter,
            "cv_edge": q.cv_edge,
            "min_angle": q.min_angle,
        }

    info = {
        "method": "uniform",
        "objective": objective,
        "d_n": d_n,
        "h": h,
        "k": int(k),
        "boundary_spacing": spacing,
        "lattice_edge": edge,
        "boundary_rows": layered,
        "relax_iterations": run["spring_rounds"],
        "sweeps": run["sweeps"],
        "relocated": moved,
        "start": (
            None
            if tp is None
            else {"method": tp.info.get("method"), **summary(q_tp), "objective": v_tp}
        ),
        "before": summary(q_tp),
        "after": summary(q_new),
        "objective_value": v_new,
    }
    if not (v_new <= v_tp) or len(pts) != nV + n:  # v_tp is inf without a T+
        if tp is None:
            raise RuntimeError(f"uniform: {len(pts) - nV} Steiner points instead of {n} (a bug)")
        info["fallback"] = "tplus"
        info["after"] = summary(q_tp)
        info["objective_value"] = v_tp
        log.info("uniform: optimised mesh (%g) not better than T+ (%g); returning T+", v_new, v_tp)
        return Mesh(np.array(tp.points), np.array(tp.triangles), polygon, n, {**tp.info, **info})
    info["fallback"] = None
    return Mesh(pts, tri, polygon, n, info)
