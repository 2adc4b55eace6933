"""Distance from many points to many segments (sites and seeds against P's edges).

Not a predicate: plain floating point, used only with margins: which given
sites lie on P's boundary (within a tolerance of 1e-10 of P's size, see
:func:`uniform2d.insert.insert`), and which seed points are a margin away from it.

Every point-segment distance is computed by one formula (:func:`_sq`), and a
point's result is the minimum of it over a set of segments that is sure to hold
the nearest one, so the result does not depend on which set that is.  With a
``cap``, distances at or above it are reported as ``cap``: the seeding only asks
whether a point is within a few target sizes of the boundary, and deep points
then cost a few cells each.  The bucketed search below returns the same bits as
the brute force over all segments, capped (pinned by a test).

Bucketing: the segments' bounding box is cut into a ``G x G`` grid (G about
sqrt(E)), every segment listed in each cell its own bounding box overlaps.  A
point inside the grid scans rings of cells around its own::

    +---+---+---+
    | 1 | 1 | 1 |     ring r = 1 around the point's cell (0); after ring r,
    +---+---+---+     every segment not yet seen lies outside the (2r+1)^2
    | 1 | 0 | 1 |     block, so at least r * cell from the point: stop once the
    +---+---+---+     best distance found is within (r - 1) * cell (one cell
    | 1 | 1 | 1 |     of slack: a point or a bounding box within rounding of a
    +---+---+---+     cell side may be filed in the neighbouring cell).

(shapely's ``STRtree.query_nearest`` with ``max_distance`` answers the same
question, but several times slower on the optimiser's sizes, and with GEOS's
own rounding, which would move points at the thresholds.)

Points outside the grid, few segments, no cap and grids whose cells are within
rounding of the coordinates (``cell`` below 1e-9 of their magnitude) go brute
force.
"""

import numpy as np
from ._jit import njit

__all__ = ["to_segments"]

#: Below this many segments (or points) the brute force is used.
BRUTE_MAX = 24


@njit(cache=True, inline="always")
def _sq(px, py, ax, ay, bx, by):
    """Squared distance from (px, py) to the segment (ax, ay)-(bx, by)."""
    dx = bx - ax
    dy = by - ay
    L2 = dx * dx + dy * dy
    s = ((px - ax) * dx + (py - ay) * dy) / L2 if L2 > 0 else 0.0
    s = min(max(s, 0.0), 1.0)
    qx = ax + s * dx - px
    qy = ay + s * dy - py
    return qx * qx + qy * qy


@njit(cache=True, inline="always")
def _nearest_sq(px, py, a, b):
    """Squared distance from (px, py) to the nearest of all segments a[e]-b[e]."""
    best = np.inf
    for e in range(a.shape[0]):
        best = min(best, _sq(px, py, a[e, 0], a[e, 1], b[e, 0], b[e, 1]))
    return best


@njit(cache=True)
def _brute(points, a, b, cap):
    out = np.empty(points.shape[0])
    for i in range(points.shape[0]):
        out[i] = min(np.sqrt(_nearest_sq(points[i, 0], points[i, 1], a, b)), cap)
    return out


@njit(cache=True)
def to_segments(points, a, b, cap):
    """Distance (K,) from each of points (K, 2) to the nearest segment a[i]-b[i]
    (E, 2), or ``cap`` (a float; ``np.inf`` for none) where that is smaller."""
    k = points.shape[0]
    E = a.shape[0]
    if E <= BRUTE_MAX or k <= BRUTE_MAX or cap == np.inf:
        return _brute(points, a, b, cap)
    # loops, not numba's generic array min / max / cumsum (costly to compile)
    x0 = y0 = np.inf
    x1 = y1 = -np.inf
    for e in range(E):
        x0 = min(x0, a[e, 0], b[e, 0])
        y0 = min(y0, a[e, 1], b[e, 1])
        x1 = max(x1, a[e, 0], b[e, 0])
        y1 = max(y1, a[e, 1], b[e, 1])
    G = max(1, int(np.sqrt(E)))
    cell = max(x1 - x0, y1 - y0) / G
    if not cell > 1e-9 * max(abs(x0), abs(y0), abs(x1), abs(y1)):
        return _brute(points, a, b, cap)
    # cells each segment's bounding box overlaps (clamped: rounding at x1, y1)
    lo_i = np.empty(E, np.int64)
    hi_i = np.empty(E, np.int64)
    lo_j = np.empty(E, np.int64)
    hi_j = np.empty(E, np.int64)
    count = np.zeros(G * G + 1, np.int64)
    for e in range(E):
        lo_i[e] = min(G - 1, int((min(a[e, 0], b[e, 0]) - x0) / cell))
        hi_i[e] = min(G - 1, int((max(a[e, 0], b[e, 0]) - x0) / cell))
        lo_j[e] = min(G - 1, int((min(a[e, 1], b[e, 1]) - y0) / cell))
        hi_j[e] = min(G - 1, int((max(a[e, 1], b[e, 1]) - y0) / cell))
        for i in range(lo_i[e], hi_i[e] + 1):
            for j in range(lo_j[e], hi_j[e] + 1):
                count[i * G + j + 1] += 1
    start = np.empty(G * G + 1, np.int64)
    total = 0
    for c in range(G * G + 1):
        total += count[c]
        start[c] = total
    fill = start[:-1].copy()
    items = np.empty(start[-1], np.int64)
    for e in range(E):
        for i in range(lo_i[e], hi_i[e] + 1):
            for j in range(lo_j[e], hi_j[e] + 1):
                items[fill[i * G + j]] = e
                fill[i * G + j] += 1
    seen = np.full(E, -1, np.int64)
    out = np.empty(k)
    for p in range(k):
        px = points[p, 0]
        py = points[p, 1]
        if not (x0 <= px <= x1 and y0 <= py <= y1):
            out[p] = min(np.sqrt(_nearest_sq(px, py, a, b)), cap)
            continue
        ci = min(G - 1, int((px - x0) / cell))
        cj = min(G - 1, int((py - y0) / cell))
        best = np.inf
        r = 0
        while True:
            for i in range(ci - r, ci + r + 1):
                if i < 0 or i >= G:
                    continue
                for j in range(cj - r, cj + r + 1):
                    if j < 0 or j >= G or (abs(i - ci) < r and abs(j - cj) < r):
                        continue  # off the grid, or an inner ring already scanned
                    c = i * G + j
                    for t in range(start[c], start[c + 1]):
                        e = items[t]
                        if seen[e] != p:
                            seen[e] = p
                            best = min(best, _sq(px, py, a[e, 0], a[e, 1], b[e, 0], b[e, 1]))
            if ci - r <= 0 and cj - r <= 0 and ci + r >= G - 1 and cj + r >= G - 1:
                break  # the whole grid is scanned
            bound = max(r - 1, 0) * cell
            if best <= bound * bound or bound >= cap:
                break  # every segment not seen is at least bound away
            r += 1
        out[p] = min(np.sqrt(best), cap)
    return out
