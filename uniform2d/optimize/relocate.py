"""Relocation moves: the one change of a mesh's structure that point moves cannot make."""

from __future__ import annotations

import numpy as np

from .._kernel.distance import to_segments
from ..geometry import polygon_edges
from ..polygon import Polygon
from ..quality import edge_lengths
from ..triangulation import boundary_tol
from . import schedule as S
from .moves import improve
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


def relocate(polygon: Polygon, pts, tri, frozen, objective: str, h: float, options):
    """Move single points to where the mesh is sparsest while the objective improves.

    Each try takes the interior point whose edges are shortest on average (away
    from the target) and moves it to the midpoint of the longest edge, then
    re-relaxes the points within ``schedule.RELOCATE_RADIUS`` sizes of either
    place (``schedule.RELOCATE``); the move is kept if the objective improves.
    A failed edge is not tried again until a move succeeds; at most
    ``schedule.RELOCATE_TRIES`` tries.  The count of points never changes.

    Returns (points, triangles, moves kept).
    """
    nV = len(polygon.vertices)
    a, d, _ = polygon_edges(polygon)
    on_edge = boundary_tol(polygon)
    value = objective_value(objective, *extremes(pts, tri), h)
    fixed = np.asarray(frozen, dtype=bool).copy()
    failed = set()
    kept = 0
    for _ in range(S.RELOCATE_TRIES):
        E, L = edge_lengths(pts, tri)
        target = next((E[j] for j in np.lexsort((np.arange(len(L)), -L)) if tuple(E[j]) not in failed), None)
        if target is None:
            break
        failed.add(tuple(target))
        new = 0.5 * (pts[target[0]] + pts[target[1]])  # on P's boundary if the edge is
        sites = pts[nV:]
        free = (to_segments(sites, a, a + d, 2.0 * on_edge) > on_edge) & ~fixed
        free &= np.hypot(*(sites - new).T) > S.RELOCATE_RADIUS * h
        if not free.any():
            break
        r = _donor(pts, E, L, nV, free)
        old = sites[r].copy()
        trial = sites.copy()
        trial[r] = new
        near = np.minimum(np.hypot(*(trial - new).T), np.hypot(*(trial - old).T))
        local = fixed | (near > S.RELOCATE_RADIUS * h)
        p2, t2, _ = improve(
            polygon, trial, objective=objective, href=h, frozen=local, **{**options, **S.RELOCATE}
        )
        v2 = objective_value(objective, *extremes(p2, t2), h)
        if v2 < value:
            pts, tri, value = p2, t2, v2
            kept += 1
            failed.clear()
    return pts, tri, kept
