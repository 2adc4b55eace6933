"""The boundary of a start: the target size, and points splitting P's edges evenly.

:func:`target_size` is the side of an equilateral mesh with the wanted count
(every part of the optimiser sizes by it); :func:`boundary_counts` and
:func:`boundary_points` split every constraint edge into equal pieces, the
first thing a start (:mod:`uniform2d.optimize.seed`) places.
"""

from __future__ import annotations

import numpy as np

from ..geometry import size_for_count
from ..polygon import Polygon

__all__ = ["target_size", "boundary_counts", "boundary_points"]


def target_size(polygon: Polygon, n: int) -> float:
    """Side h of an equilateral mesh of P with |V| + n vertices.

    The inverse of :func:`uniform2d.steiner_count_for_size`."""
    return size_for_count(polygon.area, polygon.perimeter, n + len(polygon.vertices), polygon.n_holes)


def boundary_counts(L: np.ndarray, h: float, n: int) -> np.ndarray:
    """Pieces per polygon edge: round(L/h), at least 1, at most n extra points in total."""
    m = np.maximum(1, np.rint(L / h)).astype(np.int64)
    while (m - 1).sum() > n:
        e = int(np.argmin(np.where(m > 1, L / m, np.inf)))  # merge on the shortest pieces
        m[e] -= 1
    return m


def boundary_points(a, d, m):
    """The points splitting polygon edge e (start a[e], vector d[e]) into m[e]
    equal pieces: (points, their edge, their parameter on it)."""
    pts, eid, t = [], [], []
    for e in range(len(m)):
        s = np.arange(1, m[e]) / m[e]
        pts.append(a[e] + d[e] * s[:, None])
        eid.append(np.full(len(s), e, dtype=np.int64))
        t.append(s)
    if not pts:
        return np.empty((0, 2)), np.empty(0, np.int64), np.empty(0)
    return np.concatenate(pts), np.concatenate(eid), np.concatenate(t)
