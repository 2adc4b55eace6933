"""A kept corner and a ring point too close to it merged into one point of the outline.

Resampling (:mod:`uniform2d.outline`) keeps every corner of the outline; where
the outline needs a sample less than a spacing from a corner (the tolerance
would not hold without it), the ring edge between them is a short mesh edge.
With ``resample_corners="merge"``, :func:`merge_corners` replaces such a pair by
one point *on the outline between them*, where the two ring edges that replace
the three still hold the tolerance (every input vertex between their ends
within it; with every ring point on the outline, the Hausdorff bound holds both
ways).  The corner vertex itself is then no longer a mesh vertex: the outline
there is followed within the tolerance, not through the corner.  Segment ends,
fixed points and the points where crossings were split never merge, and no pair
merges where a ring edge next to the three it replaces is no longer than the
shortest of them: the ring would stay as short there, with one point fewer for the later
stages to even it out with (a sample pinned by a spike's tip stays pinned).
"""

from __future__ import annotations

import numpy as np

from .errors import InvalidArgumentError
from .ring_slide import point_at, span_heights

__all__ = ["CANDIDATES", "CORNERS", "SHORT", "corner_policy", "merge_corners"]

#: What resampling does with a corner next to a ring edge shorter than
#: ``SHORT`` spacings: ``"keep"`` it (the default), or merge it with
#: the ring point at the edge's other end (``"merge"``, :func:`merge_corners`).
CORNERS = ("keep", "merge")
#: A ring edge shorter than this many spacings with a corner at one end is merged.
SHORT = 0.6
#: Positions tried for the merged point, evenly between the corner and the other end.
CANDIDATES = 17


def corner_policy(corners) -> bool:
    """True if ``corners`` (one of :data:`CORNERS`) lets corners merge; else
    :class:`~uniform2d.errors.InvalidArgumentError` for anything but ``"keep"``.

    Examples
    --------
    >>> corner_policy("keep"), corner_policy("merge")
    (False, True)
    """
    if not isinstance(corners, str) or corners not in CORNERS:
        raise InvalidArgumentError(
            f"resample_corners must be one of {', '.join(map(repr, CORNERS))}, got {corners!r}")
    return corners == "merge"


def merge_corners(ring, ext, S, P, corner, free, h: float, limit: float):
    """The ring's short corner edges merged (shortest first), each into one point,
    where both ring edges next to the three a merge replaces are longer than their shortest.

    Parameters
    ----------
    ring : (k, 2) float64
        The input ring.
    ext : (2k + 1,) float64
        The measure positions of its vertices, twice round.
    S : (r,) float64
        The ring points' increasing measure positions (within one turn of the first).
    P : (r, 2) float64
        The ring points, on the input ring.
    corner : (r,) bool
        Kept corners that may merge.
    free : (r,) bool
        Samples that may merge with a corner (not kept, not a split point).
    h, limit : float
        The spacing and the tolerance (lengths).

    Returns
    -------
    keep : (r,) bool
        The ring points that stay (a merged pair keeps one, moved).
    S : (r,) float64
    P : (r, 2) float64
        New arrays: a merged pair's survivor is at the merged point.
    merged : (r,) bool
        The survivors of merged pairs.

    Examples
    --------
    >>> import numpy as np
    >>> ring = np.array([(0, 0), (4, 0), (4.1, 0.3), (4, 4), (0, 4)], float)
    >>> seg = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
    >>> cum = np.concatenate([[0], np.cumsum(seg)])
    >>> ext = np.concatenate([cum[:-1], cum[-1] + cum])
    >>> S, P = cum[[0, 1, 2, 3, 4]], ring.copy()
    >>> corner = np.array([0, 1, 0, 1, 1], bool)
    >>> keep, S2, P2, merged = merge_corners(ring, ext, S, P, corner, ~corner, 1.0, 0.25)
    >>> keep.tolist(), merged.tolist()                 # (4, 0) and (4.1, 0.3) are one point
    ([True, True, False, True, True], [False, True, False, False, False])
    """
    S = np.array(S, dtype=np.float64)
    P = np.array(P, dtype=np.float64)
    keep = np.ones(len(S), dtype=bool)
    merged = np.zeros(len(S), dtype=bool)
    total = float(ext[len(ring)])
    tried = set()
    while keep.sum() > 3:
        idx = np.flatnonzero(keep)
        m = len(idx)
        nx = idx[(np.arange(m) + 1) % m]
        L = np.hypot(*(P[nx] - P[idx]).T)
        pair = ((corner[idx] & free[nx]) | (free[idx] & corner[nx])) & ~merged[idx] & ~merged[nx]
        cand = [int(e) for e in np.argsort(L, kind="stable")
                if pair[e] and L[e] < SHORT * h and int(idx[e]) not in tried]
        if not cand:
            break
        e = cand[0]
        tried.add(int(idx[e]))
        a, i, j, b = idx[(e - 1) % m], idx[e], nx[e], idx[(e + 2) % m]
        if m < 4 or len({int(a), int(i), int(j), int(b)}) < 4:
            break
        # an edge next to the stretch no longer than the three the merge replaces: the
        # ring stays as short there, with one point fewer for the slide and pull to move
        floor = min(L[(e - 1) % m], L[e], L[(e + 1) % m])
        if ((L[(e - 2) % m] <= floor and not free[idx[(e - 2) % m]])
                or (L[(e + 2) % m] <= floor and not free[idx[(e + 3) % m]])):
            continue
        best = _best_point(ring, ext, total, S, P, a, i, j, b, L[e], limit)
        if best is None:
            continue
        keep[j] = False
        S[i], P[i] = best
        merged[i] = True
    return keep, S, P, merged


def _best_point(ring, ext, total, S, P, a, i, j, b, short, limit):
    """(measure position, point) between ring points i and j (a before, b after)
    at which the two edges a-X and X-b hold the tolerance and their shorter is
    longest, if it is longer than ``short``; else None."""
    lo, hi = S[i], S[j] if S[j] > S[i] else S[j] + total
    # strictly between: at either end the merge is a plain drop (outline_band's)
    s = lo + np.linspace(0.0, 1.0, CANDIDATES + 2)[1:-1] * (hi - lo)
    X = point_at(ring, ext, s)
    sa = S[a] if S[a] < S[i] else S[a] - total
    sb = S[b] if S[b] > hi else S[b] + total
    n = len(s)
    A, B = np.broadcast_to(P[a], (n, 2)), np.broadcast_to(P[b], (n, 2))
    ok = span_heights(ring, ext, np.full(n, sa), s, A, X) <= limit
    ok &= span_heights(ring, ext, s, np.full(n, sb), X, B) <= limit
    worst = np.minimum(np.hypot(*(X - A).T), np.hypot(*(B - X).T))
    worst = np.where(ok, worst, -np.inf)
    k = int(np.argmax(worst))
    if worst[k] <= short:
        return None
    return s[k], X[k]

