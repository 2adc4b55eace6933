"""Visibility from a point of a boundary subsegment: which sites its candidate sees.

A site is visible from a point of the subsegment when no gathered constrained
edge properly crosses the segment between them (exact orientation tests);
the subsegment's own ends always are.
"""

import numpy as np
from ._jit import njit

from .cdt import nxt
from .predicates import orient2d

__all__ = ["_visible", "_nearest_visible"]


@njit(cache=True)
def _visible(m, ne, x, y, q):
    """True if no collected constrained edge properly crosses segment (x, y) -> q."""
    xy = m.xy
    qx, qy = xy[q, 0], xy[q, 1]
    for k in range(ne):
        h = m.ebuf[k]
        e0 = m.tv[h]
        e1 = m.tv[nxt(h)]
        if e0 == q or e1 == q:
            continue
        s1 = orient2d(xy[e0, 0], xy[e0, 1], xy[e1, 0], xy[e1, 1], x, y)
        s2 = orient2d(xy[e0, 0], xy[e0, 1], xy[e1, 0], xy[e1, 1], qx, qy)
        if not ((s1 > 0.0 and s2 < 0.0) or (s1 < 0.0 and s2 > 0.0)):
            continue
        s3 = orient2d(x, y, qx, qy, xy[e0, 0], xy[e0, 1])
        s4 = orient2d(x, y, qx, qy, xy[e1, 0], xy[e1, 1])
        if (s3 > 0.0 and s4 < 0.0) or (s3 < 0.0 and s4 > 0.0):
            return False
    return True


@njit(cache=True, inline="always")
def _nearest_visible(m, sites, ne, x, y):
    """Squared distance from (x, y) on the subsegment to the nearest visible site
    (sites[0], sites[1] are its ends, always visible)."""
    xy = m.xy
    wmin = np.inf
    for k in range(sites.shape[0]):
        z = sites[k]
        d2 = (xy[z, 0] - x) ** 2 + (xy[z, 1] - y) ** 2
        if d2 < wmin and (k < 2 or _visible(m, np.int64(ne), x, y, z)):
            wmin = d2
    return wmin
