"""Relocation moves: the one change of a mesh's structure that point moves cannot make."""

from __future__ import annotations

import numpy as np

from .._kernel.distance import to_segments
from ..geometry import is_vertex, polygon_edges
from ..polygon import Polygon
from ..measures import edge_lengths
from ..tolerance import boundary_tol
from . import schedule as S
from .moves import improve_kept
from .objective import extremes, objective_value

__all__ = ["relocate"]


def _donor(pts, E, L, nV, free):
    """The free site whose edges are shortest on average (farthest below the target)."""
    total = np.zeros(len(pts))
    count = np.zeros(len(pts))
    np.add.at(total, E.ravel(), np.repeat(L, 2))
    np.add.at(count, E.ravel(), 1.0)
    mean = np.where(free, total[nV:] / np.maximum(count[nV:], 1.0), np.inf)
    return int(np.argmin(mean))


def relocate(polygon: Polygon, pts, tri, frozen, objective: str, h: float, options, edges,
             tries: int | None = None):
    """Move single points to where the mesh is sparsest while the objective improves.

    Each try takes the interior point whose edges are shortest on average (away
    from the target) and moves it to the midpoint of the longest edge, then
    re-relaxes the points within ``schedule.RELOCATE_RADIUS`` sizes of either
    place (``schedule.RELOCATE``); the move is kept if the objective improves.
    A failed edge is not tried again until a move succeeds; at most
    ``tries`` tries (``schedule.RELOCATE_TRIES`` by default).  The count of points
    never changes.
    ``edges`` (as :func:`~uniform2d.optimize.improve`'s) says which sites are on
    the boundary: they are known by construction, never judged by distance.

    Returns (points, triangles, moves kept, the sites' ``edges`` after the moves).
    """
    nV = len(polygon.vertices)
    value = objective_value(objective, *extremes(pts, tri), h)
    fixed = np.asarray(frozen, dtype=bool).copy()
    failed = set()
    kept = 0
    for _ in range(S.RELOCATE_TRIES if tries is None else tries):
        E, L = edge_lengths(pts, tri)
        target = next((E[j] for j in np.lexsort((np.arange(len(L)), -L)) if tuple(E[j]) not in failed), None)
        if target is None:
            break
        failed.add(tuple(target))
        new = 0.5 * (pts[target[0]] + pts[target[1]])  # on P's boundary if the edge is
        new_edge = _common_edge(polygon, edges, *target)
        if polygon.has_constraints and _near_constraint(polygon, new, new_edge):
            continue
        sites = pts[nV:]
        free = (edges < 0) & ~fixed
        free &= np.hypot(*(sites - new).T) > S.RELOCATE_RADIUS * h
        if not free.any():
            break
        r = _donor(pts, E, L, nV, free)
        old = sites[r].copy()
        trial = sites.copy()
        trial[r] = new
        trial_edges = edges.copy()
        trial_edges[r] = new_edge
        near = np.minimum(np.hypot(*(trial - new).T), np.hypot(*(trial - old).T))
        local = fixed | (near > S.RELOCATE_RADIUS * h)
        p2, t2, info2 = improve_kept(
            polygon, trial, objective=objective, href=h, frozen=local, edges=trial_edges,
            **{**options, **S.RELOCATE},
        )
        v2 = objective_value(objective, *extremes(p2, t2), h)
        if v2 < value:
            pts, tri, value, edges = p2, t2, v2, info2["edges"]
            kept += 1
            failed.clear()
    return pts, tri, kept, edges


def _near_constraint(polygon: Polygon, p, edge: int) -> bool:
    """Whether p is a polygon vertex, or lies within :func:`boundary_tol` of a
    constraint edge other than ``edge`` (where a fixed point lies a rounding
    off a segment, say): no place for a point of its own."""
    if is_vertex(polygon, p[None])[0]:
        return True
    a, d, _ = polygon_edges(polygon, constraints=True)
    others = np.flatnonzero(np.arange(len(a)) != edge)
    p = np.asarray(p, dtype=np.float64)[None]
    dist = to_segments(p, a[others], a[others] + d[others], np.inf)
    return float(dist[0]) <= boundary_tol(polygon)


def _common_edge(polygon: Polygon, edges, u: int, v: int) -> int:
    """The polygon edge both mesh points u and v lie on, or -1: the polygon edge
    of the midpoint of mesh edge u-v (a mesh edge joining two points of one polygon
    edge runs along it).  ``edges`` as :func:`improve`'s, for the points after
    the polygon's vertices (a vertex lies on the two edges that meet there)."""
    nV = len(polygon.vertices)
    E = polygon.constraint_edges

    def on(w):
        if w >= nV:
            return {int(edges[w - nV])} - {-1}
        return {int(e) for e in np.flatnonzero((E[:, 0] == w) | (E[:, 1] == w))}

    both = on(int(u)) & on(int(v))
    return min(both) if both else -1
