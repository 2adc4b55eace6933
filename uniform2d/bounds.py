"""Lower bounds on the optimum of the paper's three problems, for one polygon and n.

Every function here returns a value that no triangulation of the polygon with
its vertices V and at most n further points can beat (the proofs are in the
docstrings and in the developers' guide, section 6).  :func:`uniform2d.quality`
turns them into certified factors.

The terms are plain ``(name, value, detail)`` triples; ``detail`` says where a
term comes from (which corner, how many boundary points) so that a report can
name the bound that is active.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .polygon import Polygon

__all__ = [
    "BOUND_SLACK",
    "Term",
    "triangle_ratio_floor",
    "corner_ratio_floor",
    "euler_ratio_floor",
    "lower_bound_terms",
    "is_convex",
]

log = logging.getLogger(__name__)

#: Every lower bound is lowered by this relative amount, far more than the
#: floating-point rounding in its evaluation, so rounding cannot lift a bound
#: above the true value it stands for.
BOUND_SLACK = 1e-9

_SQRT3 = math.sqrt(3.0)
_THIRD_PI = math.pi / 3.0

#: Above this many (candidate, polygon edge) pairs the ``sides`` term is skipped:
#: it is a refinement, and polygons with that many edges rarely need it.
_SIDES_WORK = 20_000_000


@dataclass(frozen=True)
class Term:
    """One term of a lower bound: its name, its value, and where it comes from."""

    name: str
    value: float
    detail: str = ""


# -- the edge ratio of one triangle, and of the triangles at a corner ----------
def triangle_ratio_floor(beta: float) -> float:
    """g(beta): the least longest/shortest side ratio of a triangle with an angle beta.

    ``beta`` in radians, in (0, pi).  g(beta) = min(2 cos beta, 1 / (2 sin(beta/2)))
    for beta <= 60 degrees and 2 sin(beta/2) above; g falls to 1 at 60 degrees and
    rises after.  Proof: put the angle between sides 1 >= t; the third side is
    c = sqrt(1 + t^2 - 2 t cos beta).  Above 60 degrees c >= t, so the ratio is
    at least c / t, which grows as t shrinks: at least its value 2 sin(beta/2)
    at t = 1.  Up to 60 degrees c <= 1, so the ratio is 1 / min(t, c); t = c at
    t* = 1 / (2 cos beta), below t* the minimum is t <= t*, above it c, whose
    square is convex in t, so min(t, c) <= max(t*, c(1)) = max(1 / (2 cos beta),
    2 sin(beta/2)).  The isosceles triangles with angles beta, beta and with
    apex beta reach the two values.
    """
    if beta >= _THIRD_PI:
        return 2.0 * math.sin(beta / 2.0)
    return min(2.0 * math.cos(beta), 1.0 / (2.0 * math.sin(beta / 2.0)))


def corner_ratio_floor(alpha: float) -> tuple[float, int]:
    """Least edge ratio of the triangles at a polygon corner of interior angle alpha.

    ``alpha`` in radians, in (0, 2 pi).  The k triangles at the corner split
    alpha, each taking less than pi, so k >= floor(alpha / pi) + 1; one of them
    has an angle <= alpha / k and one an angle >= alpha / k.  g decreases up to
    60 degrees and increases after, so if alpha / k <= 60 degrees the first has
    ratio >= g(alpha / k), otherwise the second does.  The corner forces
    min over admissible k of g(alpha / k); g(alpha / k) falls with k while
    alpha / k > 60 degrees and rises after, so the minimum is at one of the k
    next to alpha / 60 degrees, and a few more are tried to be safe against
    rounding in ``alpha / 60``.

    Returns
    -------
    (floor, k) : the floor and the number of triangles that reaches it.
    """
    k0 = int(math.floor(alpha / math.pi)) + 1
    k1 = max(k0, int(math.ceil(alpha / _THIRD_PI)) + 1)
    best = min((triangle_ratio_floor(alpha / k), k) for k in range(k0, k1 + 1))
    return best


#: g(360/7) and g(360/5): the least edge ratio around an interior vertex of
#: degree 7 and of degree 5 (every other degree but 6 forces more).
_G7 = 1.0 / (2.0 * math.sin(math.pi / 7.0))
_G5 = 2.0 * math.sin(math.pi / 5.0)
#: Triangles per corner tried by the ``euler`` term: a corner's floor is above
#: _G5 once alpha / k is below 50 degrees, and alpha < 360.
_K_MAX = 9


def euler_ratio_floor(alphas, n_holes: int) -> float:
    """The ``euler`` term: a floor on the edge ratio from counting triangles at vertices.

    In a mesh with edge ratio rho < g(72 deg) = 2 sin 36 deg every interior
    vertex has 6 or 7 triangles (d triangles round it split 360 degrees, so
    rho >= g(360 / d): 1.1524 for d = 7, 1.1756 for d = 5, more for the
    others), only 6 if rho < g(360/7), and every boundary point off the
    corners has 3 (2 or 4 force 1.414 or 1.307).  Counting triangle corners
    (3T) and Euler's formula (T = 2 N_i + N_b - 2 + 2h) give
    sum_i (d_i - 6) + sum_b (k_b - 3) = 6h - 6 over interior vertices i and
    boundary vertices b, so the numbers k_v of triangles at the polygon's
    corners must satisfy sum_v k_v = 3|V| + 6h - 6 (below g(360/7)), or
    sum_v k_v <= that (below g(72)), while g(alpha_v / k_v) <= rho at each.
    The term is the least rho for which such k_v exist, or g(72) if none does
    below it.  ``alphas`` are the interior angles (radians) of every vertex of
    every ring.
    """
    alphas = np.asarray(alphas, dtype=np.float64)
    target = 3 * len(alphas) + 6 * n_holes - 6
    G = np.full((len(alphas), _K_MAX + 1), np.inf)
    for k in range(1, _K_MAX + 1):
        ok = alphas < k * math.pi  # k triangles, each below 180 degrees
        G[ok, k] = [triangle_ratio_floor(a / k) for a in alphas[ok]]
    cand = np.unique(G[G < _G5])

    def feasible(rho):
        allowed = G <= rho * (1.0 + 1e-12)  # rounding may only widen the choice
        if not allowed.any(axis=1).all():
            return False
        ks = np.arange(_K_MAX + 1)
        lo = np.where(allowed, ks, _K_MAX + 1).min(axis=1).sum()
        hi = np.where(allowed, ks, -1).max(axis=1).sum()
        if rho >= _G7 * (1.0 - 1e-12):  # degree-7 vertices allowed: sum may fall short
            return lo <= target
        return lo <= target <= hi

    lo, hi = 0, len(cand)  # least index whose candidate is feasible (len: none)
    while lo < hi:
        mid = (lo + hi) // 2
        if feasible(cand[mid]):
            hi = mid
        else:
            lo = mid + 1
    below_g7 = cand[lo] if lo < len(cand) else math.inf
    # Feasibility only changes at a candidate or where the rule changes at g(360/7).
    if below_g7 > _G7 and feasible(_G7):
        return _G7
    return float(min(below_g7, _G5))


# -- helpers -----------------------------------------------------------------
def is_convex(polygon: Polygon) -> bool:
    """Convex without holes, segments or fixed points: where Lemma 9 (the packing
    terms) is proven."""
    if polygon.n_holes or polygon.has_constraints:
        return False
    r = polygon.outer  # counter-clockwise
    a = r - np.roll(r, 1, axis=0)
    b = np.roll(r, -1, axis=0) - r
    return bool((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] >= 0).all())


def _split_term(edges, n: int, t_max: int, K: float, c: float) -> tuple[float, int]:
    """The ``split`` term: min over l of max(c l, sqrt(K / (T_max - k(l)))).

    ``k(l) = sum(ceil(L_e / l) - 1)`` is the least number of boundary Steiner
    points that cut every polygon edge (lengths ``edges``) into pieces of at most
    ``l`` (infinite if it exceeds n).  Both parts are monotone in l, so the
    minimum is at the smallest l where ``c l`` reaches the other part; it is
    found by bisection, and the lower end of the final bracket is returned (a
    value at or below the minimum), with k at the upper end.
    """
    edges = np.asarray(edges, dtype=np.float64)

    def points_needed(ell):
        return int(np.maximum(np.ceil(edges / ell) - 1.0, 0.0).sum())

    def area_part(ell):
        k = points_needed(ell)
        return math.inf if k > n else math.sqrt(K / (t_max - k))

    hi = float(edges.max())
    if c * hi < area_part(hi):  # no boundary point helps: the area term itself
        return math.sqrt(K / t_max), 0
    lo = 0.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if c * mid >= area_part(mid):
            hi = mid
        else:
            lo = mid
    return c * lo, points_needed(hi)


def _sides_term(edges: np.ndarray, longest_lb: float) -> tuple[float, float]:
    """The ``sides`` term: min over L >= longest_lb of max_e L ceil(L_e / L) / L_e.

    A mesh with longest edge L cuts polygon edge e into at least ceil(L_e / L)
    pieces, the shortest at most L_e / ceil(L_e / L) long, so its edge ratio is
    at least L ceil(L_e / L) / L_e for every e.  Between the points
    L = L_e / c (c = 1, 2, ...) every part grows with L, and at those points it
    is continuous from the right, so the minimum over L >= longest_lb is at
    ``longest_lb`` or at one of them.  Returns the minimum and the L reaching it.
    """
    counts = np.floor(edges / longest_lb)
    if float(counts.sum()) * len(edges) > _SIDES_WORK:
        log.debug("sides term skipped: %d candidates", int(counts.sum()))
        return 1.0, longest_lb
    cand = [np.array([longest_lb])]
    for L_e, m in zip(edges, counts.astype(np.int64)):
        if m >= 1:
            cand.append(L_e / np.arange(1, m + 1, dtype=np.float64))
    cand = np.concatenate(cand)
    cand = cand[cand >= longest_lb]
    best, where = math.inf, longest_lb
    for chunk in np.array_split(cand, max(1, len(cand) * len(edges) // 2_000_000 + 1)):
        # Rounding may put L_e / L a hair above the integer it stands for; rounding
        # the count down instead can only lower the term.
        pieces = np.ceil(edges[None, :] / chunk[:, None] * (1.0 - 1e-12))
        h = (chunk[:, None] * pieces / edges[None, :]).max(axis=1)
        i = int(np.argmin(h))
        if h[i] < best:
            best, where = float(h[i]), float(chunk[i])
    if best <= 1.0 + 4 * BOUND_SLACK:  # the sides fit, up to rounding
        return 1.0, where
    return best, where


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _corner_term(polygon: Polygon) -> Term | None:
    """The highest corner floor over every vertex of every ring (None if none is above 1)."""
    best = None
    for i, alpha in enumerate(polygon.interior_angles()):
        floor, k = corner_ratio_floor(float(alpha))
        if best is None or floor > best[0]:
            best = (floor, k, i, float(alpha))
    floor, k, i, alpha = best
    if floor <= 1.0 + 4 * BOUND_SLACK:  # a multiple of 60 degrees, up to rounding: no floor
        return None
    x, y = polygon.vertices[i]
    return Term("corner", floor, f"{math.degrees(alpha):.4g} deg at ({_fmt(x)}, {_fmt(y)}), "
                                 f"best split in {k}")


# -- all terms -------------------------------------------------------------------
def lower_bound_terms(polygon: Polygon, n: int, d_n: float | None) -> dict[str, list[Term]]:
    """Every term of the three lower bounds (before the slack), for P, n and d_n.

    ``d_n`` is a packing distance (the least distance among V and some n points
    of P) or None; it is only used as given, so the caller decides whether the
    packing terms apply.  Returns ``{"longest_edge": [...], "max_perimeter": [...],
    "edge_ratio": [...]}``; every bound is the largest of its terms.
    """
    n_v = len(polygon.vertices)
    A, B = polygon.area, polygon.perimeter
    # Euler: T = 2 (interior vertices) + (boundary vertices) + 2h - 2, largest with
    # every Steiner point inside; segment vertices and fixed points not on a ring
    # are interior vertices, so they count twice
    t_max = 2 * n + n_v + (n_v - polygon.n_ring_vertices) + 2 * polygon.n_holes - 2
    pe = polygon.edges
    dv = polygon.vertices[pe[:, 1]] - polygon.vertices[pe[:, 0]]
    edges = np.hypot(dv[:, 0], dv[:, 1])
    per_edge = B / (n_v + n)

    longest = [Term("area", math.sqrt(4.0 * A / (_SQRT3 * t_max)), f"{t_max} triangles at most")]
    perimeter = [Term("area", math.sqrt(12.0 * _SQRT3 * A / t_max), f"{t_max} triangles at most")]
    if d_n is not None:
        longest.append(Term("packing", _SQRT3 / 2.0 * d_n, f"d_n = {_fmt(d_n)}"))
        perimeter.append(Term("packing", _SQRT3 * d_n, f"d_n = {_fmt(d_n)}"))
    longest.append(Term("boundary", per_edge, f"{n_v + n} boundary edges at most"))
    perimeter.append(Term("boundary", 2.0 * per_edge, f"{n_v + n} boundary edges at most"))
    for terms, K, c in ((longest, 4.0 * A / _SQRT3, 1.0), (perimeter, 12.0 * _SQRT3 * A, 2.0)):
        value, k = _split_term(edges, n, t_max, K, c)
        terms.append(Term("split", value, f"at {k} boundary points: {t_max - k} triangles at most"))

    longest_lb = max(t.value for t in longest)
    ratio = [Term("trivial", 1.0)]
    corner = _corner_term(polygon)
    if corner is not None:
        ratio.append(corner)
    euler = euler_ratio_floor(polygon.interior_angles(), polygon.n_holes)
    if euler > 1.0 + 4 * BOUND_SLACK:
        ratio.append(Term("euler", euler, "below it no split of the corners fits Euler's formula"))
    ratio.append(Term("boundary", longest_lb / float(edges.min()),
                      f"shortest polygon edge {_fmt(float(edges.min()))}"))
    sides, at = _sides_term(edges, longest_lb)
    ratio.append(Term("sides", sides, f"polygon edges cut at longest edge {_fmt(at)}"))
    return {"longest_edge": longest, "max_perimeter": perimeter, "edge_ratio": ratio}
