"""Topping a start up to its count: points in the largest gaps of its triangulation.

:func:`fill_largest_gaps` adds the centroids of the largest triangles of the
whole seed; :func:`fill_band_gaps`, for a large start a few points short,
triangulates only the band along the boundary, where its gaps are.
"""

from __future__ import annotations

import numpy as np
import shapely

from .._kernel.distance import to_segments
from ..polygon import Polygon
from ..triangulation import load, triangulate, unload

__all__ = ["fill_largest_gaps", "fill_band_gaps", "GAP_BLOCK", "BAND_FILL"]

#: Triangles measured at a time by :func:`fill_largest_gaps`.
GAP_BLOCK = 1 << 16


#: Depth (in sizes h) of the band :func:`fill_band_gaps` triangulates: past
#: the boundary rows (~0.9 h) and the lattice's first layers.
BAND_FILL = 6.0


def fill_largest_gaps(polygon: Polygon, bpts, P, count: int, face=None, bedges=None) -> np.ndarray:
    """Add the centroids of the largest triangles (of those inside ``face``, if
    given) until there are ``count`` points.  ``bedges``: the polygon edge of
    each of ``bpts``, known by construction (default: judged by distance)."""
    while len(P) < count:
        allp = np.concatenate([polygon.vertices, bpts, P])
        edges = None if bedges is None else np.concatenate([bedges, np.full(len(P), -1, np.int64)])
        # the kernel's exact triangulation, not checked as a mesh (only its
        # triangles' areas are read; the mesh made at the end is checked)
        tri = unload(load(polygon, allp[len(polygon.vertices):], edges=edges))
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


def fill_band_gaps(polygon: Polygon, bpts, P, count: int, h: float, sa, sb, bedges=None):
    """:func:`fill_largest_gaps` for a start with a few points too few, whose
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
