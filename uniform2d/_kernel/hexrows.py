"""The points of a hexagonal lattice inside a polygon, row by row.

The optimiser's starts search the lattice spacing that gives a count
(:func:`uniform2d.optimize.lattice.closest_count`): some ten lattices a start,
each of up to the polygon's box full of points, tested against the polygon.
Here a row of the lattice is a line: its crossings with the polygon's edges
are found once, and the row's points between them are inside (even-odd), so
the points outside are never made and the test costs the crossings, not a
point-in-polygon query per point.

A point within rounding of the boundary may come out either side; the
optimiser's starts keep only points farther from the boundary than half a
lattice spacing, where the crossings decide exactly as a point-in-polygon
query does.

The starts also want each point's distance to the segments it keeps clear of,
capped (:func:`uniform2d._kernel.distance.to_segments`): in a row only the
segments whose capsule of that radius reaches the row can be nearer than the
cap, and of those only the ones whose span along the row holds the point, so
:func:`lattice_inside` measures those alone, with the same formula: the same
bits as the brute force over all segments, capped.
"""

import numpy as np

from ._jit import njit
from .distance import _sq

__all__ = ["lattice_inside"]

#: Margin (relative to the cap and to the coordinates' magnitude) by which a
#: segment's reach along a row is widened: the rotation into the lattice's
#: coordinates rounds, and a segment within the cap must never be missed.
REACH_MARGIN = 1e-6


@njit(cache=True)
def _crossings(ua, va, ub, vb, v, out):
    """The u of every crossing of the line V = v with the edges (ua, va)-(ub,
    vb), sorted into ``out``; returns their count.  An edge counts where one
    end is at or below v and the other above (half-open: a vertex on the line
    counts once, a horizontal edge never)."""
    k = 0
    for e in range(ua.shape[0]):
        if (va[e] <= v) != (vb[e] <= v):
            u = ua[e] + (v - va[e]) * (ub[e] - ua[e]) / (vb[e] - va[e])
            i = k
            while i > 0 and out[i - 1] > u:  # insertion: a row crosses few edges
                out[i] = out[i - 1]
                i -= 1
            out[i] = u
            k += 1
    return k


@njit(cache=True)
def _reach(sua, sva, sub, svb, v, cap, pad, lo, hi, near):
    """The segments (lattice coordinates) whose capsule of radius ``cap``
    (widened by ``pad``) reaches the row V = v: their indices into ``near``,
    their span along the row into ``lo``/``hi``; returns their count."""
    k = 0
    for e in range(sua.shape[0]):
        if min(sva[e], svb[e]) - cap - pad <= v <= max(sva[e], svb[e]) + cap + pad:
            near[k] = e
            lo[k] = min(sua[e], sub[e]) - cap - pad
            hi[k] = max(sua[e], sub[e]) + cap + pad
            k += 1
    return k


@njit(cache=True)
def _rows(frame, origin, bounds, ua, va, ub, vb, seg, cap, out, dist, fill):
    """Count (``fill`` False) or write into ``out`` and ``dist`` (True) the
    lattice points inside and their distance to the segments ``seg`` = (sa,
    sb, and their ends in lattice coordinates: sua, sva, sub, svb), capped;
    returns the count.  ``frame``: (spacing, dy, cos, sin, i0, i1, j0, j1),
    the lattice as :func:`uniform2d.optimize.lattice.hex_lattice` makes it."""
    spacing, dy, c, s = frame[0], frame[1], frame[2], frame[3]
    i0, i1, j0, j1 = int(frame[4]), int(frame[5]), int(frame[6]), int(frame[7])
    xmin, ymin, xmax, ymax = bounds[0], bounds[1], bounds[2], bounds[3]
    sa, sb, sua, sva, sub, svb = seg
    pad = REACH_MARGIN * (cap + max(abs(xmin), abs(xmax), abs(ymin), abs(ymax), xmax - xmin,
                                    ymax - ymin))
    cross = np.empty(ua.shape[0] + 1)
    lo = np.empty(sa.shape[0])
    hi = np.empty(sa.shape[0])
    near = np.empty(sa.shape[0], np.int64)
    n = 0
    for j in range(j0, j1 + 1):
        v = j * dy
        k = _crossings(ua, va, ub, vb, v, cross)
        if k < 2:
            continue
        if fill:
            r = _reach(sua, sva, sub, svb, v, cap, pad, lo, hi, near)
        half = 0.5 * (j & 1)
        first = max(i0, int(np.floor(cross[0] / spacing - half)) - 1)
        last = min(i1, int(np.ceil(cross[k - 1] / spacing - half)) + 1)
        m = 0  # crossings below the point's u
        for i in range(first, last + 1):
            u = (i + half) * spacing
            while m < k and cross[m] < u:
                m += 1
            if m % 2 == 0:
                continue
            # the point exactly as hex_lattice computes it, in its box
            x = origin[0] + c * u - s * v
            y = origin[1] + s * u + c * v
            if not (x >= xmin and x <= xmax and y >= ymin and y <= ymax):
                continue
            if fill:
                out[n, 0] = x
                out[n, 1] = y
                best = np.inf
                for q in range(r):
                    if lo[q] <= u <= hi[q]:
                        e = near[q]
                        best = min(best, _sq(x, y, sa[e, 0], sa[e, 1], sb[e, 0], sb[e, 1]))
                dist[n] = min(np.sqrt(best), cap)
            n += 1
    return n


@njit(cache=True)
def lattice_inside(frame, origin, bounds, ua, va, ub, vb, seg, cap):
    """(points (K, 2), distances (K,)): the points of the lattice ``frame``
    (see :func:`_rows`) within ``bounds`` and inside the polygon whose ring
    edges, in lattice coordinates (u along the rows, v across, from
    ``origin``), run from (ua, va) to (ub, vb), row by row and in each row by
    u as ``hex_lattice`` orders them; and each one's distance to the nearest
    of the segments ``seg`` (see :func:`_rows`), or ``cap`` where that is
    smaller: :func:`.distance.to_segments`'s bits."""
    out = np.empty((0, 2))
    dist = np.empty(0)
    n = _rows(frame, origin, bounds, ua, va, ub, vb, seg, cap, out, dist, np.bool_(False))
    out = np.empty((n, 2))
    dist = np.empty(n)
    _rows(frame, origin, bounds, ua, va, ub, vb, seg, cap, out, dist, np.bool_(True))
    return out, dist
