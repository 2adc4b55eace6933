"""Algorithm INSERT (canonical Voronoi insertion) of Aurenhammer et al.

Step j inserts the point p_j of the closed polygon P farthest from the current
sites -- farthest in *visible* distance, the distance to the nearest site seen
from the point inside P (plain Euclidean distance for a convex P).  The sites
start as the polygon vertices V (and any extra ``sites``).

Contract: p_j is a global maximiser within a relative 1e-9;
``weights[j]`` = w_{j-1}(p_j) is its visible distance; the weights never
increase by more than the tie tolerance: a later point may weigh up to a
relative 1e-9 more (in practice one unit in the last place, where equal distances
were computed from different triangles); the same input gives bit-identical output.
Ties (weights within a
relative 1e-9 of the best) go to the lexicographically smallest (x, y), with x
compared to within 1e-9 of the bounding-box size, so the sequence is canonical
and invariant under scaling and translation.  See ``uniform2d._kernel.insert``
for how the tied group is found in O(log n) a step.  The polygon and its sites are
loaded into the kernel by :mod:`uniform2d.triangulation`, on coordinates
normalised exactly there; the polygon vertices and sites are returned exactly as
given, the inserted points mapped back exactly: each was rounded to what the
caller's coordinates hold before it was inserted, so the returned mesh is
exactly the constrained Delaunay triangulation the exact predicates built.  Far
from the origin that rounding (a few units in the last place of the
coordinates) is also the precision of the points and weights.

Sites: :func:`insert` decides by distance which are on the boundary (the
caller's sites); :func:`insert_on_edges` takes the edge of each site from its
caller (the library's own sites), so no tolerance judges them.  Either way a
boundary site splits its edge's constraint in order along it, and every mesh
passes :func:`uniform2d.validity.ensure_valid` before it is returned.
"""

from __future__ import annotations

import logging
import math
import numbers
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ._kernel import heap
from ._kernel import insert as kinsert
from ._kernel.clearance import closest_pair
from ._kernel.outcomes import ERR_PRECISION, RUN_STRIDE, run_failure
from .errors import CoordinatePrecisionError, InsufficientPointsError, InternalError, PLEASE_REPORT
from .grading import as_field
from .polygon import Polygon
from .sites import site_edges
from .sizefield import SizeField
from .tolerance import extent, rounding
from .triangulation import load, unload
from .validity import ensure_valid

__all__ = ["insert", "insert_on_edges", "min_distance_after", "InsertResult"]

log = logging.getLogger(__name__)

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
        present before it was inserted.  Non-increasing up to the tie tolerance:
        ``weights[j + 1] <= weights[j] * (1 + 1e-9)``.
    on_boundary : ndarray, shape (n,), bool
        Whether p_j was placed on the polygon boundary or on an interior segment
        (a constraint the mesh keeps).
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
        return _closest(self.mesh_points)


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
    size : SizeField, callable or float, optional
        A target-size field h: candidates are ranked by visible distance / h, so
        points are denser where h is small (the surface layer uses this).  A number,
        or a constant field, changes no comparison: the paper's algorithm exactly.
        A callable ``h(points (k, 2)) -> (k,)`` is sampled on a grid first
        (:func:`uniform2d.grading.as_field`); only h's shape matters.
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
    sites, edges = site_edges(polygon, sites)
    if size is not None and not isinstance(size, (numbers.Real, SizeField)):
        size = as_field(polygon, size)
    return insert_on_edges(polygon, int(n), sites, edges, size)


def insert_on_edges(polygon: Polygon, n: int, sites, edges, size=None) -> InsertResult:
    """:func:`insert` for sites whose place is known by construction.

    ``edges[i]`` is the polygon edge site i lies on, or -1 for an interior site.
    Nothing is classified by distance, so no tolerance can misjudge a site: the
    library's own callers (T+'s boundary points) come here, and a site near a
    polygon vertex is simply a boundary site.  A site that cannot be placed
    where it says it is raises :class:`~uniform2d.errors.InternalError`.  Every
    mesh made here passes :func:`~uniform2d.validity.ensure_valid` before
    it is returned.
    """
    loaded, points, weights, out_b = _run(polygon, n, sites, edges, size)
    mesh_points = np.concatenate([polygon.vertices, loaded.sites, points], axis=0)
    triangles = unload(loaded)
    sites = loaded.sites
    del loaded
    ensure_valid(mesh_points, triangles, polygon, len(mesh_points) - len(polygon.vertices), "insert")
    for arr in (points, weights, out_b, mesh_points, triangles):
        arr.setflags(write=False)
    return InsertResult(points, weights, out_b, mesh_points, triangles, polygon, sites)


def min_distance_after(polygon: Polygon, n: int) -> float:
    """d_n = l(S_n ∪ V, S_n ∪ V) of :func:`insert` ``(polygon, n)``: exactly
    ``insert(polygon, n).min_distance()``, without building the mesh (T+'s phase 1
    and the optimiser's certificates need only this distance)."""
    loaded, points, _, _ = _run(polygon, int(n), *site_edges(polygon, None))
    del loaded  # the kernel's arrays are not needed for the distance
    return _closest(np.concatenate([polygon.vertices, points], axis=0))


def _closest(P: np.ndarray) -> float:
    """The smallest distance between two of the points P (k, 2): that of
    ``cKDTree(P).query(P, k=2)``, found in a bucket grid of about four points
    a bucket (:func:`uniform2d._kernel.clearance.closest_pair`; the tree where
    the grid cannot tell)."""
    if len(P) >= 2:
        span = P.max(axis=0) - P.min(axis=0)
        cell = 2.0 * math.sqrt(float(span[0]) * float(span[1]) / len(P))
        if cell > 0.0 and math.isfinite(cell):
            d2, certain = closest_pair(np.ascontiguousarray(P, dtype=np.float64), cell)
            if certain:
                return math.sqrt(d2)
    d, _ = cKDTree(P).query(P, k=2)
    return float(d[:, 1].min())


def _run(polygon: Polygon, n: int, sites, edges, size=None):
    """INSERT's kernel run: (the loaded kernel, holding the final triangulation;
    the n points, their weights and whether each is on the boundary, in the
    caller's coordinates)."""
    loaded = load(polygon, sites, size=size, room=n, edges=edges)
    m, centre, scale = loaded.m, loaded.centre, loaded.scale
    span = extent(polygon)
    tmax = loaded.max_triangles

    # points nearer the boundary than this go on it: SNAP of the size, or more if
    # the caller's coordinates are too coarse there to hold a point nearer
    snap = max(SNAP * span, rounding(polygon))
    M = heap.new_heap(tmax + tmax // 2 + 64)  # ~1.9 n entries live; grows if needed
    kinsert.push_initial(m, M)
    P = kinsert.new_pool(64)
    out_xy = np.empty((n, 2), np.float64)
    out_w = np.empty(n, np.float64)
    out_b = np.zeros(n, np.bool_)
    xtol = (kinsert.REL_TIE * span + loaded.grain) / scale
    status = kinsert.run(m, M, P, n, out_xy, out_w, out_b, xtol, snap / scale)
    if status != n:
        _fail(polygon, status, n, out_xy, out_w, out_b)

    del M, P  # the queues are done: release them before the outputs are built
    # exact: the kernel rounded every point to what these coordinates hold (cdt.snap)
    return loaded, out_xy * scale + centre, out_w * scale, out_b


def _fail(polygon: Polygon, status: int, n: int, out_xy, out_w, out_b):
    """Raise for a failed kernel run: the caller's coordinates too coarse, or a bug."""
    j, what = run_failure(status)
    if status + RUN_STRIDE * j == ERR_PRECISION:
        V = polygon.vertices
        raise CoordinatePrecisionError(
            f"the polygon is {extent(polygon):.3g} across at {float(np.abs(V).max()):.3g} from "
            f"the origin, where coordinates are {np.spacing(np.abs(V).max()):.3g} apart: too "
            f"coarse to place point {j + 1} of {n}; translate the polygon nearer the origin "
            "(e.g. subtract its centre) or ask for fewer points"
        )
    raise InternalError(
        f"INSERT kernel failed ({what}, status {status}) at step {j}, point {tuple(out_xy[j])}, "
        f"weight {out_w[j]!r}, on boundary {bool(out_b[j])} {PLEASE_REPORT}"
    )
