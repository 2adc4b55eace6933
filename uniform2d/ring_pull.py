"""Resampled ring points moved anywhere in the tolerance band to lengthen a short ring edge.

A ring edge from a kept corner to a sample the tolerance pins (the chord
leaves an input vertex just within the tolerance) stays short under
:func:`uniform2d.ring_slide.slide_samples` (the sample cannot slide along the
outline without breaking the tolerance on one side) and under
:func:`uniform2d.ring_slide.even_out` (its one direction, along the
neighbours' chord, does the same).  Off the outline, towards the pinning
vertex, the chord can reach farther: :func:`pull_apart` tries, for a point
with a ring edge under :data:`PULL` spacings, positions on a grid of the
outline between its neighbours' anchors, each moved along the outline's
normal by up to 0.75 of the tolerance, and takes the one whose shorter ring
edge is longest, where both its edges stay within the tolerance of the input
they span, both ways (:func:`uniform2d.ring_slide.moved_heights`, the input
path now ending at the new position's anchor on the outline), no ring point
or edge within :data:`_WINDOW` places comes closer to the point or its edges
than before, and no ring angle at the point or its neighbours becomes sharper
than :data:`SHARP` (or than it was).  Alternate
points move in turn, a few sweeps, so a chain of samples moves together: a
neighbour whose edge got shorter moves next.

With ``across`` (:data:`ACROSS`, the default) a point's distance to the
nearest ring point across a narrow feature (:func:`_across`) counts as one of
its edges: the mesher joins two ring points that face each other across a
feature narrower than the spacing by an edge that short, so a point facing a
kept corner, or facing another point, slides along its side of the feature
(within the band, as above) until the corner faces the middle of a ring edge
and the two edges to its ends are longer than the feature's width.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from . import libm
from .segment_distance import point_segment_distance
from .ring_slide import SWEEPS, moved_heights, point_at, span_heights

__all__ = ["OFFSETS", "PULL", "SHARP", "pull_apart"]

#: Points with a ring edge shorter than this many spacings are moved.
PULL = 0.8
#: Offsets from the outline tried, as fractions of the tolerance (along its normal).
OFFSETS = (0.0, -0.25, 0.25, -0.5, 0.5, -0.75, 0.75)
#: Whether a point's distance to the ring across a narrow feature counts as one
#: of its edges (:func:`_across`).
ACROSS = True
#: Positions along the outline tried between a point's neighbours' anchors.
_GRID = 24
#: A move lengthens the point's shorter edge by at least this many spacings.
_GAIN = 0.01
#: A move makes no ring angle (at the point or its neighbours) sharper than this,
#: radians, unless it was already.
SHARP = np.pi / 4
#: Candidates per point checked both ways at a time (best gain first).
_BATCH = 8
#: Ring points and edges each side of a moved point whose clearance from it is kept.
_WINDOW = 6
#: A move never makes a ring edge longer than this many spacings (or than it was).
_LONGEST = 1.3


def pull_apart(inputs, samples, rings, limit: float, reach: float, sweeps: int = SWEEPS,
               across: bool = ACROSS):
    """Rings whose movable points were moved within the tolerance band to
    lengthen their shorter ring edge (see the module notes).

    Parameters
    ----------
    inputs : list of (ring (k, 2), ext (2k + 1,))
        Per ring, the input ring and its vertices' measure positions, twice round.
    samples : list of (A (r, 2), movable (r,), edge_dev (r,), S (r,))
        Per ring, the samples' anchors on the input ring, which may move, each
        edge's deviation and the anchors' measure positions (increasing, the
        first >= 0, within one turn of it).
    rings : list of (r, 2) float64
        The rings now (the anchors, possibly moved within the band already).
    limit, reach : float
        The tolerance and the spacing (lengths).
    sweeps : int
        At most this many sweeps.
    across : bool
        Whether a point's distance to the ring across a narrow feature counts
        as one of its edges (see the module notes).

    Returns
    -------
    list of (r, 2) float64
        The rings (a point that did not move is as given, bit for bit).
    float
        The largest deviation of an edge this moved (0 if none moved).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d.ring_slide import point_at
    >>> ring = np.array([(0, 0), (0.55, 0.3), (0.6, 0), (10, 0), (10, 3), (0, 3)], float)
    >>> seg = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
    >>> ext = np.concatenate([[0], np.cumsum(np.tile(seg, 2))])
    >>> S = np.r_[0, ext[1] + 0.9 * seg[1], ext[2] + np.arange(1, 10) - 0.4, ext[3], ext[4],
    ...           ext[4] + np.arange(1, 10), ext[5]]       # a sample pinned past the bump
    >>> A = point_at(ring, ext, S)
    >>> movable = np.ones(len(S), bool)
    >>> movable[[0, 11, 12, 22]] = False                     # the corners
    >>> out, dev = pull_apart([(ring, ext)], [(A, movable, None, S)], [A], 0.25, 1.0)
    >>> def shortest(P):
    ...     return round(float(np.hypot(*(np.roll(P, -1, axis=0) - P).T).min()), 2)
    >>> shortest(A), shortest(out[0]), bool(dev <= 0.25)
    (0.6, 0.76, True)
    """
    out, worst = [], 0.0
    for (ring, ext), (A0, movable, _, S0), Q in zip(inputs, samples, rings):
        P = np.array(Q, dtype=np.float64)
        A = np.array(A0, dtype=np.float64)
        S = np.array(S0, dtype=np.float64)
        r = len(P)
        idx = np.arange(r)
        stale = np.ones(r, dtype=bool)  # points to try: none near them moved since they failed
        for _ in range(sweeps if r >= 2 * _WINDOW + 2 else 0):
            moved = False
            for parity in (0, 1):
                L = np.hypot(*(P[(idx + 1) % r] - P).T)
                short = np.minimum(L, L[idx - 1])
                if across:
                    short = np.minimum(short, _across(P, idx, P, reach))
                sel = np.flatnonzero(movable & stale & (idx % 2 == parity)
                                     & ((idx < r - 1) | (r % 2 == 0)) & (short < PULL * reach))
                if not len(sel):
                    continue
                stale[sel] = False
                went, w = _pull(ring, ext, S, A, P, sel, limit, reach, across)
                if len(went):
                    worst = max(worst, w)
                    moved = True
                    near = np.arange(-_WINDOW - 1, _WINDOW + 2)  # their clearance changed
                    stale[(went[:, None] + near[None, :]).ravel() % r] = True
            if not moved:
                break
        out.append(P)
    return out, worst


def _pull(ring, ext, S, A, P, sel, limit, reach, across=False):
    """Move points ``sel`` (in place: S, A, P) to their best candidate: the
    points moved and the largest deviation of a moved edge (-1 if none moved)."""
    k, r = len(ring), len(S)
    total = float(ext[k])
    prv, nxt = (sel - 1) % r, (sel + 1) % r
    lo = np.where(prv < sel, S[prv], S[prv] - total)
    hi = np.where(nxt > sel, S[nxt], S[nxt] + total)
    shift = -total * np.floor(lo / total)  # measure positions within ext's two turns
    lo, hi = lo + shift, hi + shift
    q = len(sel)
    f = np.arange(1, _GRID + 1) / (_GRID + 1)
    s = (lo[:, None] + (hi - lo)[:, None] * f[None, :]).ravel()
    B = point_at(ring, ext, s)
    i = np.clip(np.searchsorted(ext, s, side="right") - 1, 0, 2 * k - 1)
    t = ring[(i + 1) % k] - ring[i % k]
    normal = np.c_[-t[:, 1], t[:, 0]] / np.hypot(*t.T)[:, None]
    off = np.asarray(OFFSETS) * limit
    X = (B[:, None, :] + off[None, :, None] * normal[:, None, :]).reshape(-1, 2)
    c = len(OFFSETS) * _GRID  # candidates per point
    owner = np.repeat(np.arange(q), c)
    sc = np.repeat(s, len(OFFSETS))
    Bc = np.repeat(B, len(OFFSETS), axis=0)
    l1 = np.hypot(*(X - P[prv[owner]]).T)
    l2 = np.hypot(*(P[nxt[owner]] - X).T)
    L1 = np.hypot(*(P[sel] - P[prv]).T)
    L2 = np.hypot(*(P[nxt] - P[sel]).T)
    won, had = np.minimum(l1, l2), np.minimum(L1, L2)  # the point's shorter edge
    floor = won  # no feature nearby made narrower than that
    if across:  # its distance to the ring across a narrow feature counts too
        won = np.minimum(won, _across(P, sel[owner], X, reach))
        across_had = _across(P, sel, P[sel], reach)
        # where that distance is what is short, no narrower than the new one
        floor = np.where((across_had < had)[owner], won, floor)
        had = np.minimum(had, across_had)
    gain = won - had[owner]
    cap = np.maximum(np.maximum(L1, L2), _LONGEST * reach)[owner]
    ok = (gain > _GAIN * reach) & (np.maximum(l1, l2) <= cap)
    ok &= (sel[owner] > 0) | (sc - shift[owner] >= 0)  # sample 0 keeps a position >= 0
    # no narrower feature: the moved point and edges keep their clearance from the
    # ring nearby (or at least their new shorter edge's length, or distance across)
    c_ok = np.flatnonzero(ok)
    if len(c_ok):
        old = _clearance(P, sel, P[sel], np.arange(q))
        new = _clearance(P, sel, X[c_ok], owner[c_ok])
        ok[c_ok] = new >= np.minimum(old[owner[c_ok]], floor[c_ok])
    # no sharper ring: the angles at the point and its neighbours stay at least
    # :data:`SHARP` or what they were (the mesher's triangles at a sharp ring
    # angle are small)
    c_ok = np.flatnonzero(ok)
    if len(c_ok):
        pp, nn = P[(sel - 2) % r], P[(sel + 2) % r]
        old = np.minimum(np.stack([_angle(pp, P[prv], P[sel]), _angle(P[prv], P[sel], P[nxt]),
                                   _angle(P[sel], P[nxt], nn)]), SHARP)
        o, Y = owner[c_ok], X[c_ok]
        ok[c_ok] = ((_angle(pp[o], P[prv[o]], Y) >= old[0, o])
                    & (_angle(P[prv[o]], Y, P[nxt[o]]) >= old[1, o])
                    & (_angle(Y, P[nxt[o]], nn[o]) >= old[2, o]))
    # the tolerance: one way first, for both edges (the input path's vertices
    # from the edge: cheap) ...
    edges = ((lo[owner], sc, A[prv[owner]], Bc, P[prv[owner]], X),
             (sc, hi[owner], Bc, A[nxt[owner]], X, P[nxt[owner]]))
    for lo_, hi_, A0, A1, Y0, Y1 in edges:
        j = np.flatnonzero(ok)
        ok[j] = np.maximum(span_heights(ring, ext, lo_[j], hi_[j], Y0[j], Y1[j]),
                           np.maximum(point_segment_distance(A0[j], Y0[j], Y1[j]),
                                      point_segment_distance(A1[j], Y0[j], Y1[j]))) <= limit
    # ... then both ways (the costly part), each point's candidates by decreasing
    # gain (ties: in order), a batch at a time, until one holds
    j = np.flatnonzero(ok)
    j = j[np.lexsort((j, -gain[j], owner[j]))]
    rank = np.arange(len(j)) - np.searchsorted(owner[j], owner[j])
    chosen, dev = np.full(q, -1), np.zeros(q)
    for b in range(0, int(rank.max(initial=-1)) + 1, _BATCH):
        t = j[(rank >= b) & (rank < b + _BATCH) & (chosen[owner[j]] < 0)]
        d = np.zeros(len(t))
        for lo_, hi_, A0, A1, Y0, Y1 in edges:
            d = np.maximum(d, _heights(ring, ext, lo_[t], hi_[t], A0[t], A1[t], Y0[t], Y1[t])
                           if len(t) else d)
        t, d = t[d <= limit], d[d <= limit]
        _, first = np.unique(owner[t], return_index=True)  # the best of each point's batch
        chosen[owner[t[first]]], dev[owner[t[first]]] = t[first], d[first]
    go = chosen >= 0
    if not go.any():
        return sel[:0], -1.0
    j, m = chosen[go], sel[go]
    S[m] = sc[j] - shift[go]
    A[m] = Bc[j]
    P[m] = X[j]
    return m, float(dev[go].max())


def _across(P, i, X, reach) -> np.ndarray:
    """(c,): per position X[c] of ring point i[c], its distance to the nearest ring
    point more than two places from i[c] along the ring (across a narrow feature:
    a mesh edge where it is shorter than the spacing), at most ``reach``."""
    r = len(P)
    d, j = cKDTree(P).query(X, k=min(r, 8), distance_upper_bound=reach)
    gap = np.abs(j - i[:, None]) % r
    gap = np.minimum(gap, r - gap)
    d = np.where((j < r) & (gap > 2), d, np.inf)
    return np.minimum(d.min(axis=1), reach)


def _heights(ring, ext, lo, hi, A0, A1, X, Y) -> np.ndarray:
    """(q,): per edge X[q] Y[q], its distance both ways from the input path that
    runs from A0[q] (at measure position lo[q]) along the outline to A1[q] (at hi[q])."""
    q = len(lo)
    S = np.empty(2 * q)
    S[0::2], S[1::2] = lo, hi
    A = np.empty((2 * q, 2))
    A[0::2], A[1::2] = A0, A1
    return moved_heights(ring, ext, S, A, np.arange(0, 2 * q, 2), X, Y)


def _clearance(P, sel, X, owner) -> np.ndarray:
    """Per candidate X[c] for ring point ``sel[owner[c]]``: the least distance from
    X to the ring edges within :data:`_WINDOW` of it that are not its own nor a
    neighbour's, and from the ring points within that window to its two edges
    that are not theirs nor a neighbour's (as :func:`uniform2d.outline_band.narrowest`
    measures a feature's width)."""
    r = len(P)
    i = sel[owner]
    near = np.r_[np.arange(2, _WINDOW + 1), -np.arange(3, _WINDOW + 1)]
    e = (i[:, None] + near[None, :]) % r  # edges e -> e + 1 away from X
    d = point_segment_distance(np.repeat(X, len(near), axis=0), P[e.ravel()], P[(e.ravel() + 1) % r])
    out = d.reshape(len(X), -1).min(axis=1)
    for a, b, js in (((i - 1) % r, None, near),
                     (None, (i + 1) % r, np.r_[np.arange(3, _WINDOW + 1), -np.arange(2, _WINDOW + 1)])):
        j = ((i[:, None] + js[None, :]) % r).ravel()
        A = np.repeat(P[a] if a is not None else X, len(js), axis=0)
        B = np.repeat(X if b is None else P[b], len(js), axis=0)
        out = np.minimum(out, point_segment_distance(P[j], A, B).reshape(len(X), -1).min(axis=1))
    return out


def _angle(A, B, C) -> np.ndarray:
    """(q,): the angle at B between BA and BC, radians in [0, pi]."""
    u, v = A - B, C - B
    return np.abs(libm.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1)))
