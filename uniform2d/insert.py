"""Algorithm INSERT (canonical Voronoi insertion) of Aurenhammer et al.

Step j inserts the point p_j of the closed polygon P farthest from the current
sites -- farthest in *visible* distance, the distance to the nearest site seen
from the point inside P (plain Euclidean distance for a convex P).  The sites
start as the polygon vertices V (and any extra ``sites``).

Contract (design notes §2): p_j is a global maximiser within a relative 1e-9;
``weights[j]`` = w_{j-1}(p_j) is its visible distance; the weights never
increase; the same input gives bit-identical output.  Ties (weights within a
relative 1e-9 of the best) go to the lexicographically smallest (x, y), with x
compared to within 1e-9 of the bounding-box size, so the sequence is canonical
and invariant under scaling and translation.  See ``uniform2d._kernel.insert``
for how the tied group is found in O(log n) a step.  The kernel works on coordinates
normalised exactly (see ``_normaliser``); the polygon vertices and sites are
returned exactly as given, the inserted points mapped back exactly: each was
rounded to what the caller's coordinates hold before it was inserted, so the
returned mesh is exactly the constrained Delaunay triangulation the exact
predicates built.  Far from the origin that rounding (a few units in the last
place of the coordinates) is also the precision of the points and weights.

Sites: :func:`insert` decides by distance which are on the boundary (the
caller's sites); :func:`insert_on_edges` takes the edge of each site from its
caller (the library's own sites), so no tolerance judges them.  Either way a
boundary site splits its edge's constraint in order along it, and every mesh
passes :func:`ensure_valid` before it is returned.
"""

from __future__ import annotations

import logging
import numbers
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ._kernel import cavity, cdt, heap, polytri
from ._kernel import insert as kinsert
from ._kernel.distance import to_segments
from ._kernel.validity import mesh_problem
from .errors import (
    CoordinatePrecisionError,
    InsufficientPointsError,
    InternalError,
    InvalidSitesError,
)
from .polygon import Polygon
from .sizefield import SizeField

__all__ = ["insert", "InsertResult"]

log = logging.getLogger(__name__)

#: A site closer than this (relative to the polygon size) to the boundary is on it.
BOUNDARY_TOL = 1e-10
#: A chosen point closer than this (relative) to the boundary is placed on it.
SNAP = 1e-12


@dataclass(frozen=True, eq=False)
class InsertResult:
    """Result of :func:`insert`.

    Attributes
    ----------
    points : ndarray, shape (n, 2)
        Inserted points p_1..p_n, in insertion order.
    weights : ndarray, shape (n,)
        ``weights[j]`` = w_{j-1}(p_j), the visible distance of p_j to the sites
        present before it was inserted.  Non-increasing.
    on_boundary : ndarray, shape (n,), bool
        Whether p_j was placed on the polygon boundary.
    mesh_points : ndarray, shape (N, 2)
        All vertices of the final triangulation: the polygon vertices (exactly as
        ``polygon.vertices``), then the extra ``sites``, then ``points``.
    triangles : ndarray, shape (M, 3), int64
        The constrained Delaunay triangulation of ``mesh_points`` restricted to P,
        counter-clockwise.
    polygon : Polygon
    sites : ndarray, shape (k, 2)
        The extra initial sites (empty if none were given).
    """

    points: np.ndarray
    weights: np.ndarray
    on_boundary: np.ndarray
    mesh_points: np.ndarray
    triangles: np.ndarray
    polygon: Polygon
    sites: np.ndarray

    def min_distance(self) -> float:
        """d = l(S ∪ V, S ∪ V): the smallest distance between two vertices of the mesh."""
        d, _ = cKDTree(self.mesh_points).query(self.mesh_points, k=2)
        return float(d[:, 1].min())


def _normaliser(polygon: Polygon):
    """(centre, scale) with x_norm = (x - centre) / scale, exact both ways.

    ``scale`` is the power of two nearest max(width, height), so dividing by it
    and multiplying back are exact.  A coordinate whose bounding-box centre is
    within 2 sizes of the origin is not translated; one farther away is
    translated by its centre rounded to a multiple of 2**-20 scale.  Then
    X - centre is exact for every float X in the polygon's box (Sterbenz: X and
    centre are within a factor 2 of each other), so the kernel works on an exact
    image of the caller's coordinates, and new points rounded to what those
    coordinates can hold (:func:`cdt.snap`) map back exactly: the mesh the
    predicates certified is the one the caller gets.
    """
    xmin, ymin, xmax, ymax = polygon.bounds
    size = max(xmax - xmin, ymax - ymin)
    scale = 2.0 ** round(np.log2(size))
    centre = np.array([(xmin + xmax) / 2.0, (ymin + ymax) / 2.0])
    q = scale * 2.0**-20
    return np.where(np.abs(centre) <= 2.0 * size, 0.0, np.round(centre / q) * q), scale


def _grain(polygon: Polygon, centre) -> float:
    """How far rounding a new point to the caller's coordinates (:func:`cdt.snap`)
    can move a distance: a few units in the last place of the translated
    coordinates, 0 where nothing is translated (there the rounding is exact)."""
    if not centre.any():
        return 0.0
    return 4.0 * float(np.spacing(np.abs(centre).max() + _extent(polygon)))


def _extent(polygon: Polygon) -> float:
    """The larger side of P's bounding box."""
    xmin, ymin, xmax, ymax = polygon.bounds
    return max(xmax - xmin, ymax - ymin)


def _rounding(polygon: Polygon) -> float:
    """How far rounding alone can move a point computed near P's coordinates (a
    few units in their last place): far from the origin that exceeds the
    relative tolerances below."""
    return 8 * np.finfo(float).eps * float(np.abs(polygon.vertices).max())


def boundary_tol(polygon: Polygon) -> float:
    """Distance within which a site counts as on P's boundary.

    :data:`BOUNDARY_TOL` of the polygon's size, or more where its coordinates are
    so large for its size (far from the origin) that rounding alone moves a point
    computed on an edge, ``a + t (b - a)``, that far off it.
    """
    return max(BOUNDARY_TOL * _extent(polygon), _rounding(polygon))


def ensure_valid(points, triangles, polygon: Polygon, n_steiner: int, what: str) -> None:
    """Raise :class:`~uniform2d.errors.InternalError` unless the mesh is a valid
    triangulation of P with exactly ``n_steiner`` Steiner points (the checks of
    :mod:`uniform2d._kernel.validity`; cheap enough to run on every mesh returned)."""
    problem = mesh_problem(points, triangles, polygon, n_steiner, boundary_tol(polygon))
    if problem is not None:
        raise InternalError(
            f"{what} made an invalid mesh ({problem}). This is a bug in uniform2d, not a "
            f"problem with the input: please report it with the polygon "
            f"({len(polygon.vertices)} vertices, {polygon.n_holes} holes) and n = {n_steiner}"
        )


def _classify_sites(polygon: Polygon, sites: np.ndarray, tol: float):
    """Split sites into interior ones and boundary ones (edge index, parameter).

    Vectorised: one compiled point-to-edges distance and one GEOS point-in-polygon
    query per site; only the few sites within ``tol`` of the boundary are matched
    to their edge.
    """
    if len(sites) == 0:
        return [], []
    V = polygon.vertices
    edges = polygon.edges
    a = V[edges[:, 0]]
    d = V[edges[:, 1]] - a
    # only "within tol or not" is asked: distances beyond 2 tol come back as 2 tol
    cap = 2.0 * tol if tol > 0 else np.inf
    dist = to_segments(np.ascontiguousarray(sites, dtype=np.float64), a, V[edges[:, 1]], cap)
    near = np.flatnonzero(dist <= tol)
    inside = shapely.contains_xy(polygon.to_shapely(), sites[:, 0], sites[:, 1])
    outside = np.flatnonzero((dist > tol) & ~inside)
    if len(outside):
        i = int(outside[0])
        raise InvalidSitesError(
            f"site {i} {tuple(sites[i])} lies outside the polygon; sites must be inside P "
            "or on its boundary"
        )
    L2 = (d * d).sum(axis=1)
    boundary = []
    for i in near:
        s = sites[i]
        rel = s - a
        t = np.clip((rel * d).sum(axis=1) / L2, 0.0, 1.0)
        e = int(np.argmin(np.hypot(*(rel - t[:, None] * d).T)))
        if t[e] * np.sqrt(L2[e]) <= tol or (1 - t[e]) * np.sqrt(L2[e]) <= tol:
            k = edges[e, 0] if t[e] < 0.5 else edges[e, 1]
            raise InvalidSitesError(
                f"site {int(i)} {tuple(s)} coincides with polygon vertex {int(k)}; "
                "polygon vertices are sites already, remove it"
            )
        boundary.append((int(i), e, float(t[e])))
    near_set = np.zeros(len(sites), bool)
    near_set[near] = True
    interior = np.flatnonzero(~near_set).tolist()
    return interior, boundary


def _check_sites(polygon: Polygon, sites) -> np.ndarray:
    if sites is None:
        return np.empty((0, 2), np.float64)
    try:
        s = np.array(sites, dtype=np.float64).reshape(-1, 2)
    except (TypeError, ValueError):
        raise InvalidSitesError("sites must be a (k, 2) array of coordinates") from None
    if not np.isfinite(s).all():
        i = int(np.flatnonzero(~np.isfinite(s).all(axis=1))[0])
        raise InvalidSitesError(f"site {i} has a non-finite coordinate {s[i].tolist()}")
    _, first, counts = np.unique(s, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        i = int(first[np.flatnonzero(counts > 1)[0]])
        raise InvalidSitesError(f"site {i} {tuple(s[i])} is given more than once")
    return s


def insert(polygon: Polygon, n: int, *, sites=None, size=None) -> InsertResult:
    """Run Algorithm INSERT: place ``n`` points, each farthest from all sites before it.

    Parameters
    ----------
    polygon : Polygon
        The domain P (holes allowed).
    n : int
        Number of points to insert, n >= 0.
    sites : array_like, shape (k, 2), optional
        Extra initial sites inside P or on its boundary (besides the polygon
        vertices), e.g. prescribed boundary points (T+ uses this).
    size : SizeField or float, optional
        A target-size field h: candidates are ranked by visible distance / h, so
        points are denser where h is small (the surface layer uses this).  A number,
        or a constant field, changes no comparison: the paper's algorithm exactly.
        ``weights`` stay visible distances.

    Returns
    -------
    InsertResult

    Raises
    ------
    InsufficientPointsError
        If n is negative or not an integer.
    InvalidSitesError
        If a site is outside P, repeated, non-finite or equal to a polygon vertex.

    Examples
    --------
    >>> from uniform2d import Polygon, insert
    >>> res = insert(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), 3)
    >>> res.points.round(6).tolist()
    [[0.5, 0.5], [0.0, 0.5], [0.5, 0.0]]
    >>> res.weights.round(6).tolist()
    [0.707107, 0.5, 0.5]
    >>> res.triangles.shape        # 7 vertices, 6 of them on the boundary
    (6, 3)
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 0:
        raise InsufficientPointsError(f"n must be a non-negative integer, got {n!r}")
    sites = _check_sites(polygon, sites)
    _, boundary = _classify_sites(polygon, sites, boundary_tol(polygon))
    edges = np.full(len(sites), -1, np.int64)
    for i, e, _t in boundary:
        edges[i] = e
    return insert_on_edges(polygon, int(n), sites, edges, size)


def edge_parameters(polygon: Polygon, sites: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Parameter t in [0, 1] of each site's projection on its polygon edge (0 for
    interior sites, ``edges`` -1)."""
    t = np.zeros(len(sites))
    on = np.flatnonzero(edges >= 0)
    if len(on):
        V, E = polygon.vertices, polygon.edges[edges[on]]
        a = V[E[:, 0]]
        d = V[E[:, 1]] - a
        t[on] = np.clip(((sites[on] - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
    return t


def insert_on_edges(polygon: Polygon, n: int, sites: np.ndarray, edges: np.ndarray, size=None):
    """:func:`insert` for sites whose place is known by construction.

    ``edges[i]`` is the polygon edge site i lies on, or -1 for an interior site.
    Nothing is classified by distance, so no tolerance can misjudge a site: the
    library's own callers (T+'s boundary points, the optimiser's sliding points)
    come here, and a site near a polygon vertex is simply a boundary site.  A
    site that cannot be placed where it says it is raises ``RuntimeError``.
    Every mesh made here passes :func:`ensure_valid` before it is returned.
    """
    centre, scale = _normaliser(polygon)
    extent = _extent(polygon)
    sites = np.asarray(sites, dtype=np.float64).reshape(-1, 2)
    edges = np.asarray(edges, dtype=np.int64)
    V = polygon.vertices
    nV = len(V)
    interior = np.flatnonzero(edges < 0)
    n_int = len(interior)
    rings, chains = _rings_with_sites(polygon, sites, edges)
    allxy = np.concatenate([(V - centre) / scale, (sites - centre) / scale], axis=0)
    nmax = nV + len(sites) + n
    nb0 = sum(len(r) for r in rings)
    t0 = nb0 + 2 * (len(rings) - 1) - 2  # triangles of a triangulated polygon with holes
    tmax = t0 + 2 * (n_int + n) + 4
    grid = _size_grid(size, centre, scale)
    grain = _grain(polygon, centre)
    m, xy = _initial(allxy, rings, chains, nV, nmax, tmax, grid, (centre, scale, grain / scale))

    if n_int:
        idx = nV + interior
        idx = idx[hilbert_order(allxy[idx])]
        status = cavity.insert_sites(m, idx)
        if status < 0:
            raise RuntimeError(f"could not insert site {int(idx[-status - 1]) - nV}")

    # points nearer the boundary than this go on it: SNAP of the size, or more if
    # the caller's coordinates are too coarse there to hold a point nearer
    snap = max(SNAP * extent, _rounding(polygon))
    M = heap.new_heap(tmax + tmax // 2 + 64)  # ~1.9 n entries live; grows if needed
    kinsert.push_initial(m, M)
    P = kinsert.new_pool(64)
    out_xy = np.empty((n, 2), np.float64)
    out_w = np.empty(n, np.float64)
    out_b = np.zeros(n, np.bool_)
    xtol = (kinsert.REL_TIE * extent + grain) / scale
    status = kinsert.run(m, M, P, n, out_xy, out_w, out_b, xtol, snap / scale)
    if status != n:
        j = -status // 100
        if status + 100 * j == kinsert.ERR_PRECISION:
            raise CoordinatePrecisionError(
                f"the polygon is {extent:.3g} across at {float(np.abs(V).max()):.3g} from the "
                f"origin, where coordinates are {np.spacing(np.abs(V).max()):.3g} apart: too "
                f"coarse to place point {j + 1} of {n}; translate the polygon nearer the origin "
                "(e.g. subtract its centre) or ask for fewer points"
            )
        raise RuntimeError(
            f"INSERT kernel failed (status {status}) at step {j}, point {tuple(out_xy[j])}, "
            f"weight {out_w[j]!r}, on boundary {bool(out_b[j])}"
        )

    del M, P  # the queues are done: release them before the outputs are built
    # exact: the kernel rounded every point to what these coordinates hold (cdt.snap)
    points = out_xy * scale + centre
    weights = out_w * scale
    mesh_points = np.concatenate([V, sites, points], axis=0)
    triangles = cdt.triangle_list(m)
    del m, xy
    ensure_valid(mesh_points, triangles, polygon, len(mesh_points) - nV, "insert")
    for arr in (points, weights, out_b, mesh_points, triangles):
        arr.setflags(write=False)
    return InsertResult(points, weights, out_b, mesh_points, triangles, polygon, sites)


def _rings_with_sites(polygon: Polygon, sites: np.ndarray, edges: np.ndarray):
    """The rings with the boundary sites spliced in (kernel vertex indices), and the
    chains of sites per polygon edge: (start vertex, [sites in order along it])."""
    nV = len(polygon.vertices)
    t = edge_parameters(polygon, sites, edges)
    by_edge: dict[int, list[int]] = {}
    for i in np.lexsort((np.arange(len(sites)), t)):
        if edges[i] >= 0:
            by_edge.setdefault(int(edges[i]), []).append(nV + int(i))
    rings, chains = [], []
    for r in range(len(polygon.rings)):
        lo, hi = polygon.ring_offsets[r], polygon.ring_offsets[r + 1]
        ring = []
        for e in range(lo, hi):
            ring.append(e)  # edge e starts at vertex e (Polygon.edges layout)
            ring.extend(by_edge.get(e, []))
            if e in by_edge:
                chains.append((e, by_edge[e]))
        rings.append(ring)
    return rings, chains


def _initial(allxy, rings, chains, nV, nmax, tmax, grid, normal):
    """The triangulation of the rings (boundary sites included), exactly CDT.

    GEOS triangulates the rings; its result is used only if it passes the exact
    check (every triangle strictly counter-clockwise, twins opposite, the
    boundary exactly the rings' edges).  GEOS decides in floating point: on
    collinear vertices, or a site rounded a few ulps off a rotated edge (which
    makes the ring locally reflex), it may cut a flat or inverted ear.  Then the
    polygon's own rings are triangulated exactly (:mod:`._kernel.polytri`) and
    each boundary site splits its edge's constraint by index
    (:func:`._kernel.cavity.split_sites`).
    """
    m, xy = cdt.allocate(nmax, tmax, grid, normal)
    xy[: len(allxy)] = allxy
    cdt.set_nv(m, len(allxy))
    if not _load_triangles(m, allxy, rings):
        log.debug("insert: GEOS's triangulation failed the exact check; exact fallback")
        m, xy = cdt.allocate(nmax, tmax, grid, normal)
        xy[: len(allxy)] = allxy
        cdt.set_nv(m, len(allxy))
        own = [[v for v in r if v < nV] for r in rings]
        tris = polytri.triangulate(allxy[:nV], own)
        if cdt.build_adjacency(m, tris) != nV or not _valid(m, allxy, own):
            raise RuntimeError("could not triangulate the polygon exactly (please report it)")
        if chains:
            idx = np.array([v for _, c in chains for v in c], dtype=np.int64)
            first = np.array([([e] + c)[j] for e, c in chains for j in range(len(c))], np.int64)
            status = cavity.split_sites(m, idx, first)
            if status < 0:
                k = int(idx[-status - 1]) - nV
                raise RuntimeError(f"could not put boundary site {k} on its edge")
    cdt.legalize_all(m)
    return m, xy


def _load_triangles(m, allxy, rings) -> bool:
    """Load GEOS's triangulation of ``rings``; whether it is valid (exact check)."""
    try:
        tris = _initial_triangles(allxy, rings)
    except (RuntimeError, shapely.errors.GEOSException):
        return False
    nb0 = sum(len(r) for r in rings)
    if len(tris) != nb0 + 2 * (len(rings) - 1) - 2:
        return False
    if cdt.build_adjacency(m, tris) != nb0:
        return False
    return _valid(m, allxy, rings)


def _valid(m, allxy, rings) -> bool:
    ring_next = np.full(len(allxy), -1, np.int64)
    for r in rings:
        ring_next[np.asarray(r)] = np.roll(np.asarray(r), -1)
    return cdt.count_not_ccw(m) == 0 and cdt.boundary_is(m, ring_next)


def _size_grid(size, centre, scale):
    """The size field in the kernel's coordinates, or None for a constant one."""
    if size is None or isinstance(size, numbers.Real):
        if size is not None and not (np.isfinite(size) and size > 0):
            raise ValueError(f"size must be a positive number or a SizeField, got {size!r}")
        return None
    if not isinstance(size, SizeField):
        raise TypeError(f"size must be a SizeField or a number, got {type(size).__name__}")
    if np.all(size.values == size.values.flat[0]):
        return None
    return ((size.x - centre[0]) / scale, (size.y - centre[1]) / scale, size.values / scale)


def hilbert_order(points: np.ndarray, bits: int = 16) -> np.ndarray:
    """Indices sorting points (K, 2) along a Hilbert curve over their bounding box."""
    lo = points.min(axis=0)
    span = max(float((points.max(axis=0) - lo).max()), 1e-300)
    side = 1 << bits
    q = np.minimum(((points - lo) / span * (side - 1)).astype(np.int64), side - 1)
    x, y = q[:, 0].copy(), q[:, 1].copy()
    d = np.zeros(len(points), np.int64)
    s = side >> 1
    while s > 0:
        rx = (x & s) > 0
        ry = (y & s) > 0
        d += s * s * ((3 * rx) ^ ry)
        # rotate the quadrant
        flip = ~ry
        swap_x = np.where(flip & rx, s - 1 - x, x)
        swap_y = np.where(flip & rx, s - 1 - y, y)
        x, y = np.where(flip, swap_y, swap_x), np.where(flip, swap_x, swap_y)
        s >>= 1
    return np.argsort(d, kind="stable")


def _complex_key(p: np.ndarray) -> np.ndarray:
    """(K,) complex128 holding the points (K, 2) bit for bit (no arithmetic)."""
    out = np.empty(len(p), dtype=np.complex128)
    out.real = p[:, 0]
    out.imag = p[:, 1]
    return out


def _initial_triangles(xy: np.ndarray, rings: list[list[int]]) -> np.ndarray:
    """Constrained Delaunay triangles of the rings (GEOS), as CCW vertex indices.

    GEOS returns the input coordinates unchanged, so vertices are matched exactly.
    Its in-circle decisions are not exact; :func:`cdt.legalize_all` fixes that.
    """
    shell = xy[rings[0]]
    holes = [xy[r] for r in rings[1:]]
    geom = shapely.constrained_delaunay_triangles(shapely.Polygon(shell, holes))
    rings_ = shapely.get_exterior_ring(shapely.get_parts(geom))
    corners = shapely.get_coordinates(rings_).reshape(len(rings_), 4, 2)[:, :3]
    # exact matching on (x, y) through a complex key (ordered by x, then y)
    idx = np.concatenate([np.asarray(r, dtype=np.int64) for r in rings])
    key = _complex_key(xy[idx])
    order = np.argsort(key, kind="stable")
    want = _complex_key(corners.reshape(-1, 2))
    pos = np.minimum(np.searchsorted(key[order], want), len(key) - 1)
    if not np.array_equal(key[order][pos], want):
        raise RuntimeError("GEOS returned a vertex that is not a polygon vertex")
    tris = idx[order[pos]].astype(np.int32).reshape(-1, 3)
    p = xy[tris]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (
        p[:, 1, 1] - p[:, 0, 1]
    ) * (p[:, 2, 0] - p[:, 0, 0])
    flip = cross < 0
    tris[flip] = tris[flip][:, ::-1]
    return np.ascontiguousarray(tris)
