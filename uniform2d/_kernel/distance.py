"""Distance from many points to a few segments (the optimiser's seeding).

Brute force over the segments, O(points x segments), compiled: for the
polygons uniform2d meshes (tens to a few hundred edges) this beats building a
GEOS point per query by a wide margin.  Not a predicate: plain floating point,
used only to keep seed points a margin away from the boundary.
"""

import numpy as np
from numba import njit

__all__ = ["to_segments"]


@njit(cache=True)
def to_segments(points, a, b):
    """Distance (K,) from each of points (K, 2) to the nearest segment a[i]-b[i] (E, 2)."""
    k = points.shape[0]
    out = np.empty(k)
    for i in range(k):
        px = points[i, 0]
        py = points[i, 1]
        best = np.inf
        for e in range(a.shape[0]):
            ax = a[e, 0]
            ay = a[e, 1]
            dx = b[e, 0] - ax
            dy = b[e, 1] - ay
            L2 = dx * dx + dy * dy
            s = ((px - ax) * dx + (py - ay) * dy) / L2 if L2 > 0 else 0.0
            s = min(max(s, 0.0), 1.0)
            qx = ax + s * dx - px
            qy = ay + s * dy - py
            best = min(best, qx * qx + qy * qy)
        out[i] = np.sqrt(best)
    return out
