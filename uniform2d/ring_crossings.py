"""Where resampled rings cross: the edges to split (:mod:`uniform2d.outline`)."""

from __future__ import annotations

import numpy as np
import shapely

from .polygon import Polygon

__all__ = ["crossing_edges", "share_end"]


def crossing_edges(polygon: Polygon, samples) -> dict:
    """Per ring, the sampled edges (index of their first point) that cross or
    touch another edge of the rings or segments (not their neighbours)."""
    segs, owner = [], []
    for r, (pts, _, _, _) in enumerate(samples):
        segs.append(np.stack([pts, np.roll(pts, -1, axis=0)], axis=1))
        owner += [(r, i, len(pts)) for i in range(len(pts))]
    V = polygon.vertices
    E = polygon.segment_edges
    segs.append(np.stack([V[E[:, 0]], V[E[:, 1]]], axis=1).reshape(-1, 2, 2))
    owner += [(-1, i, 0) for i in range(len(E))]
    lines_xy = np.concatenate(segs)
    lines = shapely.linestrings(lines_xy)
    a, b = shapely.STRtree(lines).query(lines, predicate="intersects")
    out: dict = {}
    for i, j in zip(a.tolist(), b.tolist()):
        ri, pi, ni = owner[i]
        rj, pj, _ = owner[j]
        if i == j or ri < 0 or (ri == rj and (pj - pi) % ni in (1, ni - 1)):
            continue
        if rj < 0 and share_end(lines_xy[i], lines_xy[j]):  # a segment's junction
            continue
        out.setdefault(ri, set()).add(pi)
    return {r: np.array(sorted(k)) for r, k in out.items()}


def share_end(p, q) -> bool:
    """True if segments p and q ((2, 2) each) have an end point in common."""
    return any(np.array_equal(a, b) for a in p for b in q)
