"""Which polygon edge each Steiner point lies on, found independently of the optimiser."""

from __future__ import annotations

import numpy as np

from uniform2d.geometry import polygon_edges


def edges_of(polygon, points):
    """The polygon edge each site lies on exactly (-1: none), found independently
    of the optimiser (a boundary site lies on its edge within rounding)."""
    a, d, _ = polygon_edges(polygon, constraints=True)
    nV = len(polygon.vertices)
    out = np.full(len(points) - nV, -1)
    for i, p in enumerate(points[nV:]):
        w = p - a
        cross = w[:, 0] * d[:, 1] - w[:, 1] * d[:, 0]
        t = (w * d).sum(axis=1) / (d * d).sum(axis=1)
        on = np.flatnonzero((np.abs(cross) <= 1e-12) & (t >= 0) & (t <= 1))
        out[i] = on[0] if len(on) else -1
    return out
