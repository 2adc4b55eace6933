"""The ``lattice`` term of the edge-ratio bound: below 2 sin 36 degrees a mesh is a lattice patch.

For a polygon P without holes, segments or fixed points, and a mesh of P with
exactly N = |V| + n vertices.  The ``euler`` term (:func:`uniform2d.bounds.euler_ratio_floor`)
shows that in a mesh with edge ratio rho < g(72 deg) = 2 sin 36 deg every
inner vertex has 6 or 7 triangles, every boundary point off the corners 3,
and that the numbers k_v of triangles at the corners add up to 3|V| - 6 minus
the number of 7-vertices.  Where no choice of k_v allowed below the cap (each
with g(alpha_v / k_v) < cap) adds up to less than 3|V| - 6, there are no
7-vertices (cap = g(72 deg)); elsewhere the term only speaks below g(360/7)
(cap = g(360/7), where 7-vertices are not allowed).  Below the cap, then,
every inner vertex has 6 triangles: the mesh is a simply connected patch of
the triangular lattice.  Mapping each triangle onto a unit triangle of the
lattice, neighbour after neighbour (well defined: P is simply connected and
every inner vertex has 6), sends each polygon edge e, whose boundary points
all have 3 triangles, to a straight run of a_e lattice steps (a_e: the mesh
edges on e), turning by 180 - 60 k_v degrees at each corner v.  That closed
lattice path is the image of the disk under a map that is one to one near
every point and keeps orientation, so the mesh's T triangles are the signed
area inside the path in unit triangles, and Euler's formula
T = 2 N_i + N_b - 2 gives N = (T + B + 2) / 2 with B = sum a_e.

So a mesh with ratio rho below the cap has counts a_e (and k_v) such that the
lattice path closes and holds exactly N points; for those, its longest edge is
at least max_e L_e / a_e (some piece of e is at least the mean piece) and at
least sqrt(4 A / (sqrt 3 T)) (some triangle has area A / T), its shortest at
most min_e L_e / a_e, and each corner forces g(alpha_v / k_v).  The term is
the least of these floors over every such (k, a), or the cap if none has
exactly N points: for a regular hexagon, a lattice fits only for some N
(3m(m+1) + 1 points on a regular one, a few other counts on lattice hexagons
with sides within 2 sin 36 deg of each other), and at every other N the ratio
is at least 1.1756.  Unlike the other terms, this one holds for exactly n
Steiner points, not at most n: :func:`uniform2d.quality` uses it only for a
mesh with exactly that many points.

The counts are enumerated: mean pieces within a factor cap of each other
bound each a_e by the first free edge's count a_r, and
4 A / (sqrt 3 T) <= (cap L_r / a_r)^2 with T < 2N bounds a_r; two edges of
independent lattice directions are solved from the path's closure (their
2x2 system has determinant 1).  Polygons with more than :data:`MAX_EDGES`
edges, or whose enumeration would exceed :data:`WORK` candidates, get no term.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from .bounds import Term, triangle_ratio_floor
from .polygon import Polygon

__all__ = ["lattice_ratio_floor", "lattice_count", "MAX_EDGES", "WORK"]

#: g(72 deg) and g(360/7 deg): below the first no inner vertex has 5 triangles,
#: below the second none has 7.
G5 = 2.0 * math.sin(math.pi / 5.0)
G7 = 1.0 / (2.0 * math.sin(math.pi / 7.0))
#: Polygons with more edges get no term (the enumeration grows with the edges).
MAX_EDGES = 8
#: Candidate count vectors enumerated at most (else no term).
WORK = 3_000_000
#: The six lattice steps in the basis (1, 0), (1/2, sqrt(3)/2), counter-clockwise.
STEPS = np.array([(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)], dtype=np.int64)
#: Triangles per corner tried: below g(72) a corner's triangles have angles above 50 degrees.
_K_MAX = 9


def lattice_count(a, k) -> tuple[int, int]:
    """(points N, triangles T) of the lattice polygon whose side e has ``a[e]``
    steps and that turns by 180 - 60 ``k[v]`` degrees at the start of side v
    (``k[0]``: between the last side and the first); raises ValueError if it
    does not close.

    >>> lattice_count([1] * 6, [2] * 6), lattice_count([2] * 6, [2] * 6)
    ((7, 6), (19, 24))
    """
    a, k = np.asarray(a, np.int64), np.asarray(k, np.int64)
    t = np.concatenate([[0], np.cumsum(3 - k[1:])]) % 6
    corners = np.cumsum(a[:, None] * STEPS[t], axis=0)
    if corners[-1].any():
        raise ValueError(f"the lattice path of sides {a.tolist()} does not close")
    x, y = corners[:, 0], corners[:, 1]
    T = int((x * np.roll(y, -1) - np.roll(x, -1) * y).sum())
    return (T + int(a.sum()) + 2) // 2, T


def _allowed(alphas, cap: float) -> list[list[int]]:
    """Per corner, the triangle counts k with g(alpha / k) below ``cap`` (rounding
    may only widen the choice)."""
    return [[k for k in range(int(a // math.pi) + 1, _K_MAX + 1)
             if triangle_ratio_floor(a / k) < cap * (1.0 + 1e-12)] for a in alphas]


def _cap_and_splits(alphas):
    """(cap, the corner splits k allowed below it that add up to 3|V| - 6), or
    None if some corner allows none below g(72) (the corner term is that high)."""
    target = 3 * len(alphas) - 6
    cap, allowed = G5, _allowed(alphas, G5)
    if any(not s for s in allowed):
        return None
    if sum(min(s) for s in allowed) < target:  # 7-vertices possible below g(72)
        cap, allowed = G7, _allowed(alphas, G7)
        if any(not s for s in allowed):
            return None
    return cap, [ks for ks in itertools.product(*allowed) if sum(ks) == target]


def _solver(D):
    """Two sides (i, j) of independent lattice directions and the integer
    inverse of [D_i D_j] (determinant +-1 for any two of the six steps)."""
    E = len(D)
    for i, j in sorted(itertools.combinations(range(E), 2), key=lambda p: (-p[0] - p[1], p)):
        det = D[i, 0] * D[j, 1] - D[i, 1] * D[j, 0]
        if det:
            inv = np.array([[D[j, 1], -D[j, 0]], [-D[i, 1], D[i, 0]]], dtype=np.int64) * det
            return i, j, inv
    return None


def _split_floor(L, A: float, N: int, cap: float, ks, budget: list):
    """The least floor over the side counts a closing the lattice path of the
    corner split ``ks`` with exactly N points (module docstring), cap if none;
    None if the enumeration would exceed ``budget[0]``."""
    E = len(L)
    k = np.asarray(ks, np.int64)
    D = STEPS[np.concatenate([[0], np.cumsum(3 - k[1:])]) % 6]
    solved = _solver(D)
    if solved is None:
        return cap
    i, j, inv = solved
    free = [e for e in range(E) if e not in (i, j)]
    r = free[0]
    a_top = int(cap * L[r] * math.sqrt(2.0 * N * math.sqrt(3.0) / (4.0 * A))) + 1

    def window(a_r):
        return [np.arange(a_r, a_r + 1)] + [
            np.arange(max(1, math.floor(a_r * L[e] / (L[r] * cap))),
                      math.ceil(a_r * L[e] * cap / L[r]) + 1) for e in free[1:]]

    budget[0] -= sum(math.prod(len(x) for x in window(a_r)) for a_r in range(1, a_top + 1))
    if budget[0] < 0:  # counted before any is enumerated: a refusal costs nothing
        return None
    best = cap
    for a_r in range(1, a_top + 1):
        ranges = window(a_r)
        grid = np.stack([g.ravel() for g in np.meshgrid(*ranges, indexing="ij")], axis=1)
        S = grid @ D[free]
        sol = -(S @ inv.T)  # rows: (a_i, a_j)
        ok = (sol > 0).all(axis=1)
        if not ok.any():
            continue
        a = np.zeros((int(ok.sum()), E), np.int64)
        a[:, free] = grid[ok]
        a[:, [i, j]] = sol[ok]
        corners = np.cumsum(a[:, :, None] * D[None], axis=1)
        x, y = corners[..., 0], corners[..., 1]
        T = (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1)
        hit = (T > 0) & ((T + a.sum(axis=1) + 2) == 2 * N)
        if not hit.any():
            continue
        piece = L[None, :] / a[hit]
        floor = np.maximum(piece.max(axis=1), np.sqrt(4.0 * A / (math.sqrt(3.0) * T[hit])))
        best = min(best, float((floor / piece.min(axis=1)).min()))
    return best


def lattice_ratio_floor(polygon: Polygon, n: int) -> Term | None:
    """The ``lattice`` term for meshes of P with exactly n Steiner points (module
    docstring), or None where it does not apply (holes, segments, fixed points,
    more than :data:`MAX_EDGES` edges, a corner that allows no split below
    2 sin 36 deg, or too large an enumeration).

    >>> import math
    >>> hexagon = Polygon([(math.cos(i * math.pi / 3), math.sin(i * math.pi / 3)) for i in range(6)])
    >>> round(lattice_ratio_floor(hexagon, 331 - 6).value, 6)   # 331 = 3*10*11 + 1: the lattice fits
    1.0
    >>> round(lattice_ratio_floor(hexagon, 300).value, 4)   # no lattice patch has 306 points
    1.1756
    """
    if polygon.n_holes or polygon.has_constraints or len(polygon.vertices) > MAX_EDGES:
        return None
    alphas = [float(x) for x in polygon.interior_angles()]
    made = _cap_and_splits(alphas)
    if made is None:
        return None
    cap, splits = made
    V = polygon.vertices
    L = np.hypot(*(np.roll(V, -1, axis=0) - V).T)
    N = len(V) + int(n)
    best, budget = cap, [WORK]
    for ks in splits:
        corner = max(triangle_ratio_floor(a / kv) for a, kv in zip(alphas, ks))
        if corner >= best:
            continue
        value = _split_floor(L, polygon.area, N, cap, ks, budget)
        if value is None:
            return None
        best = min(best, max(value, corner))
    detail = (f"no lattice patch of {N} points below {cap:.6g}" if best >= cap
              else f"a lattice patch of {N} points, its sides cut evenly")
    return Term("lattice", best, detail)
