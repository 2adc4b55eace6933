"""Moves of a resampled outline's points within its tolerance band.

A resampled outline (:mod:`uniform2d.outline`) keeps every feature wider than
its tolerance: a pier, a fjord, a neck of land narrower than the mesh spacing h
stays, and its width becomes a mesh edge.  The tolerance allows more than
keeping it: the rings need only stay within ``limit`` (a length, the tolerance
times h) of the input outline, both ways, so each side of a narrow feature may
move up to that far from the other, widening a feature of width w to
``w + 2 * limit`` (outwards for a pier, into the material for a notch).

- :func:`merge_short_edges` drops a sample where a ring edge is much shorter
  than h and the edge replacing the two stays within the tolerance;
- :func:`widen_moves` pushes every movable ring point closer than ``reach`` to
  a ring edge that is not its own nor its neighbours' away from it, along its
  own normal (half the shortfall if the edge can move too), at most ``limit``,
  a few rounds, never making a ring edge shorter than 0.75 ``reach``; at a
  spike whose one side is a long input edge between kept points (longer than
  :data:`TIP_EDGE` ``reach``: the mesher splits it), the point next to the tip
  on the other side is pushed away from it too;
- :func:`hold_tolerance` cuts those moves back where a moved edge would leave
  the tolerance, measured both ways against the input path it spans;
- :func:`narrowest` is the narrowest part of rings: the caller keeps the moves
  only if they make it no narrower (and the rings stay a valid polygon).
"""

from __future__ import annotations

import numpy as np
import shapely

from .segment_distance import point_segment_distance

__all__ = ["MERGE", "REACH", "TIP_EDGE", "feature_width", "hold_tolerance", "merge_short_edges", "narrowest", "widen", "widen_moves", "widen_rings"]

#: Ring points closer than this many spacings to another part of the rings are
#: pushed apart (a mesh edge across a feature narrower than that is short).
REACH = 1.0
#: Ring edges shorter than MERGE[0] spacings lose an end where the edge that
#: replaces the two is at most MERGE[1] spacings long and within the tolerance.
MERGE = (0.6, 1.3)
#: Points per moved edge (besides its ends) whose distance to the input is measured.
_SAMPLES = 32
#: Moves are proposed up to this fraction of the tolerance (the measured bound on
#: a moved edge's distance exceeds the distance by up to half a sample step).
_SHARE = 0.9
#: A ring edge between two points that do not move, longer than this many
#: spacings (an input edge the mesher splits where it chooses), is across a spike
#: from the point beyond a neighbour where the ring turns back (see _near_pairs).
TIP_EDGE = 2.0
#: Rounds of pushing (each one recomputes the nearest edges).
_ROUNDS = 6


def widen_moves(rings, movable, reach: float, limit: float) -> list[np.ndarray]:
    """The moves (per ring, (r, 2) float64, each at most 0.9 ``limit`` long) that
    widen the rings' narrow features towards ``reach``; :func:`hold_tolerance`
    then cuts them back where a moved edge would leave the tolerance.

    Parameters
    ----------
    rings : list of (r, 2) float64
        Closed rings, the first point not repeated.
    movable : list of (r,) bool
        The points that may move (kept input vertices may not).
    reach : float
        The distance (a length) features are widened to where the moves allow.
    limit : float
        The longest move (a length): the tolerance.

    Examples
    --------
    >>> import numpy as np
    >>> slot = np.array([(0, 0), (4, 0), (4, 3), (2.2, 3), (2.2, 2), (2.2, 1),
    ...                  (1.8, 1), (1.8, 2), (1.8, 3), (0, 3)], float)
    >>> movable = np.array([0, 0, 0, 0, 1, 0, 0, 1, 0, 0], bool)
    >>> d = widen_moves([slot], [movable], 1.0, 0.25)[0]
    >>> (slot + d)[[4, 7], 0].round(3).tolist()      # the slot's sides, 0.4 apart: 0.85 now
    [2.425, 1.575]
    """
    P0, nxt, prv, start = _topology(rings)
    can = np.concatenate(movable)
    budget = np.where(can, _SHARE * limit, 0.0)
    L0 = np.hypot(*(P0[nxt] - P0).T)
    floor = np.minimum(L0, 0.75 * reach)  # no ring edge made shorter than this
    P = P0.copy()
    for _ in range(_ROUNDS):
        step = _push(P, nxt, prv, can, reach)
        if not step.any():
            break
        D = P + step - P0
        norm = np.hypot(*D.T)
        over = norm > budget
        D[over] *= (budget[over] / norm[over])[:, None]
        Q = P0 + D
        L = np.hypot(*(Q[nxt] - Q).T)
        short = (L < floor) & (L < np.hypot(*(P[nxt] - P).T))
        hold = np.zeros(len(P), dtype=bool)
        hold[short] = True
        hold[nxt[short]] = True
        Q[hold] = P[hold]
        if np.array_equal(Q, P):
            break
        P = Q
    return np.split(P - P0, start[1:-1])


def narrowest(rings, reach: float) -> tuple[float, np.ndarray]:
    """The narrowest part of closed rings: the shortest ring edge or the least
    distance from a ring point to a ring edge that is not its own nor a
    neighbour's (a feature's width), whichever is less, if less than ``reach``
    (else ``reach``); and where it is (a ring point, (2,)).  A mesh with these
    rings as its boundary has an edge at most that long where it is an edge,
    and almost always where it is a width.

    Examples
    --------
    >>> import numpy as np
    >>> slot = np.array([(0, 0), (4, 0), (4, 3), (2.2, 3), (2.2, 2), (2.2, 1),
    ...                  (1.8, 1), (1.8, 2), (1.8, 3), (0, 3)], float)
    >>> w, at = narrowest([slot], 1.0)
    >>> round(w, 3), at.tolist()
    (0.4, [2.2, 3.0])
    """
    P, nxt, prv, _ = _topology(rings)
    c, _ = _clearance(P, nxt, prv, reach)
    i = int(np.argmin(c))
    return float(c[i]), P[i]


def feature_width(rings, reach: float) -> tuple[float, np.ndarray]:
    """The least width of a feature of closed rings: the least distance from a
    ring point to a ring edge that is not its own nor a neighbour's (across a
    pier, a notch, a neck), if less than ``reach`` (else ``reach``), and the
    point.  Unlike a ring edge, it is a mesh edge only where the mesh spans it
    (a pier, a neck: not a notch).

    Examples
    --------
    >>> import numpy as np
    >>> slot = np.array([(0, 0), (4, 0), (4, 3), (2.2, 3), (2.2, 2), (2.2, 1),
    ...                  (1.8, 1), (1.8, 2), (1.8, 3), (0, 3)], float)
    >>> w, at = feature_width([slot], 1.0)
    >>> round(w, 3), at.tolist()
    (0.4, [2.2, 3.0])
    """
    P, nxt, prv, _ = _topology(rings)
    pi, e = _near_pairs(P, nxt, prv, reach)
    if not len(pi):
        return reach, P[0]
    d = point_segment_distance(P[pi], P[e], P[nxt[e]])
    i = int(np.argmin(d))
    return min(float(d[i]), reach), P[pi[i]]


def widen(inputs, samples, reach: float, limit: float):
    """Narrow features of resampled rings widened within ``limit`` of the input.

    :func:`widen_moves`, cut back by :func:`hold_tolerance`; a point whose
    clearance (its distance to the nearest ring edge not its own nor a
    neighbour's, or its own edges' length, up to ``reach``) the moves made
    smaller does not move, nor do the ends of the edge it came closer to, a
    few rounds.

    Parameters
    ----------
    inputs : list of (ring (k, 2), ext (2k + 1,))
        Per ring, the input ring and its vertices' measure positions, twice round.
    samples : list of (A (r, 2), movable (r,), edge_dev (r,), S (r,))
        Per ring, the samples (on the input ring), which may move, each edge's
        deviation and the samples' measure positions (see :func:`hold_tolerance`).
    reach, limit : float
        See :func:`widen_moves`.

    Returns
    -------
    list of (moves (r, 2), deviation (r,))
        Per ring, the moves and the deviation of each edge from the input.
    """
    base = [s[0] for s in samples]
    moves = widen_moves(base, [s[1] for s in samples], reach, limit)
    P0, nxt, prv, start = _topology(base)
    c0, _ = _clearance(P0, nxt, prv, reach)
    for _ in range(_ROUNDS):
        held = [hold_tolerance(g[0], g[1], s[3], s[0], d, s[2], limit)
                for g, s, d in zip(inputs, samples, moves)]
        D = np.concatenate([m for m, _ in held])
        c1, e = _clearance(P0 + D, nxt, prv, reach)
        worse = np.flatnonzero((c1 < c0) & (c1 < reach))
        if not len(worse):
            break
        still = np.ones(len(P0), dtype=bool)
        still[np.concatenate([worse, e[worse], nxt[e[worse]]])] = False
        moves = np.split(np.concatenate(moves) * still[:, None], start[1:-1])
    return held


def widen_rings(inputs, samples, reach: float, limit: float):
    """The rings moved by :func:`widen` if that leaves their narrowest part
    (:func:`narrowest`) no narrower, else as they were; and the deviation.

    Parameters and the deviation as in :func:`widen`; returns the rings (a
    list of (r, 2) float64) and the largest deviation (a float)."""
    base = [s[0] for s in samples]
    held = widen(inputs, samples, reach, limit)
    moved = [b + m for b, (m, _) in zip(base, held)]
    if narrowest(moved, reach)[0] >= narrowest(base, reach)[0]:
        return moved, max(float(d.max()) for _, d in held)
    return base, max(float(s[2].max()) for s in samples)


def _clearance(P, nxt, prv, reach):
    """Per ring point: the shorter of its two edges and its distance to the
    nearest ring edge not its own nor a neighbour's, at most ``reach``; and
    that edge (the point's own edge if none is nearer)."""
    L = np.hypot(*(P[nxt] - P).T)
    c = np.minimum(np.minimum(L, L[prv]), reach)
    e = np.where(L <= L[prv], np.arange(len(P)), prv)
    pi, ed = _near_pairs(P, nxt, prv, reach)
    if len(pi):
        d = point_segment_distance(P[pi], P[ed], P[nxt[ed]])
        order = np.lexsort((ed, -d, pi))  # per point, its nearest last
        pi, ed, d = pi[order], ed[order], d[order]
        closer = d < c[pi]
        c_new = c.copy()
        np.minimum.at(c_new, pi, d)
        last = np.concatenate([pi[1:] != pi[:-1], [True]]) & closer
        e[pi[last]] = ed[last]
        c = c_new
    return c, e


def hold_tolerance(ring, ext, S, A, moves, edge_dev, limit: float):
    """``moves`` of one ring's samples cut back (halved, then dropped) until every
    moved edge is within ``limit`` of the input outline, both ways; and the
    deviation reached per edge.

    A sampled edge e spans the input *path* from its sample A[e] to A[e + 1]
    (both on the outline) through the input vertices between them.  The path is
    within a distance of the moved edge if its vertices are (the distance to a
    segment is convex along each path edge); the moved edge is within a
    distance of the path if the mean of that distance at each two successive
    points ``1 / _SAMPLES`` of it apart, plus half their distance, is (the
    distance to the path changes no faster than a point moving along the edge).  Both are measured only where the simpler bound
    does not do: ``edge_dev[e]`` plus the longer move of the edge's ends (each
    point of the edge moves at most that far).

    Parameters
    ----------
    ring : (k, 2) float64
        The input ring.
    ext : (2k + 1,) float64
        The measure positions of its vertices, twice round.
    S : (r,) float64
        The samples' increasing measure positions (within one turn of the first).
    A : (r, 2) float64
        The samples, on the input ring.
    moves : (r, 2) float64
        Their moves.
    edge_dev : (r,) float64
        The deviation of each unmoved edge (A[e] to A[e + 1]).
    limit : float
        The tolerance (a length).

    Returns
    -------
    moves : (r, 2) float64
    deviation : (r,) float64

    Examples
    --------
    >>> import numpy as np
    >>> ring = np.array([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)], float)
    >>> ext = np.concatenate([[0, 1, 2, 4, 6], 8 + np.array([0, 1, 2, 4, 6, 8])])
    >>> S = np.array([0.0, 2, 4, 6])
    >>> A = ring[[0, 2, 3, 4]]
    >>> moves = np.array([(0, 0), (0, -0.3), (0, 0), (0, 0)])   # the corner pulled out by 0.3
    >>> m, dev = hold_tolerance(ring, ext, S, A, moves, np.zeros(4), 0.25)
    >>> m[1].round(3).tolist(), bool(dev.max() <= 0.25)
    ([0.0, -0.15], True)
    """
    r = len(S)
    nxt = (np.arange(r) + 1) % r
    Q, owner = _span_paths(ring, ext, S, A)
    f = np.ones(r)
    measured = np.full(r, np.inf)
    stale = np.ones(r, dtype=bool)  # edges whose ends moved since they were measured
    for rnd in range(_ROUNDS * 3):
        D = moves * f[:, None]
        m = np.hypot(*D.T)
        # moving an edge's ends by at most d moves each of its points by at most d
        dev = edge_dev + np.maximum(m, m[nxt])
        need = np.flatnonzero((dev > limit) & stale)
        if len(need):
            measured[need] = _moved_heights(Q, owner, A + D, need)
        dev = np.minimum(dev, measured)
        bad = np.flatnonzero(dev > np.maximum(limit, edge_dev))
        if not len(bad):
            return D, dev
        ends = np.concatenate([bad, nxt[bad]])
        f[ends] = 0.5 * f[ends] if rnd < _ROUNDS else 0.0
        stale[:] = False
        stale[ends] = stale[(ends - 1) % r] = True
        measured[stale] = np.inf
    return np.zeros_like(moves), edge_dev


def _span_paths(ring, ext, S, A):
    """The input paths of a ring's sampled edges, flattened: points (q, 2) and the
    edge each belongs to (q,), each path from A[e] through the input vertices
    strictly between S[e] and S[e + 1] to A[e + 1]."""
    k, r = len(ring), len(S)
    hi = np.append(S[1:], S[0] + ext[k])
    i0 = np.searchsorted(ext, S, side="right")
    c = np.searchsorted(ext, hi, side="left") - i0
    size = c + 2
    owner = np.repeat(np.arange(r), size)
    pos = np.arange(len(owner)) - np.repeat(np.cumsum(size) - size, size)  # place in its path
    inner = (pos > 0) & (pos <= c[owner])
    Q = np.empty((len(owner), 2))
    Q[inner] = ring[(i0[owner[inner]] + pos[inner] - 1) % k]
    first, last = pos == 0, pos == c[owner] + 1
    Q[first] = A[owner[first]]
    Q[last] = A[(owner[last] + 1) % r]
    return Q, owner


def _moved_heights(Q, owner, P, edges) -> np.ndarray:
    """Per edge in ``edges`` (from P[e] to P[e + 1]): the larger of the distance of
    its input path (Q, owner) from it and a bound on its distance from the path."""
    r = len(P)
    sel = np.isin(owner, edges)
    Qs, os_ = Q[sel], owner[sel]
    out = np.zeros(r)
    np.maximum.at(out, os_, point_segment_distance(Qs, P[os_], P[(os_ + 1) % r]))
    seg = np.flatnonzero(os_[:-1] == os_[1:])  # path edges (Qs[s], Qs[s + 1])
    e = os_[seg]
    t = np.arange(_SAMPLES + 1) / _SAMPLES
    X = P[e][:, None, :] + t[None, :, None] * (P[(e + 1) % r] - P[e])[:, None, :]
    d = point_segment_distance(X.reshape(-1, 2), np.repeat(Qs[seg], _SAMPLES + 1, axis=0),
                               np.repeat(Qs[seg + 1], _SAMPLES + 1, axis=0)).reshape(len(seg), -1)
    near = np.full((r, _SAMPLES + 1), np.inf)
    np.minimum.at(near, e, d)
    # between two samples a step apart, a distance that changes no faster than
    # the point is at most the mean of its two values plus half the step
    step = np.hypot(*(P[(np.arange(r) + 1) % r] - P).T) / _SAMPLES
    between = 0.5 * (near[:, :-1] + near[:, 1:] + step[:, None])
    far = np.where(np.isfinite(near).all(axis=1), between.max(axis=1), 0.0)
    return np.maximum(out, far)[edges]


def _topology(rings):
    """All ring points (P, 2), each one's next and previous point, ring starts."""
    sizes = [len(r) for r in rings]
    start = np.concatenate([[0], np.cumsum(sizes)])
    P = np.concatenate(rings)
    loc = np.arange(len(P))
    ring_of = np.repeat(np.arange(len(rings)), sizes)
    nxt = start[ring_of] + (loc - start[ring_of] + 1) % np.repeat(sizes, sizes)
    prv = np.empty_like(nxt)
    prv[nxt] = loc
    return P, nxt, prv, start


def _near_pairs(P, nxt, prv, reach, fixed=None):
    """(point, edge) pairs closer than ``reach``, the edge (from point e to nxt[e])
    not the point's own nor a neighbour's; with ``fixed`` ((n,) bool, the points
    that do not move), also an edge beyond a neighbour where the ring turns back
    (an acute angle at that neighbour: a spike, the point on one side, the edge
    on the other) if the edge's ends are fixed and it is longer than
    :data:`TIP_EDGE` ``reach`` (the mesher puts points on it, up the spike)."""
    lines = shapely.linestrings(np.stack([P, P[nxt]], axis=1))
    pi, e = shapely.STRtree(lines).query(shapely.points(P), predicate="dwithin", distance=reach)
    near = (e != pi) & (e != prv[pi]) & (e != nxt[pi]) & (e != prv[prv[pi]])
    if fixed is not None:
        b, f = prv[pi], nxt[pi]
        back = (e == prv[b]) & (np.einsum("ij,ij->i", P[pi] - P[b], P[prv[b]] - P[b]) > 0)
        fwd = (e == f) & (np.einsum("ij,ij->i", P[pi] - P[f], P[nxt[f]] - P[f]) > 0)
        long_fixed = (np.hypot(*(P[nxt[e]] - P[e]).T) > TIP_EDGE * reach) & fixed[e] & fixed[nxt[e]]
        near |= (back | fwd) & long_fixed
    return pi[near], e[near]


def _push(P, nxt, prv, can, reach) -> np.ndarray:
    """One round: per point, its move away from the nearest ring edge closer than
    ``reach`` that is not its own nor a neighbour's (zero if none)."""
    pi, e = _near_pairs(P, nxt, prv, reach, ~can)
    pi, e = pi[can[pi]], e[can[pi]]
    step = np.zeros_like(P)
    if not len(pi):
        return step
    d = point_segment_distance(P[pi], P[e], P[nxt[e]])
    order = np.lexsort((e, d, pi))  # per point, its nearest edge first (ties: lowest index)
    pi, e, d = pi[order], e[order], d[order]
    first = np.concatenate([[True], pi[1:] != pi[:-1]]) & (d > 0)
    pi, e, d = pi[first], e[first], d[first]
    A, B = P[e], P[nxt[e]]
    AB = B - A
    t = np.clip(np.einsum("ij,ij->i", P[pi] - A, AB) / np.einsum("ij,ij->i", AB, AB), 0.0, 1.0)
    away = (P[pi] - (A + t[:, None] * AB)) / d[:, None]
    # along the point's own normal (sliding along its ring would shorten its edges)
    tang = P[nxt[pi]] - P[prv[pi]]
    normal = np.c_[-tang[:, 1], tang[:, 0]] / np.hypot(*tang.T)[:, None]
    share = np.where(can[e] | can[nxt[e]], 0.5, 1.0)  # the other side moves too, or not
    step[pi] = normal * (np.einsum("ij,ij->i", away, normal) * share * (reach - d))[:, None]
    return step


def merge_short_edges(ring, ext, S, P, removable, h: float, limit: float) -> np.ndarray:
    """(r,) bool: the samples of a ring kept once its short edges are merged.

    The shortest edge shorter than ``MERGE[0] * h`` loses a removable end when
    the edge joining that end's neighbours is at most ``MERGE[1] * h`` long and
    every input vertex between them is within ``limit`` of it (the samples lie
    on the outline, so the new edge is then within ``limit`` of it both ways),
    the shorter new edge first; again until no short edge can lose an end.  A
    removed boundary point is one more point inside: n is unchanged.

    Parameters
    ----------
    ring : (k, 2) float64
        The input ring.
    ext : (2k + 1,) float64
        The measure position of its vertices, twice round.
    S : (r,) float64
        The samples' increasing measure positions (within one turn of the first).
    P : (r, 2) float64
        The samples (on the input ring).
    removable : (r,) bool
        The samples that may go.
    h, limit : float
        The spacing and the tolerance (lengths).

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], float)
    >>> ext = np.arange(9.0)
    >>> S = np.array([0, 0.9, 1, 2, 3])
    >>> P = np.array([(0, 0), (0.9, 0), (1, 0), (1, 1), (0, 1)])
    >>> merge_short_edges(sq, ext, S, P, np.array([0, 1, 0, 0, 0], bool), 1.0, 0.1).tolist()
    [True, False, True, True, True]
    """
    k = len(ring)
    total = float(ext[k])
    keep = np.ones(len(S), dtype=bool)
    while keep.sum() > 3:
        idx = np.flatnonzero(keep)
        m = len(idx)
        L = np.hypot(*(P[idx[(np.arange(m) + 1) % m]] - P[idx]).T)
        best = None
        for e in np.argsort(L, kind="stable"):
            if L[e] >= MERGE[0] * h:
                break
            for j in (e, (e + 1) % m):
                a, b = idx[(j - 1) % m], idx[(j + 1) % m]
                new = float(np.hypot(*(P[b] - P[a])))
                if removable[idx[j]] and new <= MERGE[1] * h and (best is None or new < best[0]) \
                        and _span_height(ring, ext, total, S[a], S[b], P[a], P[b]) <= limit:
                    best = (new, idx[j])
            if best is not None:
                break
        if best is None:
            break
        keep[best[1]] = False
    return keep


def _span_height(ring, ext, total, lo, hi, A, B) -> float:
    """Largest distance of the input vertices strictly between measure positions
    ``lo`` and ``hi`` (the next sample, a turn later if it wrapped) from edge AB."""
    if hi <= lo:
        hi += total
    if lo >= total:
        lo, hi = lo - total, hi - total
    i = np.arange(np.searchsorted(ext, lo, side="right"), np.searchsorted(ext, hi, side="left"))
    if not len(i):
        return 0.0
    k = len(ring)
    return float(point_segment_distance(ring[i % k], np.broadcast_to(A, (len(i), 2)),
                                        np.broadcast_to(B, (len(i), 2))).max())
