"""Loading a polygon and its sites into the kernel's constrained Delaunay triangulation.

The service INSERT, the optimiser and the surface layer share: the sites
(sorted onto P's edges by :mod:`uniform2d.sites`) and P's vertices are mapped
exactly to the kernel's coordinates (:func:`uniform2d.tolerance.normaliser`),
the rings triangulated and made exactly Delaunay, the interior sites inserted
in Hilbert order and the segment pieces recovered as chains of constrained edges.

:func:`triangulate` is the exact CDT of P and some points; :func:`load` leaves
it in the kernel for INSERT to continue; :func:`load_mesh` loads a mesh that is
triangulated already (the optimiser moves its points), flagging its segment
pieces (:func:`piece_chains`, :func:`rebuild`).
"""

from __future__ import annotations

import collections
import functools
import logging
import numbers
import threading
from dataclasses import dataclass

import numpy as np
import shapely

from ._kernel import adjacency, cavity, cdt, lawson, polytri
from ._kernel.hilbert import hilbert_order
from ._kernel.outcomes import failed_site
from .errors import PLEASE_REPORT, ArgumentTypeError, InternalError, InvalidArgumentError
from .polygon import Polygon
from .sites import classify_sites, edge_parameters, site_edges
from .sizefield import SizeField
from .tolerance import boundary_tol, grain, normaliser
from .validity import ensure_valid

__all__ = ["triangulate", "load", "unload", "load_mesh", "Loaded", "piece_pairs", "piece_chains",
           "rebuild"]

log = logging.getLogger(__name__)

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


def _complex_key(p: np.ndarray) -> np.ndarray:
    """(K,) complex128 holding the points (K, 2) bit for bit (no arithmetic)."""
    out = np.empty(len(p), dtype=np.complex128)
    out.real = p[:, 0]
    out.imag = p[:, 1]
    return out


def _initial_triangles(xy: np.ndarray, rings: list[list[int]]) -> np.ndarray:
    """Constrained Delaunay triangles of the rings (GEOS), as CCW vertex indices.

    GEOS returns the input coordinates unchanged, so vertices are matched exactly.
    Its in-circle decisions are not exact; :func:`lawson.legalize_all` fixes that.
    The last few are kept (:func:`_ring_triangles`): the optimiser's starts of
    one boundary spacing have the same rings, and GEOS gives the same triangles
    for the same coordinates.
    """
    idx = np.concatenate([np.asarray(r, dtype=np.int64) for r in rings])
    key = (np.ascontiguousarray(xy[idx]).tobytes(), idx.tobytes(), tuple(len(r) for r in rings))
    return _ring_triangles(key).copy()


#: How many ring sets :func:`_ring_triangles` keeps (a mesh's starts have up
#: to three boundary spacings; threads may interleave several meshes).
RING_CACHE = 16


@functools.lru_cache(maxsize=RING_CACHE)
def _ring_triangles(key) -> np.ndarray:
    """:func:`_initial_triangles` of the rings ``key`` = (their vertices'
    coordinates, their indices, each ring's length), as bytes and a tuple."""
    pts = np.frombuffer(key[0], dtype=np.float64).reshape(-1, 2)
    idx = np.frombuffer(key[1], dtype=np.int64)
    parts = np.split(pts, np.cumsum(key[2])[:-1])
    geom = shapely.constrained_delaunay_triangles(shapely.Polygon(parts[0], parts[1:]))
    rings_ = shapely.get_exterior_ring(shapely.get_parts(geom))
    corners = shapely.get_coordinates(rings_).reshape(len(rings_), 4, 2)[:, :3]
    # exact matching on (x, y) through a complex key (ordered by x, then y)
    key_ = _complex_key(pts)
    order = np.argsort(key_, kind="stable")
    want = _complex_key(corners.reshape(-1, 2))
    pos = np.minimum(np.searchsorted(key_[order], want), len(key_) - 1)
    if not np.array_equal(key_[order][pos], want):
        raise InternalError(f"GEOS returned a vertex that is not a polygon vertex {PLEASE_REPORT}")
    tris = idx[order[pos]].astype(np.int32).reshape(-1, 3)
    p = pts[order[pos]].reshape(-1, 3, 2)  # the vertices of tris: xy[idx[j]] is pts[j]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (
        p[:, 1, 1] - p[:, 0, 1]
    ) * (p[:, 2, 0] - p[:, 0, 0])
    flip = cross < 0
    tris[flip] = tris[flip][:, ::-1]
    tris = np.ascontiguousarray(tris)
    tris.flags.writeable = False  # kept: callers get copies
    return tris


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
        distance (:func:`uniform2d.tolerance.grain`), in the caller's units.
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


def _rings_with_sites(polygon: Polygon, sites: np.ndarray, edges: np.ndarray):
    """The rings with the boundary sites spliced in (kernel vertex indices) and
    the chains of sites per polygon edge: (start vertex, [sites in order along
    it])."""
    nV = len(polygon.vertices)
    nE = polygon.n_ring_vertices  # ring edge e starts at vertex e
    ring = np.flatnonzero((edges >= 0) & (edges < nE))
    t = edge_parameters(polygon, sites[ring], edges[ring])
    by_edge: dict[int, list[int]] = {}
    # along each edge by parameter, then by index (as a sort of every site by
    # (t, index) read edge by edge)
    for i in ring[np.lexsort((ring, t))].tolist():
        by_edge.setdefault(int(edges[i]), []).append(nV + i)
    rings, chains = [], []
    for r in range(len(polygon.rings)):
        lo, hi = polygon.ring_offsets[r], polygon.ring_offsets[r + 1]
        ring_ = []
        for e in range(lo, hi):
            ring_.append(e)  # edge e starts at vertex e (Polygon.edges layout)
            ring_.extend(by_edge.get(e, []))
            if e in by_edge:
                chains.append((e, by_edge[e]))
        rings.append(ring_)
    return rings, chains


def _pieces(polygon: Polygon, sites: np.ndarray, edges: np.ndarray):
    """The segment pieces split at their sites, as (u, v) vertex pairs."""
    if not len(polygon.segment_edges):
        return []
    nV = len(polygon.vertices)
    nE = polygon.n_ring_vertices
    at = np.flatnonzero(edges >= nE)
    t = edge_parameters(polygon, sites[at], edges[at])
    on = {}
    for i, ti in zip(at.tolist(), t.tolist()):
        on.setdefault(int(edges[i]) - nE, []).append((ti, nV + i))
    return piece_pairs(polygon, on, boundary_tol(polygon))


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
        if adjacency.build_adjacency(m, tris) != nR or not _valid(m, allxy, own):
            raise InternalError(f"could not triangulate the polygon exactly {PLEASE_REPORT}")
        if chains:
            idx = np.array([v for _, c in chains for v in c], dtype=np.int64)
            first = np.array([([e] + c)[j] for e, c in chains for j in range(len(c))], np.int64)
            status = cavity.split_sites(m, idx, first)
            if status < 0:
                k = int(idx[-status - 1])
                raise InternalError(
                    f"could not put boundary vertex {k} on its edge {PLEASE_REPORT}")
    lawson.legalize_all(m)
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
    if adjacency.build_adjacency(m, tris) != nb0:
        return False
    return _valid(m, allxy, rings)


def _valid(m, allxy, rings) -> bool:
    ring_next = np.full(len(allxy), -1, np.int64)
    for r in rings:
        ring_next[np.asarray(r)] = np.roll(np.asarray(r), -1)
    return cdt.count_not_ccw(m) == 0 and cdt.boundary_is(m, ring_next)


#: Loads of at most this many points keep the triangulation of their rings
#: (with the boundary sites) for the next load with the same rings and as many
#: points (:func:`_staged`); how many are kept.
STAGE_MAX = 25000
STAGES = 8

_stages: collections.OrderedDict = collections.OrderedDict()
_stages_lock = threading.Lock()


def _stage_key(polygon: Polygon, sites, edges, nmax: int, tmax: int):
    """What decides the rings' triangulation of a load (:func:`_initial`),
    as bytes: P, the sites on its rings (their places, edges and indices) and
    the arrays' sizes; None for a load too large to keep (``STAGE_MAX``)."""
    if nmax > STAGE_MAX:
        return None
    at = np.flatnonzero((edges >= 0) & (edges < polygon.n_ring_vertices))
    return (polygon.vertices.tobytes(), polygon.edges.tobytes(), polygon.ring_offsets.tobytes(),
            at.tobytes(), sites[at].tobytes(), edges[at].tobytes(), len(sites), nmax, tmax)


def _staged(key, allxy):
    """(m, xy): a copy of the rings' triangulation kept for ``key``
    (:func:`_keep_stage`), its coordinates ``allxy``; (None, None) if none is.
    The optimiser's starts of one boundary spacing (12 a mesh of 1000 points,
    3 spacings) have the same rings: the triangulation of the rings (and the
    Python around it, which holds the GIL while the starts are built on
    several threads) is made once per spacing.  The rings' triangulation
    reads no other point, so the copy is the state :func:`_initial` makes."""
    if key is None:
        return None, None
    with _stages_lock:
        kept = _stages.get(key)
        if kept is None:
            return None, None
        _stages.move_to_end(key)
    m, xy = cdt.copied(kept)
    xy[: len(allxy)] = allxy
    return m, xy


def _keep_stage(key, m) -> None:
    """Keep a copy of the rings' triangulation ``m`` for ``key`` (see :func:`_staged`)."""
    if key is None:
        return
    kept, _ = cdt.copied(m)
    with _stages_lock:
        _stages[key] = kept
        _stages.move_to_end(key)
        while len(_stages) > STAGES:
            _stages.popitem(last=False)


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
    centre, scale = normaliser(polygon)
    snap_grain = grain(polygon, centre)
    V = polygon.vertices
    nV = len(V)
    nR = polygon.n_ring_vertices
    # inside the rings: the constraint vertices, the interior sites, the sites on pieces
    interior = np.concatenate([np.arange(nR, nV), nV + np.flatnonzero((edges < 0) | (edges >= nR))])
    allxy = np.concatenate([(V - centre) / scale, (sites - centre) / scale], axis=0)
    nb0 = nR + len(sites) - (len(interior) - (nV - nR))  # the rings' vertices, their sites
    t0 = nb0 + 2 * (len(polygon.rings) - 1) - 2  # triangles of a triangulated polygon with holes
    tmax = t0 + 2 * (len(interior) + room) + 4
    nmax = nV + len(sites) + room
    grid = _size_grid(size, centre, scale)
    key = _stage_key(polygon, sites, edges, nmax, tmax) if grid is None else None
    m, xy = _staged(key, allxy)
    if m is None:
        rings, chains = _rings_with_sites(polygon, sites, edges)
        m, xy = _initial(allxy, rings, chains, nR, nmax, tmax, grid,
                         (centre, scale, snap_grain / scale))
        _keep_stage(key, m)
    pieces = _pieces(polygon, sites, edges)
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
    return Loaded(m, xy, sites, edges, centre, scale, snap_grain, tmax)


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
        _, boundary = classify_sites(polygon, P0[nV:], boundary_tol(polygon))
    else:
        edges = np.asarray(edges, dtype=np.int64)
        tb = edge_parameters(polygon, P0[nV:], edges)
        boundary = [(int(i), int(edges[i]), float(tb[i])) for i in np.flatnonzero(edges >= 0)]
    centre, scale = normaliser(polygon)
    grid = _size_grid(size, centre, scale)
    m, xy = cdt.allocate(len(P0), len(T0), grid, (centre, scale, grain(polygon, centre) / scale))
    xy[:] = (P0 - centre) / scale
    cdt.set_nv(m, len(P0))
    rebuild(m, T0, piece_chains(polygon, boundary, boundary_tol(polygon)))
    return m, xy, centre, scale, boundary, grid is not None


# -- the segment pieces: chains of constrained edges through the points on them ----
def piece_chains(polygon: Polygon, boundary, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The segment pieces of P split at the points on them, as vertex pairs
    ``(us, vs)`` (mesh indices), from ``boundary`` as :func:`load_mesh` returns
    it: ``(index among the points after P's vertices, edge, parameter)``; ``tol``
    as :func:`piece_pairs`'s."""
    nV, nR = len(polygon.vertices), polygon.n_ring_vertices
    on: dict[int, list] = {}
    for i, e, t in boundary:
        if e >= nR:
            on.setdefault(e - nR, []).append((t, nV + i))
    out = np.array(piece_pairs(polygon, on, tol), dtype=np.int64).reshape(-1, 2)
    return out[:, 0].copy(), out[:, 1].copy()


def piece_pairs(polygon: Polygon, on: dict, tol: float) -> list:
    """Consecutive vertex pairs along every segment piece s: its ends, the points
    ``on[s]`` ((parameter, vertex) pairs) and any polygon vertex within ``tol``
    (the boundary tolerance) of the piece between its ends, in order along it.  Such a
    vertex (a fixed point a few ulps off a segment, beyond the 2 that make it a
    junction splitting the piece, ``constraints.NEAR_ULPS``) may lie exactly on
    the line between two points placed on the piece, which then cannot be an
    edge: it joins the chain."""
    V = polygon.vertices
    pairs = []
    for s, (a, b) in enumerate(polygon.segment_edges):
        d = V[b] - V[a]
        L2 = float(d @ d)
        rel = V - V[a]
        tt = rel @ d / L2
        off = np.abs(d[0] * rel[:, 1] - d[1] * rel[:, 0]) / np.sqrt(L2)
        near = np.flatnonzero((off <= tol) & (tt > 0.0) & (tt < 1.0))
        inner = sorted(on.get(s, []) + [(float(tt[k]), int(k)) for k in near if k not in (a, b)])
        chain = [int(a), *(v for _, v in inner), int(b)]
        pairs.extend(zip(chain[:-1], chain[1:]))
    return pairs


def rebuild(m, triangles, pieces) -> None:
    """Load the triangles (a valid mesh of P whose edges include the segment
    pieces ``pieces`` = (us, vs)) into ``m``, flag the pieces and make it the
    constrained Delaunay triangulation of its points."""
    adjacency.build_adjacency(m, np.ascontiguousarray(triangles, dtype=np.int32))
    if len(pieces[0]):
        if polytri.recover_pieces(m, pieces[0], pieces[1]) < 0:
            raise InternalError(f"a segment piece is not an edge of the mesh {PLEASE_REPORT}")
    else:
        lawson.legalize_all(m)
