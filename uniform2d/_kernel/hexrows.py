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
"""

import numpy as np

from ._jit import njit

__all__ = ["lattice_inside"]


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
def _rows(frame, origin, bounds, ua, va, ub, vb, out, fill):
    """Count (``fill`` False) or write into ``out`` (True) the lattice points
    inside; returns the count.  ``frame``: (spacing, dy, cos, sin, i0, i1, j0,
    j1), the lattice as :func:`uniform2d.optimize.lattice.hex_lattice` makes it."""
    spacing, dy, c, s = frame[0], frame[1], frame[2], frame[3]
    i0, i1, j0, j1 = int(frame[4]), int(frame[5]), int(frame[6]), int(frame[7])
    xmin, ymin, xmax, ymax = bounds[0], bounds[1], bounds[2], bounds[3]
    cross = np.empty(ua.shape[0] + 1)
    n = 0
    for j in range(j0, j1 + 1):
        v = j * dy
        k = _crossings(ua, va, ub, vb, v, cross)
        if k < 2:
            continue
        half = 0.5 * (j & 1)
        lo = max(i0, int(np.floor(cross[0] / spacing - half)) - 1)
        hi = min(i1, int(np.ceil(cross[k - 1] / spacing - half)) + 1)
        m = 0  # crossings below the point's u
        for i in range(lo, hi + 1):
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
            n += 1
    return n


@njit(cache=True)
def lattice_inside(frame, origin, bounds, ua, va, ub, vb):
    """The points (K, 2) of the lattice ``frame`` (see :func:`_rows`) within
    ``bounds`` and inside the polygon whose ring edges, in lattice coordinates
    (u along the rows, v across, from ``origin``), run from (ua, va) to (ub,
    vb): row by row, in each row by u, as ``hex_lattice`` orders them."""
    out = np.empty((0, 2))
    n = _rows(frame, origin, bounds, ua, va, ub, vb, out, np.bool_(False))
    out = np.empty((n, 2))
    _rows(frame, origin, bounds, ua, va, ub, vb, out, np.bool_(True))
    return out
