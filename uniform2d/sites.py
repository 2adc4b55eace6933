"""The sites a caller adds to a polygon: checked, and sorted onto P's edges.

A site is inside P or on its boundary; which edge a site lies on is decided by
distance (:func:`uniform2d.tolerance.boundary_tol`) for the caller's sites
(:func:`site_edges`), while the library's own sites carry their edge by
construction and only need their parameter along it (:func:`edge_parameters`).
"""

from __future__ import annotations

import numpy as np
import shapely

from ._kernel.distance import to_segments
from .errors import InvalidSitesError
from .polygon import Polygon
from .tolerance import boundary_tol

__all__ = ["site_edges", "classify_sites", "edge_parameters"]


def site_edges(polygon: Polygon, sites) -> tuple[np.ndarray, np.ndarray]:
    """The caller's ``sites`` checked, and the polygon edge each lies on (-1 inside).

    Raises :class:`~uniform2d.errors.InvalidSitesError` if a site is outside P,
    repeated, non-finite or on a polygon vertex.  Which edge a site lies on is
    decided by distance (:func:`boundary_tol`): the library's own sites carry
    their edge instead (``edges`` of :func:`load`).
    """
    sites = _check_sites(polygon, sites)
    _, boundary = classify_sites(polygon, sites, boundary_tol(polygon))
    edges = np.full(len(sites), -1, np.int64)
    for i, e, _t in boundary:
        edges[i] = e
    return sites, edges


def classify_sites(polygon: Polygon, sites: np.ndarray, tol: float):
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
