"""A Lloyd / centroidal Voronoi (CVT) baseline of our own, with an exact vertex count.

The usual "just smooth it" answer to uniform meshing, implemented plainly:

1. h = :func:`~uniform2d.peers.base.size_for_count` for the target count N.
2. Boundary: every polygon edge and interior segment piece
   (``polygon.constraint_edges``) of length L gets ``max(1, round(L / h))``
   equal pieces; these boundary vertices, and the fixed points, stay fixed.  (If they alone exceed N,
   h grows by 5 % until they fit.)
3. Interior: the remaining points start uniformly at random in P (fixed seed).
4. Lloyd iterations: each interior point moves to the centroid of its Voronoi
   cell clipped to P (shapely/GEOS), unless that centroid falls outside P (a
   cell wrapped round a reflex corner), in which case it stays.
5. The mesh is the constrained Delaunay triangulation of all points, from
   uniform2d's own kernel (``uniform2d.insert(polygon, 0, sites=...)``).

The vertex count is exactly N, so there is nothing to tune.
"""

from __future__ import annotations

import logging

import numpy as np
import shapely

from ..errors import InvalidArgumentError
from ..insert import insert
from .base import PeerMesh, size_for_count

log = logging.getLogger(__name__)

NAME = "cvt"
KIND = "planar"
DESCRIPTION = "Lloyd/CVT baseline (uniform2d): fixed equispaced boundary, Lloyd iterations, CDT"
REQUIRES = ()
#: Segments are split like ring edges and kept by the CDT; fixed points are
#: fixed generators (see :func:`uniform2d.peers.takes_constraints`).
CONSTRAINTS = True

#: Lloyd iterations (at most).
ITERATIONS = 60
#: Stop when no point moves more than this fraction of h.
TOLERANCE = 1e-4
#: Seed of the initial interior points.
SEED = 0


def available() -> bool:
    """Always True: only numpy, shapely and uniform2d are needed."""
    return True


def boundary_points(polygon, h: float) -> np.ndarray:
    """Equispaced points strictly inside the constraint edges (ring edges, then
    segment pieces), ``max(1, round(L/h))`` pieces each."""
    V = polygon.vertices
    E = polygon.constraint_edges
    out = []
    for a, b in E:
        pa, pb = V[a], V[b]
        m = max(1, int(round(float(np.hypot(*(pb - pa))) / h)))
        t = np.arange(1, m)[:, None] / m
        out.append(pa + t * (pb - pa))
    return np.vstack(out) if out else np.empty((0, 2))


def _random_inside(geom, k: int, rng) -> np.ndarray:
    minx, miny, maxx, maxy = geom.bounds
    got = []
    n = 0
    while n < k:
        cand = rng.random((max(64, 2 * (k - n)), 2)) * [maxx - minx, maxy - miny] + [minx, miny]
        cand = cand[shapely.contains_xy(geom, cand[:, 0], cand[:, 1])]
        got.append(cand)
        n += len(cand)
    return np.vstack(got)[:k]


def lloyd(polygon, fixed: np.ndarray, free: np.ndarray, *, iterations=ITERATIONS, tol=0.0):
    """Move the ``free`` points to the centroids of their clipped Voronoi cells.

    Parameters
    ----------
    polygon : uniform2d.Polygon
    fixed : ndarray, shape (k, 2)
        Generators that do not move (the boundary points).
    free : ndarray, shape (m, 2)
        Starting interior points.
    iterations : int
    tol : float
        Stop early when no point moves more than ``tol``.

    Returns
    -------
    points : ndarray, shape (m, 2)
    done : int
        Iterations run.
    """
    geom = polygon.to_shapely()
    minx, miny, maxx, maxy = geom.bounds
    pad = max(maxx - minx, maxy - miny)
    frame = shapely.box(minx - pad, miny - pad, maxx + pad, maxy + pad)
    k = len(fixed)
    pts = free.copy()
    done = 0
    for done in range(1, iterations + 1):
        gens = np.vstack([fixed, pts])
        cells = shapely.get_parts(
            shapely.voronoi_polygons(shapely.MultiPoint(gens), extend_to=frame, ordered=True)
        )
        clipped = shapely.intersection(cells[k:], geom)
        cent = shapely.get_coordinates(shapely.centroid(clipped))
        ok = ~shapely.is_empty(clipped)
        ok &= shapely.contains_xy(geom, cent[:, 0], cent[:, 1]) if len(cent) == len(pts) else False
        new = np.where(ok[:, None], cent, pts)
        move = float(np.abs(new - pts).max()) if len(pts) else 0.0
        pts = new
        if move <= tol:
            break
    return pts, done


def mesh(polygon, n_vertices: int) -> PeerMesh:
    """Lloyd/CVT mesh of ``polygon`` with exactly ``n_vertices`` vertices.

    Raises
    ------
    ValueError
        If ``n_vertices`` is smaller than the number of polygon vertices.
    """
    nV = len(polygon.vertices)
    if n_vertices < nV:
        raise InvalidArgumentError(f"n_vertices={n_vertices} is below the {nV} polygon vertices")
    h = size_for_count(polygon.area, polygon.perimeter, n_vertices, polygon.n_holes)
    while True:
        bpts = boundary_points(polygon, h)
        if nV + len(bpts) <= n_vertices:
            break
        h *= 1.05
    m = n_vertices - nV - len(bpts)
    rng = np.random.default_rng(SEED)
    start = _random_inside(polygon.to_shapely(), m, rng)
    fixed = np.vstack([polygon.vertices, bpts])
    free, done = lloyd(polygon, fixed, start, tol=TOLERANCE * h)
    log.debug("cvt: %d boundary + %d interior points, %d Lloyd iterations", len(bpts), m, done)
    res = insert(polygon, 0, sites=np.vstack([bpts, free]))
    return PeerMesh(
        np.array(res.mesh_points, dtype=np.float64),
        np.array(res.triangles, dtype=np.int64),
        None,
        1,
        {"h": h, "boundary_points": int(len(bpts)), "interior_points": int(m), "iterations": done},
    )
