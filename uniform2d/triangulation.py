"""Loading a polygon and its sites into the kernel's constrained Delaunay triangulation.

The service INSERT, the optimiser and the surface layer share: sites checked
and sorted into interior and boundary ones (or, for the library's own sites,
placed on their edge by index), coordinates normalised exactly for the kernel,
and the rings triangulated and made exactly Delaunay.  :func:`ensure_valid` is
the cheap exact check every mesh passes before the library returns it.

:func:`triangulate` is the exact CDT of P and some points; :func:`load` leaves
it in the kernel for INSERT to continue; :func:`load_mesh` loads a mesh that is
triangulated already (the optimiser moves its points).
"""

from __future__ import annotations

import logging
import numbers
from dataclasses import dataclass

import numpy as np
import shapely

from ._kernel import cavity, cdt, polytri
from ._kernel._jit import njit
from ._kernel.distance import to_segments
from ._kernel.outcomes import failed_site
from ._kernel.validity import mesh_problem
from .errors import (
    PLEASE_REPORT, ArgumentTypeError, InternalError, InvalidArgumentError, InvalidSitesError)
from .polygon import Polygon
from .segment_chains import piece_chains, piece_pairs, rebuild
from .sizefield import SizeField

__all__ = [
    "triangulate", "load", "unload", "load_mesh", "Loaded", "site_edges", "edge_parameters",
    "ensure_valid", "boundary_tol", "hilbert_order",
]

log = logging.getLogger(__name__)

#: A site closer than this (relative to the polygon size) to the boundary is on it.
BOUNDARY_TOL = 1e-10


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
    """Split sites into interior ones and constrained ones (edge index into
    ``polygon.constraint_edges``: a ring edge, or a segment piece after them,
    and parameter).

    Vectorised: one compiled point-to-edges distance and one GEOS point-in-polygon
    query per site; only the few sites within ``tol`` of the boundary are matched
    to their edge.
    """
    if len(sites) == 0:
        return [], []
    V = polygon.vertices
    edges = polygon.constraint_edges
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


def _size_grid(size, centre, scale):
    """The size field in the kernel's coordinates, or None for a constant one."""
    if size is None or isinstance(size, numbers.Real):
        if size is not None and not (np.isfinite(size) and size > 0):
            raise InvalidArgumentError(f"size must be a positive number or a SizeField, got {size!r}")
        return None
    if not isinstance(size, SizeField):
        raise ArgumentTypeError(f"size must be a SizeField or a number, got {type(size).__name__}")
    if np.all(size.values == size.values.flat[0]):
        return None
    return ((size.x - centre[0]) / scale, (size.y - centre[1]) / scale, size.values / scale)


def hilbert_order(points: np.ndarray, bits: int = 16) -> np.ndarray:
    """Indices sorting points (K, 2) along a Hilbert curve over their bounding box."""
    lo = points.min(axis=0)
    span = max(float((points.max(axis=0) - lo).max()), 1e-300)
    side = 1 << bits
    q = np.minimum(((points - lo) / span * (side - 1)).astype(np.int64), side - 1)
    return np.argsort(_hilbert_index(q, np.int64(side)), kind="stable")


@njit(cache=True)
def _hilbert_index(q, side):
    """The distance along the Hilbert curve of each cell ``q`` (K, 2) of a
    ``side`` x ``side`` grid (one pass per point: vectorised, each of the
    log2(side) levels made a dozen K-sized temporaries)."""
    d = np.zeros(q.shape[0], np.int64)
    for k in range(q.shape[0]):
        x, y = q[k, 0], q[k, 1]
        s = side >> 1
        while s > 0:
            rx = 1 if (x & s) > 0 else 0
            ry = 1 if (y & s) > 0 else 0
            d[k] += s * s * ((3 * rx) ^ ry)
            if ry == 0:  # rotate the quadrant
                if rx == 1:
                    x, y = s - 1 - x, s - 1 - y
                x, y = y, x
            s >>= 1
    return d


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
        raise InternalError(f"GEOS returned a vertex that is not a polygon vertex {PLEASE_REPORT}")
    tris = idx[order[pos]].astype(np.int32).reshape(-1, 3)
    p = xy[tris]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (
        p[:, 1, 1] - p[:, 0, 1]
    ) * (p[:, 2, 0] - p[:, 0, 0])
    flip = cross < 0
    tris[flip] = tris[flip][:, ::-1]
    return np.ascontiguousarray(tris)


@dataclass(frozen=True, eq=False)
class Loaded:
    """P and its sites in the kernel: the exact constrained Delaunay triangulation.

    Attributes
    ----------
    m : cdt.Tri
        The kernel's triangulation, in normalised coordinates.
    xy : ndarray, shape (capacity, 2)
        Its coordinate array: the polygon vertices, then the sites, then room
        for the points still to come.
    sites : ndarray, shape (k, 2)
        The checked sites, in the caller's coordinates.
    edges : ndarray, shape (k,), int64
        The polygon edge each site lies on, -1 for an interior site.
    centre, scale :
        The normalisation: kernel coordinates are ``(x - centre) / scale``.
    grain : float
        How far rounding a new point to the caller's coordinates can move a
        distance (:func:`_grain`), in the caller's units.
    max_triangles : int
        The triangle capacity allocated.
    """

    m: object
    xy: np.ndarray
    sites: np.ndarray
    edges: np.ndarray
    centre: np.ndarray
    scale: float
    grain: float
    max_triangles: int


def edge_parameters(polygon: Polygon, sites: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Parameter t in [0, 1] of each site's projection on its constraint edge (an
    index into ``polygon.constraint_edges``; 0 for interior sites, ``edges`` -1)."""
    t = np.zeros(len(sites))
    on = np.flatnonzero(edges >= 0)
    if len(on):
        V, E = polygon.vertices, polygon.constraint_edges[edges[on]]
        a = V[E[:, 0]]
        d = V[E[:, 1]] - a
        t[on] = np.clip(((sites[on] - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
    return t


def _rings_with_sites(polygon: Polygon, sites: np.ndarray, edges: np.ndarray):
    """The rings with the boundary sites spliced in (kernel vertex indices), the
    chains of sites per polygon edge: (start vertex, [sites in order along it]),
    and the segment pieces split at their sites, as (u, v) vertex pairs."""
    nV = len(polygon.vertices)
    nE = polygon.n_ring_vertices  # ring edge e starts at vertex e
    t = edge_parameters(polygon, sites, edges)
    by_edge: dict[int, list[int]] = {}
    order = np.lexsort((np.arange(len(sites)), t))
    for i in order[edges[order] >= 0].tolist():  # the boundary sites only, in that order
        by_edge.setdefault(int(edges[i]), []).append(nV + i)
    on = {}
    for i in np.flatnonzero(edges >= nE):
        on.setdefault(int(edges[i]) - nE, []).append((float(t[i]), nV + int(i)))
    pieces = piece_pairs(polygon, on, boundary_tol(polygon))
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
    return rings, chains, pieces


def _initial(allxy, rings, chains, nR, nmax, tmax, grid, normal):
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
        own = [[v for v in r if v < nR] for r in rings]
        tris = polytri.triangulate(allxy[:nR], own)
        if cdt.build_adjacency(m, tris) != nR or not _valid(m, allxy, own):
            raise InternalError(f"could not triangulate the polygon exactly {PLEASE_REPORT}")
        if chains:
            idx = np.array([v for _, c in chains for v in c], dtype=np.int64)
            first = np.array([([e] + c)[j] for e, c in chains for j in range(len(c))], np.int64)
            status = cavity.split_sites(m, idx, first)
            if status < 0:
                k = int(idx[-status - 1])
                raise InternalError(
                    f"could not put boundary vertex {k} on its edge {PLEASE_REPORT}")
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


def site_edges(polygon: Polygon, sites) -> tuple[np.ndarray, np.ndarray]:
    """The caller's ``sites`` checked, and the polygon edge each lies on (-1 inside).

    Raises :class:`~uniform2d.errors.InvalidSitesError` if a site is outside P,
    repeated, non-finite or on a polygon vertex.  Which edge a site lies on is
    decided by distance (:func:`boundary_tol`): the library's own sites carry
    their edge instead (``edges`` of :func:`load`).
    """
    sites = _check_sites(polygon, sites)
    _, boundary = _classify_sites(polygon, sites, boundary_tol(polygon))
    edges = np.full(len(sites), -1, np.int64)
    for i, e, _t in boundary:
        edges[i] = e
    return sites, edges


def load(polygon: Polygon, sites=None, *, size=None, room: int = 0, edges=None) -> Loaded:
    """Build the exact constrained Delaunay triangulation of P's vertices and ``sites``.

    Without ``edges`` the sites are the caller's: checked and sorted by
    :func:`site_edges`.  With ``edges`` (the polygon edge of each site, -1
    inside) they are the library's own, placed by construction: nothing is
    judged by distance, so no tolerance can misjudge a site near a vertex.
    Boundary sites split their edge's constraint in order along it; the rings
    are triangulated and made exactly Delaunay (:func:`_initial`), then the
    interior sites inserted in Hilbert order.  ``room`` points more fit in the
    arrays (INSERT's n); ``size`` is the size field the kernel reads (see
    :func:`uniform2d.insert`).
    """
    if edges is None:
        sites, edges = site_edges(polygon, sites)
    else:
        sites = np.asarray(sites, dtype=np.float64).reshape(-1, 2)
        edges = np.asarray(edges, dtype=np.int64)
    centre, scale = _normaliser(polygon)
    grain = _grain(polygon, centre)
    V = polygon.vertices
    nV = len(V)
    nR = polygon.n_ring_vertices
    # inside the rings: the constraint vertices, the interior sites, the sites on pieces
    interior = np.concatenate([np.arange(nR, nV), nV + np.flatnonzero((edges < 0) | (edges >= nR))])
    rings, chains, pieces = _rings_with_sites(polygon, sites, edges)
    allxy = np.concatenate([(V - centre) / scale, (sites - centre) / scale], axis=0)
    nb0 = sum(len(r) for r in rings)
    t0 = nb0 + 2 * (len(rings) - 1) - 2  # triangles of a triangulated polygon with holes
    tmax = t0 + 2 * (len(interior) + room) + 4
    grid = _size_grid(size, centre, scale)
    m, xy = _initial(allxy, rings, chains, nR, nV + len(sites) + room, tmax, grid,
                     (centre, scale, grain / scale))
    if len(interior):
        idx = interior.astype(np.int64)
        idx = idx[hilbert_order(allxy[idx])]
        status = cavity.insert_sites(m, idx)
        if status < 0:
            k = int(idx[failed_site(status)])
            raise InternalError(f"could not insert vertex {k} {PLEASE_REPORT}")
    if pieces:
        us, vs = np.array(pieces, dtype=np.int64).T.copy()
        status = polytri.recover_pieces(m, us, vs)
        if status < 0:
            u, v = pieces[-status - 1]
            raise InternalError(
                f"could not recover the segment piece {u}-{v} as an edge {PLEASE_REPORT}")
    return Loaded(m, xy, sites, edges, centre, scale, grain, tmax)


def unload(loaded: Loaded) -> np.ndarray:
    """The triangles (M, 3) of the kernel's mesh.  They are exactly the constrained
    Delaunay triangulation of the points the caller gets: the kernel rounded
    every new point to what the caller's coordinates hold (:func:`cdt.snap`)."""
    return cdt.triangle_list(loaded.m)


def triangulate(polygon: Polygon, sites=None, edges=None) -> tuple[np.ndarray, np.ndarray]:
    """The exact constrained Delaunay triangulation of P with extra ``sites``.

    Parameters
    ----------
    polygon : Polygon
    sites : array_like, shape (k, 2), optional
        Points inside P or on its boundary (those on it split their edges).
    edges : array_like of int, shape (k,), optional
        The polygon edge each site lies on (-1 inside), for sites placed by
        construction; by default decided by distance (see :func:`load`).

    Returns
    -------
    points : ndarray, shape (|V| + k, 2)
        The polygon's vertices, then the sites, exactly as given.
    triangles : ndarray, shape (M, 3), int64
        Counter-clockwise, restricted to P.

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> from uniform2d.triangulation import triangulate
    >>> pts, tri = triangulate(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), [(0.5, 0.5)])
    >>> pts.shape, tri.shape
    ((5, 2), (4, 3))
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    loaded = load(polygon, sites, edges=edges)
    points = np.concatenate([polygon.vertices, loaded.sites], axis=0)
    triangles = unload(loaded)
    del loaded  # the kernel's arrays go before the check's own
    ensure_valid(points, triangles, polygon, len(points) - len(polygon.vertices), "triangulate")
    return points, triangles


def load_mesh(polygon: Polygon, points: np.ndarray, triangles: np.ndarray, size=None, edges=None):
    """A triangulated mesh of P (polygon vertices first) loaded into the kernel.

    Returns ``(m, xy, centre, scale, boundary, graded)``: the kernel's
    triangulation made exactly Delaunay in normalised coordinates (new points
    rounded to the caller's coordinates, :func:`cdt.snap`), its coordinate
    array, the normalisation, for every point on P's boundary ``(index among
    the points after the polygon vertices, polygon edge, parameter on it)``,
    and whether the kernel reads a (non-constant) size field.  ``edges`` as
    :func:`load`'s (None: found by distance).
    """
    nV = len(polygon.vertices)
    P0 = np.asarray(points, dtype=np.float64)
    T0 = np.asarray(triangles, dtype=np.int32)
    if edges is None:
        _, boundary = _classify_sites(polygon, P0[nV:], boundary_tol(polygon))
    else:
        edges = np.asarray(edges, dtype=np.int64)
        tb = edge_parameters(polygon, P0[nV:], edges)
        boundary = [(int(i), int(edges[i]), float(tb[i])) for i in np.flatnonzero(edges >= 0)]
    centre, scale = _normaliser(polygon)
    grid = _size_grid(size, centre, scale)
    m, xy = cdt.allocate(len(P0), len(T0), grid, (centre, scale, _grain(polygon, centre) / scale))
    xy[:] = (P0 - centre) / scale
    cdt.set_nv(m, len(P0))
    rebuild(m, T0, piece_chains(polygon, boundary, boundary_tol(polygon)))
    return m, xy, centre, scale, boundary, grid is not None
