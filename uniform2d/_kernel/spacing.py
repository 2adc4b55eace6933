"""The optimiser's search on the lattice spacing, whole, in one call.

A start of the optimiser tries some ten lattices (each a spacing) until one has
the count it wants (:func:`uniform2d.optimize.lattice.closest_count`).  Each
try made in Python cost some 40 microseconds of small numpy calls holding
the GIL around the row pass (:func:`.hexrows.lattice_inside`), while the
starts run on two threads: here the whole search runs in the kernel, nogil.
The search's steps (the bracket, its aims, when to stop: :func:`step`) are
the ones the Python loop takes too, on the candidates of a region, which only
shapely counts; the lattice's frame and the candidates' tests make the same
operations in the same order as the Python ones, so it finds the same lattice,
the same bits.
"""

import math

import numpy as np

from ._jit import njit
from .clearance import clear_at
from .hexrows import lattice_inside

__all__ = ["closest_count", "start", "step", "NEAREST", "ABOVE", "BELOW", "NEXT", "TAKE", "BEST"]

#: The fits of :class:`uniform2d.optimize.lattice.Fit`, as codes.
NEAREST, ABOVE, BELOW = 0, 1, 2


@njit(cache=True)
def _frame(bounds, sp, c, s, ox, oy):
    """:func:`uniform2d.optimize.lattice._frame` as the array
    :func:`.hexrows.lattice_inside` reads, the same operations."""
    xmin, ymin, xmax, ymax = bounds[0], bounds[1], bounds[2], bounds[3]
    dy = sp * math.sqrt(3.0) / 2
    X0, X1, Y0, Y1 = xmin - ox, xmax - ox, ymin - oy, ymax - oy
    u0, u1, u2, u3 = c * X0 + s * Y0, c * X1 + s * Y0, c * X1 + s * Y1, c * X0 + s * Y1
    v0, v1, v2, v3 = -s * X0 + c * Y0, -s * X1 + c * Y0, -s * X1 + c * Y1, -s * X0 + c * Y1
    j0 = math.floor(min(min(v0, v1), min(v2, v3)) / dy) - 2
    j1 = math.ceil(max(max(v0, v1), max(v2, v3)) / dy) + 2
    i0 = math.floor(min(min(u0, u1), min(u2, u3)) / sp) - 2
    i1 = math.ceil(max(max(u0, u1), max(u2, u3)) / sp) + 2
    out = np.empty(8)
    out[0], out[1], out[2], out[3] = sp, dy, c, s
    out[4], out[5], out[6], out[7] = i0, i1, j0, j1
    return out


@njit(cache=True)
def _kept(P, dist, sp, band, rows, rgrid, held, hgrid, cell):
    """The candidates of :class:`uniform2d.optimize.lattice.Candidates` among
    the lattice points P and their capped distances ``dist``: (points,
    distances) of those kept, in their order."""
    k = P.shape[0]
    ok = np.empty(k, np.bool_)
    clear = 0.75 * sp
    R, x0, y0, nx, ny, start, order = rgrid
    H, hx0, hy0, hnx, hny, hstart, horder = hgrid
    n = 0
    for a in range(k):
        d = dist[a]
        keep = d >= 0.5 * sp
        if rows:
            keep = keep and d >= band + 0.5 * sp
            if keep and d < 2.0 * band + sp:
                keep = clear_at(P[a, 0], P[a, 1], R, x0, y0, cell, nx, ny, start, order, clear)
        if held and keep:
            keep = clear_at(P[a, 0], P[a, 1], H, hx0, hy0, cell, hnx, hny, hstart, horder, clear)
        ok[a] = keep
        n += keep
    Q = np.empty((n, 2))
    q = np.empty(n)
    n = 0
    for a in range(k):
        if ok[a]:
            Q[n, 0] = P[a, 0]
            Q[n, 1] = P[a, 1]
            q[n] = dist[a]
            n += 1
    return Q, q


@njit(cache=True)
def _aim(sp, got, count, lo, hi, under):
    """The next spacing to try after ``got`` candidates at ``sp``: where the
    count would be ``count`` (plus a quarter of the tolerance, to land above
    it; minus, ``under``, to land below) if it went as 1/spacing**2, strictly
    inside the bracket (lo, hi)."""
    want = count + (-1.0 if under else 1.0) * (0.25 * (count // 500) + 0.5)
    x = sp * math.sqrt(max(got, 1) / want)
    margin = 1e-3 * (hi - lo)
    return min(max(x, lo + margin), hi - margin)


#: What :func:`step` says of the lattice just tried: try the next spacing,
#: take this lattice, or stop with the best one found.
NEXT, TAKE, BEST = 0, 1, 2


@njit(cache=True)
def start(h):
    """(lo, hi, mid, aimed): the search's bracket for target size ``h`` and its
    first spacing."""
    lo, hi = 0.5 * h, 1.5 * h
    # np.bool_: a literal False would compile step once more (for its type)
    return lo, hi, 0.5 * (lo + hi), np.bool_(False)


@njit(cache=True)
def step(got, best, have, count, h, fit, lo, hi, mid, aimed):
    """One step of the search on the spacing (the loop of
    :func:`uniform2d.optimize.lattice.closest_count` and of :func:`closest_count`
    here), after ``got`` candidates at spacing ``mid``; ``best``: the count of the
    best lattice so far (``have``: whether there is one).  Returns (better,
    outcome, lo, hi, mid, aimed): whether this lattice is the best now, what
    to do (:data:`NEXT` with the new bracket and spacing, :data:`TAKE`,
    :data:`BEST`)."""
    over, under = fit == ABOVE, fit == BELOW
    tol = count // 500
    off, boff = abs(got - count), abs(best - count)
    better = not have or off < boff or (off == boff and got >= count)
    if over and 0 <= got - count <= tol:
        return better, TAKE, lo, hi, mid, aimed
    if under and 0 <= count - got <= tol:
        return better, TAKE, lo, hi, mid, aimed
    if not (over or under) and off <= tol:  # the fix-up after it is exact
        return better, BEST, lo, hi, mid, aimed
    width = hi - lo
    if got > count:
        lo = mid
    else:
        hi = mid
    fast = (over or under) and tol > 0
    if fast and hi - lo < 1e-4 * h:
        return better, BEST, lo, hi, mid, aimed
    # aim, unless the last aim left more than half the bracket (then bisect)
    aimed = fast and not (aimed and hi - lo > 0.5 * width)
    mid = _aim(mid, got, count, lo, hi, under) if aimed else 0.5 * (lo + hi)
    return better, NEXT, lo, hi, mid, aimed


@njit(cache=True)
def closest_count(count, h, fit, bounds, origin, c, s, rings, seg, band, rows, rgrid, held,
                  hgrid, cell):
    """:func:`uniform2d.optimize.lattice.closest_count` on a
    :class:`~uniform2d.optimize.lattice.Candidates` of P (not of a region):
    (points, distances) of the lattice found.  ``fit``: NEAREST, ABOVE or
    BELOW; ``rings``: (ua, va, ub, vb), P's ring edges in the lattice's
    coordinates, and ``seg`` what its points keep clear of, as
    :func:`.hexrows.lattice_inside` reads them; ``rows`` / ``held``: whether
    the points of ``rgrid`` / ``hgrid`` (bucket grids of side ``cell``) are
    kept clear of; ``band``: the rows' band."""
    ua, va, ub, vb = rings
    lo, hi, mid, aimed = start(h)
    best = np.empty((0, 2))
    bestd = np.empty(0)
    have = np.bool_(False)
    for _ in range(30):
        cap = (2.0 * band + 2.0 * mid) if rows else 2.0 * mid
        frame = _frame(bounds, mid, c, s, origin[0], origin[1])
        P, dist = lattice_inside(frame, origin, bounds, ua, va, ub, vb, seg, cap)
        P, dist = _kept(P, dist, mid, band, rows, rgrid, held, hgrid, cell)
        better, outcome, lo, hi, mid, aimed = step(P.shape[0], best.shape[0], have, count, h,
                                                   fit, lo, hi, mid, aimed)
        if better:
            best, bestd, have = P, dist, True
        if outcome == TAKE:
            return P, dist
        if outcome == BEST:
            break
    return best, bestd
