"""Resampled ring points moved along the outline, or within its band, to even out ring edges.

A resampled ring (:mod:`uniform2d.outline`) is sampled evenly in a
*straightened* arc length, and the dynamic programme moves samples where the
tolerance needs it, so a ring edge next to a kept corner can be half a spacing
long while its neighbour is a whole one.  The mesher cannot move ring points
(they are polygon vertices), and the mesh keeps that short ring edge as an edge.

- :func:`slide_samples` moves each movable sample *along the outline* (it stays
  on it) towards the point where its two ring edges are equally long, as long as
  both edges stay within the tolerance of the input they span (every input
  vertex between their ends within ``limit`` of them; a chord between two points
  of the outline whose input lies within ``limit`` of it is within ``limit`` of
  that input both ways, so the Hausdorff bound of the resampling holds).
  :mod:`uniform2d.outline` does not slide points :func:`crowded` by a narrow
  feature (there :mod:`uniform2d.outline_band` widens);
- :func:`even_out`, after widening, moves a point with a ring edge shorter than
  :data:`EVEN` spacings off the outline, within the band, along its
  neighbours' chord, where both its edges stay within the tolerance of the input
  they span, both ways (:func:`moved_heights`).

Alternate points move in turn (a point's neighbours stay still while it moves),
a few sweeps.
"""

from __future__ import annotations

import numpy as np
import shapely

from .segment_distance import point_segment_distance

__all__ = ["EVEN", "SWEEPS", "crowded", "edge_heights", "even_out", "moved_heights", "point_at",
           "slide_samples", "span_heights"]

#: Sweeps of sliding (each moves the even, then the odd samples).
SWEEPS = 12
#: Ring points with an edge shorter than this many spacings are moved by :func:`even_out`.
EVEN = 0.75
#: Bisection steps locating the point of equal ring edges between two neighbours.
_BISECT = 24
#: Points of a moved edge at which its distance to the input is measured, less one.
_SAMPLES = 32
#: A move of :func:`even_out` lengthens a point's shorter edge by at least this many spacings.
_GAIN = 0.01
#: Fractions of the way to that point tried in turn where the whole way leaves the tolerance.
_STEPS = (1.0, 0.5, 0.25)


def slide_samples(ring, ext, S, P, movable, limit: float, sweeps: int = SWEEPS,
                  short: float = np.inf):
    """The samples of one ring slid along the outline to even out their edges.

    Parameters
    ----------
    ring : (k, 2) float64
        The input ring (closed, the first point not repeated).
    ext : (2k + 1,) float64
        The measure positions of its vertices, twice round (increasing).
    S : (r,) float64
        The samples' increasing measure positions (within one turn of the first).
    P : (r, 2) float64
        The samples, on the input ring (at S).
    movable : (r,) bool
        The samples that may slide (not kept vertices, fixed points, segment ends).
    limit : float
        The tolerance (a length): every input vertex between two successive
        samples stays within it of the ring edge joining them (or no farther than
        it was, where it was farther).
    sweeps : int
        At most this many sweeps (fewer if nothing moves).
    short : float
        Only samples with a ring edge shorter than this (a length) move.

    Returns
    -------
    S : (r,) float64
    P : (r, 2) float64
        New arrays; a sample that did not move is as given (bit for bit).

    Examples
    --------
    >>> import numpy as np
    >>> ring = np.array([(0, 0), (4, 0), (4, 1), (0, 1)], float)
    >>> ext = np.concatenate([[0, 4, 5, 9], 10 + np.array([0, 4, 5, 9, 10])])
    >>> S = np.array([0.0, 0.5, 2.0, 4, 5, 9])
    >>> P = np.array([(0, 0), (0.5, 0), (2, 0), (4, 0), (4, 1), (0, 1)], float)
    >>> movable = np.array([0, 1, 1, 0, 0, 0], bool)
    >>> S2, P2 = slide_samples(ring, ext, S, P, movable, 0.1)
    >>> np.round(S2[1:3], 4).tolist()                  # edges of 4/3 on the straight side
    [1.3333, 2.6667]
    """
    S = np.array(S, dtype=np.float64)
    P = np.array(P, dtype=np.float64)
    r = len(S)
    if r < 3 or not np.any(movable):
        return S, P
    total = float(ext[len(ring)])
    idx = np.arange(r)
    prv, nxt = (idx - 1) % r, (idx + 1) % r
    base = edge_heights(ring, ext, S, P)
    bound = np.maximum(base, limit)  # an edge already beyond the tolerance may not get worse
    for _ in range(sweeps):
        moved = False
        for parity in (0, 1):
            L = np.hypot(*(P[nxt] - P).T)
            sel = np.flatnonzero(movable & (idx % 2 == parity) & ((idx < r - 1) | (r % 2 == 0))
                                 & (np.minimum(L, L[prv]) < short))
            if not len(sel):
                continue
            lo = np.where(prv[sel] < sel, S[prv[sel]], S[prv[sel]] - total)
            hi = np.where(nxt[sel] > sel, S[nxt[sel]], S[nxt[sel]] + total)
            target = _equal_point(ring, ext, lo, hi, P[prv[sel]], P[nxt[sel]])
            moved |= _move(ring, ext, S, P, sel, target, prv, nxt, bound)
        if not moved:
            break
    return S, P


def crowded(P, reach: float) -> np.ndarray:
    """(r,) bool: the points of a closed ring (r, 2) closer than ``reach`` to a ring
    edge that is not their own nor a neighbour's (across a narrow feature).

    Examples
    --------
    >>> import numpy as np
    >>> slot = np.array([(0, 0), (4, 0), (4, 3), (2.2, 3), (2.2, 1), (1.8, 1), (1.8, 3),
    ...                  (0, 3)], float)
    >>> np.flatnonzero(crowded(slot, 1.0)).tolist()     # the slot's sides, 0.4 apart
    [3, 4, 5, 6]
    """
    r = len(P)
    nxt = (np.arange(r) + 1) % r
    lines = shapely.linestrings(np.stack([P, P[nxt]], axis=1))
    pi, e = shapely.STRtree(lines).query(shapely.points(P), predicate="dwithin", distance=reach)
    gap = (e - pi) % r
    out = np.zeros(r, dtype=bool)
    out[pi[(gap >= 2) & (gap <= r - 3)]] = True
    return out


def edge_heights(ring, ext, S, P) -> np.ndarray:
    """(r,): per ring edge (from sample e to e + 1), the largest distance of the
    input vertices strictly between them (in measure position) from it (0 if none)."""
    k, r = len(ring), len(S)
    hi = np.append(S[1:], S[0] + ext[k])
    return span_heights(ring, ext, S, hi, P, P[(np.arange(r) + 1) % r])


def span_heights(ring, ext, lo, hi, A, B) -> np.ndarray:
    """(q,): per edge A[q] B[q] spanning measure positions (lo[q], hi[q]) (less than
    a turn, any turn), the largest distance of the input vertices strictly between
    from it (0 if none)."""
    k = len(ring)
    shift = -ext[k] * np.floor(lo / ext[k])  # lo in the first turn, hi within the second
    lo, hi = lo + shift, hi + shift
    i0 = np.searchsorted(ext, lo, side="right")
    c = np.maximum(np.searchsorted(ext, hi, side="left") - i0, 0)
    out = np.zeros(len(lo))
    if not c.sum():
        return out
    owner = np.repeat(np.arange(len(lo)), c)
    pos = np.arange(len(owner)) - np.repeat(np.cumsum(c) - c, c)
    d = point_segment_distance(ring[(i0[owner] + pos) % k], A[owner], B[owner])
    np.maximum.at(out, owner, d)
    return out


def point_at(ring, ext, s) -> np.ndarray:
    """(q, 2): the points of the ring at measure positions ``s`` (q,) (any turn)."""
    k = len(ring)
    total = ext[k]
    s = np.mod(s, total)
    cum = ext[:k + 1]
    i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, k - 1)
    t = np.clip((s - cum[i]) / (cum[i + 1] - cum[i]), 0.0, 1.0)
    return ring[i] + t[:, None] * (ring[(i + 1) % k] - ring[i])


def _equal_point(ring, ext, lo, hi, A, B) -> np.ndarray:
    """Measure positions in (lo, hi) where the outline's point X has |XA| = |XB|
    (bisection: |XA| - |XB| goes from negative at A to positive at B)."""
    a, b = lo.copy(), hi.copy()
    for _ in range(_BISECT):
        m = 0.5 * (a + b)
        X = point_at(ring, ext, m)
        f = np.hypot(*(X - A).T) - np.hypot(*(B - X).T)
        a = np.where(f < 0, m, a)
        b = np.where(f < 0, b, m)
    return 0.5 * (a + b)


def _move(ring, ext, S, P, sel, target, prv, nxt, bound) -> bool:
    """Move samples ``sel`` (in place) towards ``target``, the largest step of
    :data:`_STEPS` that makes the shorter of their two edges longer and keeps
    both within ``bound``; True if any moved."""
    total = float(ext[len(ring)])
    left = np.ones(len(sel), dtype=bool)
    L1 = np.hypot(*(P[sel] - P[prv[sel]]).T)
    L2 = np.hypot(*(P[nxt[sel]] - P[sel]).T)
    short = np.minimum(L1, L2)
    any_moved = False
    for f in _STEPS:
        i = sel[left]
        s = S[i] + f * (target[left] - S[i])
        X = point_at(ring, ext, s)
        A, B = P[prv[i]], P[nxt[i]]
        lo = np.where(prv[i] < i, S[prv[i]], S[prv[i]] - total)
        hi = np.where(nxt[i] > i, S[nxt[i]], S[nxt[i]] + total)
        l1, l2 = np.hypot(*(X - A).T), np.hypot(*(B - X).T)
        # sample 0 stays at a measure position >= 0 (S increasing from it, ext from 0)
        ok = (np.minimum(l1, l2) > short[left]) & (s > lo) & (s < hi) & ((i > 0) | (s >= 0))
        ok &= span_heights(ring, ext, lo, s, A, X) <= bound[prv[i]]
        ok &= span_heights(ring, ext, s, hi, X, B) <= bound[i]
        if ok.any():
            S[i[ok]] = s[ok]
            P[i[ok]] = X[ok]
            any_moved = True
        left[np.flatnonzero(left)[ok]] = False
        if not left.any():
            break
    return any_moved


def even_out(inputs, samples, rings, limit: float, reach: float, sweeps: int = SWEEPS):
    """Rings whose movable points were moved (off the outline, within the
    tolerance band) to lengthen their shorter ring edge.

    A point whose shorter edge is under ``EVEN * reach`` steps along the chord
    of its two neighbours by half the difference of its edges' lengths (the step that makes them equal), or half or a quarter of that step,
    the largest that lengthens its shorter edge and keeps both its edges within
    ``limit`` of the input they span, both ways (:func:`moved_heights`).
    Alternate points move in turn, a few sweeps.

    Parameters
    ----------
    inputs : list of (ring (k, 2), ext (2k + 1,))
        Per ring, the input ring and its vertices' measure positions, twice round.
    samples : list of (A (r, 2), movable (r,), edge_dev (r,), S (r,))
        Per ring, the samples on the input ring, which may move, each unmoved
        edge's deviation and the samples' measure positions.
    rings : list of (r, 2) float64
        The rings now: the samples, possibly moved within the band already.
    limit, reach : float
        The tolerance and the spacing (lengths).

    Returns
    -------
    list of (r, 2) float64
        The rings.
    float
        The largest deviation of an edge this moved (0 if none moved).
    """
    out, worst = [], 0.0
    for (ring, ext), (A, movable, _, S), Q in zip(inputs, samples, rings):
        P = np.array(Q, dtype=np.float64)
        r = len(A)
        idx = np.arange(r)
        prv, nxt = (idx - 1) % r, (idx + 1) % r
        stale = np.ones(r, dtype=bool)  # points to try: not tried since a neighbour moved
        for _ in range(sweeps):
            moved = False
            for parity in (0, 1):
                L = np.hypot(*(P[nxt] - P).T)
                short = np.minimum(L, L[prv])
                sel = np.flatnonzero(movable & stale & (idx % 2 == parity)
                                     & ((idx < r - 1) | (r % 2 == 0)) & (short < EVEN * reach))
                if not len(sel):
                    continue
                stale[sel] = False
                chord = P[nxt[sel]] - P[prv[sel]]
                step = (0.5 * (L[sel] - L[prv[sel]]) / np.hypot(*chord.T))[:, None] * chord
                for f in _STEPS:
                    T = P[sel] + f * step
                    d1 = moved_heights(ring, ext, S, A, prv[sel], P[prv[sel]], T)
                    d2 = moved_heights(ring, ext, S, A, sel, T, P[nxt[sel]])
                    gain = np.minimum(np.hypot(*(T - P[prv[sel]]).T),
                                      np.hypot(*(P[nxt[sel]] - T).T)) > short[sel] + _GAIN * reach
                    ok = gain & (d1 <= limit) & (d2 <= limit)
                    if ok.any():
                        P[sel[ok]] = T[ok]
                        worst = max(worst, float(np.maximum(d1, d2)[ok].max()))
                        stale[np.concatenate([sel[ok], prv[sel[ok]], nxt[sel[ok]]])] = True
                        moved = True
                    sel, step = sel[~ok], step[~ok]
                    if not len(sel):
                        break
            if not moved:
                break
        out.append(P)
    return out, worst


def moved_heights(ring, ext, S, A, e, X, Y) -> np.ndarray:
    """(q,): per ring edge e[q] (from sample e to e + 1) moved to X[q] Y[q], its
    distance from the input it spans, both ways (a bound): the input path from
    A[e] through the input vertices strictly between S[e] and S[e + 1] to
    A[e + 1] is within it of segment XY (exact: the distance to a segment is
    convex along each path edge), and so is every point of XY from the path (the
    distance at 33 points of XY, the mean of each two successive plus half their
    distance between them)."""
    k, r = len(ring), len(S)
    total = ext[k]
    lo = S[e]
    hi = np.where(e + 1 < r, S[(e + 1) % r], S[0] + total)
    i0 = np.searchsorted(ext, lo, side="right")
    c = np.maximum(np.searchsorted(ext, hi, side="left") - i0, 0)
    size = c + 2
    owner = np.repeat(np.arange(len(e)), size)
    pos = np.arange(len(owner)) - np.repeat(np.cumsum(size) - size, size)
    path = ring[(i0[owner] + pos - 1) % k]
    first, last = pos == 0, pos == c[owner] + 1
    path[first] = A[e[owner[first]]]
    path[last] = A[(e[owner[last]] + 1) % r]
    # every path has two points or more (size >= 2), in order of its edge: each
    # edge's path is one run of rows, reduced at the run's start
    start = np.cumsum(size) - size
    out = np.maximum.reduceat(point_segment_distance(path, X[owner], Y[owner]), start)
    seg = np.flatnonzero(owner[:-1] == owner[1:])
    t = np.arange(_SAMPLES + 1) / _SAMPLES
    o = owner[seg]
    Z = X[o][:, None, :] + t[None, :, None] * (Y[o] - X[o])[:, None, :]
    d = point_segment_distance(Z.reshape(-1, 2), np.repeat(path[seg], _SAMPLES + 1, axis=0),
                               np.repeat(path[seg + 1], _SAMPLES + 1, axis=0))
    near = np.minimum.reduceat(d.reshape(len(seg), -1), start - np.arange(len(e)), axis=0)
    half = 0.5 * np.hypot(*(Y - X).T) / _SAMPLES
    between = 0.5 * (near[:, :-1] + near[:, 1:]) + half[:, None]
    return np.maximum(out, between.max(axis=1))
