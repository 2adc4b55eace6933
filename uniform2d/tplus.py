"""The paper's two-phase mesh T+ (Section 3), with one documented correction.

1. Run INSERT for n points; d_n = l(S_n ∪ V, S_n ∪ V), the smallest distance
   among the polygon vertices and the inserted points.
2. Put points on every polygon edge (outer ring and holes) and every interior
   segment piece at equal spacing: an
   edge of length L gets m = max(1, ⌈L / (hi · d_n)⌉) pieces (hi = 3 by default),
   where a ratio L / (hi · d_n) within the precision of the coordinates of an
   integer j counts as j (see "The piece count" below).
3. k = number of boundary points placed; run INSERT again for n − k points from
   the sites V ∪ (those k points).
4. T+ = the constrained Delaunay triangulation of all of them: exactly n Steiner
   points.

The correction.  The paper asks for consecutive boundary distances in
[2 d_n, 3 d_n] and says such a placement always exists.  It does not for an edge
of length L ∈ (3 d_n, 4 d_n): one piece is too long, two are too short.  With
m = ⌈L/(3 d_n)⌉ pieces the spacing L/m is still ≤ 3 d_n, and it is ≥ 1.5 d_n:
for L ≥ 3 d_n, m < L/(3 d_n) + 1 ≤ 2L/(3 d_n), so L/m > 1.5 d_n; for L < 3 d_n
the edge is not split and its length is ≥ l(V, V) ≥ 2 d_n under the theorem's
first hypothesis.  The proofs only use (i) boundary gaps ≤ 3 d_n (Lemma 5: the
circles of radius 3/2 d_n around later points stay inside P; Theorem 2, case 1:
critical triangles have edges ≤ 3 d_n by Lemma 3) and (ii) l(V', V') ≥ d_n for
the new boundary set V' (the lower bound of Theorem 2), and 1.5 d_n ≥ d_n; the
count bound k ≤ B/(2 d_n) − |V| of Lemma 6 uses the gaps being ≥ 2 d_n, and with
gaps ≥ 1.5 d_n it becomes k ≤ B/(1.5 d_n), so Lemma 6's sufficient condition is
weaker than stated -- which is why the hypothesis n ≥ 2k is checked directly.

Which hypotheses are checked.  Theorem 2 assumes d_n ≤ l(V,V)/2 and
d_n ≤ A/(π·B); with interior segments V holds their vertices and fixed points
too, and B is the total length phase 2 places points on (the perimeter plus
the segments' length).  The second only serves (Lemma 6) to guarantee n ≥ 2k, which
Lemma 5 needs.  Since k is known, ``info`` reports all three conditions and
the theorem is taken to apply when d_n ≤ l(V,V)/2 and n ≥ 2k hold -- exactly
what the proof uses.  Then every edge of T+ is ≤ 6 d_n and the edge ratio ≤ 6.

The piece count.  On polygons with exact geometry (rectilinear outlines, regular
polygons) d_n is often exactly L / (3 j) for some edge, and the computed ratio
L / (3 d_n) then lands within rounding of the integer j, on either side: ⌈·⌉
alone would give j or j + 1 depending on the scale and the position of the
polygon.  So the ratio r is compared with a tolerance τ r, τ = 1e-9 (the
tie tolerance of INSERT) plus the relative error rounding the coordinates
can put on a length of size d_n there: m = max(1, ⌈r − τ r⌉).  An edge within
τ of j pieces gets j, with gaps at most 3 d_n (1 + τ); the rule is the same at
every scale and offset up to rounding, and flips only for a ratio within
~1e-16 of j − τ j, which no exact geometry produces.

Other ``spacing=(lo, hi)``.  The edges get m = max(1, ⌈L/(hi·d_n)⌉) pieces, so
gaps are ≤ hi·d_n, and ≥ hi·d_n/2 on split edges.  Redoing the proofs with hi:
the gaps must stay ≥ d_n, so hi ≥ 2; Lemma 5's circles get radius hi/2·d_n and
its area count gives w(p'_n) ≤ hi·d_n once n ≥ c·k with c = hi²/(hi² − 4)
(the paper rounds c = 9/5 up to 2 for hi = 3; we use c = max(2, hi²/(hi² − 4))).
Theorem 2's two cases then become: if w(p'_n) < d_n, every edge lies in
[d_n/2, hi·d_n] (interior edges ≥ w(p'_n) ≥ d_n*/2 ≥ d_n/2; non-critical ones
≤ 2 w(p'_n) < 2 d_n; critical ones ≤ the longest boundary gap, hi·d_n); otherwise
every edge lies in [d_n, 2·hi·d_n].  Either way the edge ratio is at most 2·hi
(``info["edge_ratio_bound"]``; 6 for hi = 3) -- note that edges shorter than d_n do
occur, in the first case.  For hi ≤ 2 no bound follows.  ``lo`` is
only reported: whether every gap is ≥ lo·d_n (``info["gaps_within_spacing"]``).
"""

from __future__ import annotations

import logging
import math
import numbers

import numpy as np

from .errors import InsufficientPointsError, InvalidArgumentError
from ._kernel.insert import REL_TIE
from .geometry import is_vertex
from .insert import insert_on_edges, min_distance_after
from .mesh import Mesh
from .polygon import Polygon

__all__ = ["tplus", "boundary_points"]

log = logging.getLogger(__name__)


def boundary_points(polygon: Polygon, gap: float, rtol: float = 0.0):
    """Equally spaced points on every constraint edge (polygon edges, then the
    interior segment pieces: ``polygon.constraint_edges``), at most ``gap`` apart.

    Returns ``(points (k, 2) float64, pieces (E,) int)``: an edge of length L is
    cut into m = max(1, ⌈r − rtol · r⌉) equal pieces, r = L / gap (m − 1 new points
    on it; see the module docstring for ``rtol``).  ``edge_of(pieces)`` gives the
    edge each point lies on.
    """
    V = polygon.vertices
    E = polygon.constraint_edges
    a, b = V[E[:, 0]], V[E[:, 1]]
    m = boundary_counts(polygon, gap, rtol)
    pts = [a[e] + (b[e] - a[e]) * (np.arange(1, m[e])[:, None] / m[e]) for e in range(len(E))]
    return np.concatenate(pts, axis=0) if pts else np.empty((0, 2)), m


def boundary_counts(polygon: Polygon, gap: float, rtol: float = 0.0) -> np.ndarray:
    """The piece count m of every constraint edge, as :func:`boundary_points`
    cuts it (without making the points)."""
    V = polygon.vertices
    E = polygon.constraint_edges
    r = np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T) / gap
    return np.maximum(1, np.ceil(r - rtol * r)).astype(np.int64)


def least_k(polygon: Polygon, hi: float = 3.0, d: float | None = None) -> int:
    """A lower bound on T+'s k for every n whose d_n is at most ``d`` (default
    l(V, V), which bounds every d_n): a smaller d_n only shortens the gap, so the
    edges take at least the points they take for d_n = d (less any that land on
    a polygon vertex and are dropped).  INSERT's points for n are the first n of
    its points for any larger n, so d_n never grows with n: the d_n found for
    one n bounds k for every larger n."""
    d = polygon.min_vertex_distance() if d is None else d
    m = boundary_counts(polygon, hi * d, ratio_tolerance(polygon, d))
    dropped = len(polygon.vertices) if polygon.has_constraints else 0
    return max(0, int(m.sum() - len(m)) - dropped)


def edge_of(pieces: np.ndarray) -> np.ndarray:
    """The constraint edge of each point :func:`boundary_points` placed."""
    return np.repeat(np.arange(len(pieces)), pieces - 1)


def ratio_tolerance(polygon: Polygon, d_n: float) -> float:
    """τ of the piece count (module docstring): 1e-9, plus the relative error that
    rounding the coordinates (a few units in the last place of the largest)
    can put on a length of d_n."""
    return REL_TIE + 16.0 * np.finfo(float).eps * float(np.abs(polygon.vertices).max()) / d_n


def _phase1(polygon, n, hi):
    """(d_n, the boundary points T+ keeps and their edges, the piece counts); the
    points are None when there are more than n of them for certain (they are
    then not made: a tiny d_n can ask for billions).  Only d_n of INSERT's run is
    used, so its mesh is not built."""
    d_n = min_distance_after(polygon, n)
    rtol = ratio_tolerance(polygon, d_n)
    m = boundary_counts(polygon, hi * d_n, rtol)
    if int(m.sum() - len(m)) - len(polygon.vertices) > n:
        return d_n, None, None, m
    pts, m = boundary_points(polygon, hi * d_n, rtol)
    on = edge_of(m)
    if polygon.has_constraints:
        # a fixed point a few ulps off a segment (beyond the 2 that make it a
        # junction, constraints.NEAR_ULPS) does not split it; a point placed on
        # that piece can round onto it
        keep = ~is_vertex(polygon, pts)
        pts, on = pts[keep], on[keep]
    return d_n, pts, on, m


def _k(polygon, n, hi):
    """(T+'s k for n, or n + 1 when it is certainly more than n; d_n)."""
    d_n, pts, _, _ = _phase1(polygon, n, hi)
    return (n + 1 if pts is None else len(pts)), d_n


#: Above this lower bound on k, T+ is refused without searching for the smallest
#: n that works (each step of that search runs INSERT for about k points); the
#: search itself stops at this n (or the caller's n, if larger): on
#: near-degenerate domains d_n keeps shrinking as n grows (a point lands in a
#: thin wedge), so k can stay above n up to millions of points.
SEARCH_LIMIT = 100_000


class SearchLimitReached(InsufficientPointsError):
    """:func:`smallest_feasible_n` stopped at its limit with k still above n:
    at n (d_n there), and, if ``least`` > n, no n below ``least`` works either
    (:func:`least_k` for that d_n)."""

    def __init__(self, n: int, k: int, d_n: float, least: int, tried: list):
        self.n, self.k, self.d_n, self.least, self.tried = n, k, d_n, least, tried
        super().__init__(f"at n = {n} (d_n = {d_n:.6g}), T+ still needs more than n boundary points")


def smallest_feasible_n(polygon: Polygon, hi: float = 3.0, start: int = 1,
                        limit: int | None = None) -> int:
    """The smallest n for which T+ places no more boundary points than n (k <= n).

    From ``start``, a failed n moves on to the k it needed, or the lower bound
    :func:`least_k` its d_n gives every larger n, if larger (where d_n stays
    put, that n works at once), doubling instead after three such moves; then
    bisects down to the last n known to fail (stopping where d_n is the same at
    both ends: k, a function of d_n, is then the same in between).  It raises
    :class:`SearchLimitReached` (the n tried, the last one's k and d_n) at
    ``limit`` (default: no limit below 10^7), or as soon as that lower bound
    exceeds it."""
    cap = 10_000_000 if limit is None else max(int(limit), start)
    start = max(start, least_k(polygon, hi))
    lo, n = max(0, start - 1), max(1, start)
    tried = []
    d_fail = None  # d_n of the last n run that failed (lo is at or above it)
    while True:
        k, d_n = _k(polygon, n, hi)
        tried.append(n)
        if k <= n:
            break
        # every larger n has d_n no larger, so at least this many boundary points
        least = least_k(polygon, hi, d_n)
        if n >= cap or least > cap:
            raise SearchLimitReached(n, k, d_n, least, tried)
        lo, d_fail = max(n, least - 1), d_n  # fails: below least, k >= least > n
        n = min(max(k, least) if len(tried) <= 3 else max(2 * n, least), cap)
    while lo + 1 < n:  # ok(n) holds, ok(lo) does not (or lo is the start)
        if d_fail == d_n:
            # d_n is the same from the failed run to n, so is k (a function of
            # d_n): the first n from lo + 1 on that holds k works
            return max(lo + 1, k)
        mid = (lo + n) // 2
        k_mid, d_mid = _k(polygon, mid, hi)
        if k_mid <= mid:
            n, k, d_n = mid, k_mid, d_mid
        else:
            lo, d_fail = mid, d_mid
    return n


_NARROW = (
    "d_n, the distance of the closest two points INSERT places, is that small here (a "
    "narrow part of the polygon, e.g. between two segments at a small angle, takes points "
    "very close together); use uniform_mesh or insert for this polygon, or widen that part"
)


def _too_few(polygon, n, hi, d_n, k):
    """The error for k > n: naming the smallest n that works, or, where even a
    lower bound on k is out of reach, the polygon's closest vertices, or, where
    the search reaches :data:`SEARCH_LIMIT` (or n, if larger) with k still above
    it, the k found there."""
    least = least_k(polygon, hi)
    if least > SEARCH_LIMIT:
        return InsufficientPointsError(
            f"T+ needs at least {least} boundary points for this polygon, more than n = {n}: "
            f"two of its vertices are only {polygon.min_vertex_distance():.6g} apart, d_n is "
            f"never larger, and T+ puts boundary points at most {hi:g} d_n apart; use "
            "uniform_mesh or insert for this polygon, or move those vertices apart"
        )
    try:
        need = smallest_feasible_n(polygon, hi, start=n + 1, limit=max(SEARCH_LIMIT, n + 1))
    except SearchLimitReached as stop:
        if stop.least > stop.n:
            return InsufficientPointsError(
                f"T+ needs {k} boundary points for n = {n} (d_n = {d_n:.6g}), more than n; "
                f"the search for the smallest n that works tried n = "
                f"{', '.join(map(str, stop.tried))} in vain, and every n from {stop.n} on "
                f"needs at least {stop.least} (d_n = {stop.d_n:.6g} at n = {stop.n}, and d_n "
                f"never grows with n), more than the search goes to ({SEARCH_LIMIT}); {_NARROW}"
            )
        return InsufficientPointsError(
            f"T+ needs {k} boundary points for n = {n} (d_n = {d_n:.6g}), more than n, and "
            f"still more than n at n = {stop.n} (d_n = {stop.d_n:.6g}), where the search for "
            f"the smallest n that works stops; {_NARROW}"
        )
    return InsufficientPointsError(
        f"T+ needs {k} boundary points for n = {n} (d_n = {d_n:.6g}), more than n; "
        f"the smallest n that works for this polygon is {need}"
    )


def tplus(polygon: Polygon, n: int, *, spacing=(2.0, 3.0)) -> Mesh:
    """The paper's mesh T+ with exactly ``n`` Steiner points.

    Parameters
    ----------
    polygon : Polygon
    n : int
        Number of Steiner points (boundary and interior together).
    spacing : (float, float)
        (lo, hi): boundary gaps are at most hi·d_n; lo·d_n is the lower end the
        paper asks for, reported in ``info["gaps_within_spacing"]``.

    Returns
    -------
    Mesh
        ``info`` holds ``d_n``, ``k``, ``hypotheses`` (the three conditions of
        Theorem 2), ``theorem_applies``, ``gap_min``/``gap_max`` (in units of
        d_n) and ``w_last`` (w(p'_n), the last weight of phase 2).

    Raises
    ------
    InsufficientPointsError
        If phase 1 asks for more boundary points than n (the message names the
        smallest n that works, or, when even a lower bound on k over every n
        exceeds :data:`SEARCH_LIMIT`, the polygon's closest vertices).

    Examples
    --------
    >>> from uniform2d import Polygon, tplus
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> mesh = tplus(sq, 100)
    >>> mesh.n_steiner, len(mesh.points)
    (100, 104)
    >>> mesh.info["k"], mesh.info["theorem_applies"]
    (12, True)
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InsufficientPointsError(f"n must be a positive integer, got {n!r}")
    lo, hi = (float(s) for s in spacing)
    if not (0 < lo <= hi):
        raise InvalidArgumentError(f"spacing must be (lo, hi) with 0 < lo <= hi, got {spacing!r}")
    return _tplus(polygon, int(n), lo, hi, name_smallest=True)


def tplus_if_feasible(polygon: Polygon, n: int):
    """:func:`tplus` with the default spacing, or None where n is too small for it.

    For callers that only compare with T+ when there is one: the search for the
    smallest n that works, which :func:`tplus`'s error names, can cost many
    INSERT runs when phase 1 needs far more boundary points than n.
    """
    try:
        return _tplus(polygon, int(n), 2.0, 3.0, name_smallest=False)
    except InsufficientPointsError:
        return None


def _tplus(polygon: Polygon, n: int, lo: float, hi: float, *, name_smallest: bool) -> Mesh:
    d_n, bpts, on, m = _phase1(polygon, n, hi)
    k = int(m.sum() - len(m)) if bpts is None else len(bpts)
    if k > n:
        if not name_smallest:
            raise InsufficientPointsError(f"T+ needs {k} boundary points for n = {n}")
        raise _too_few(polygon, n, hi, d_n, k)
    # the boundary points are on their edges by construction: placed by index;
    # insert_on_edges checks the mesh (ensure_valid) before it returns it
    res2 = insert_on_edges(polygon, n - k, bpts, on)

    V = polygon.vertices
    E = polygon.constraint_edges
    L = np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T)
    gaps = L / m
    lVV = polygon.min_vertex_distance()
    # B: the length phase 2 places points on (Lemma 6 counts them by it)
    A, B = polygon.area, polygon.perimeter + float(L[len(polygon.edges):].sum())
    c = 2.0 if hi == 3.0 else (max(2.0, hi * hi / (hi * hi - 4.0)) if hi > 2 else math.inf)
    hyp = {
        "d_n <= l(V,V)/2": bool(d_n <= lVV / 2),
        "d_n <= A/(pi*B)": bool(d_n <= A / (math.pi * B)),
        f"n >= {c:g}k": bool(n >= c * k),
    }
    applies = hyp["d_n <= l(V,V)/2"] and n >= c * k and hi > 2
    info = {
        "method": "paper",
        "d_n": d_n,
        "k": k,
        "spacing": (lo, hi),
        "gap_min": float(gaps.min() / d_n),
        "gap_max": float(gaps.max() / d_n),
        "gaps_within_spacing": bool(
            np.all(gaps >= lo * d_n * (1 - 1e-12))
            and np.all(gaps <= hi * d_n * (1 + ratio_tolerance(polygon, d_n)))
        ),
        "w_last": float(res2.weights[-1]) if len(res2.weights) else float("nan"),
        "l(V,V)": lVV,
        "hypotheses": hyp,
        "n_over_k_required": c,
        "theorem_applies": applies,
        "edge_ratio_bound": 2 * hi if applies else None,
    }
    log.debug("tplus: n=%d d_n=%g k=%d theorem=%s", n, d_n, k, info["theorem_applies"])
    return Mesh(
        points=np.array(res2.mesh_points),
        triangles=np.array(res2.triangles),
        polygon=polygon,
        n_steiner=n,
        info=info,
    )
