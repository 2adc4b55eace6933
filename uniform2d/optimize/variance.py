"""The last stage of a graded mesh: the CV of q lowered directly, the triangulation held.

The moves (:mod:`~uniform2d.optimize.moves`) lower a p-norm energy of the
objective, which weighs the extremes of q = length / h; once they stop, moving
the points can still lower the spread of q in the bulk.  :func:`lower_variance`
takes the mesh's edges as they are and minimises, over the free coordinates,

    CV(q)² = var(q) / mean(q)²,   q_e = |b - a| / h((a + b) / 2),

(a smooth function of the points while the edges stay the same) with
L-BFGS (:func:`lbfgs`) and the exact gradient (the field's bilinear interpolation
differentiated cell by cell), plus a penalty that keeps every log q within the
band [min q, max q] the mesh had, so that neither extreme (nor max q / min q)
grows.  Polygon vertices stay; a boundary point slides along its own polygon
edge; interior points move freely; the line search steps back from any point
where a triangle of the held triangulation would turn over (so points stay
inside P and in order along its edges).  The moved points are then
triangulated afresh (the exact constrained Delaunay triangulation,
:func:`uniform2d.triangulation.triangulate`); the result is kept only if the
CV of q of the new triangulation is lower and its max q / min q has not grown
by more than ``RATIO_SLACK``, else the input comes back unchanged.
"""

from __future__ import annotations

import math

import numpy as np

from .. import libm
from ..geometry import polygon_edges, unique_edges
from ..polygon import Polygon
from ..sizefield import SizeField
from ..triangulation import triangulate

__all__ = ["lower_variance", "lbfgs", "q_spread", "sliding_variables", "retriangulated", "areas",
           "ITERATIONS", "PENALTY", "RATIO_SLACK"]

#: L-BFGS iterations, at most, the pairs it keeps, its first step (in local
#: edge lengths), its sufficient-decrease constant and the step at which its
#: line search gives up.
ITERATIONS = 400
MEMORY = 10
FIRST_STEP = 0.01
ARMIJO = 1e-4
MIN_STEP = 1e-8
#: Weight of the band penalty on log q (relative to CV², a number near 0.004).
PENALTY = 1e3
#: The relative growth of max q / min q a result may have and be kept (the
#: penalty is soft: its optimum lies a hair outside the band).
RATIO_SLACK = 0.005


def q_spread(points, edges, field: SizeField) -> tuple[float, float]:
    """(CV of q, max q / min q) over ``edges`` (E, 2), q = length / field(midpoint).

    Examples
    --------
    >>> f = SizeField([0, 2], [0, 1], [[1.0, 1.0], [1.0, 1.0]])
    >>> cv, ratio = q_spread(np.array([(0, 0), (1, 0), (0, 2.0)]), np.array([(0, 1), (0, 2)]), f)
    >>> round(cv, 4), ratio
    (0.3333, 2.0)
    """
    p = np.asarray(points, dtype=np.float64)
    a, b = p[edges[:, 0]], p[edges[:, 1]]
    q = np.hypot(*(b - a).T) / field(0.5 * (a + b))
    return float(q.std() / q.mean()), float(q.max() / q.min())


def lower_variance(polygon: Polygon, points, triangles, edges, field: SizeField, *,
                   iterations: int = ITERATIONS):
    """Lower the CV of q of a mesh by moving its points, its edges held (see the module).

    Parameters
    ----------
    polygon : Polygon
    points : array_like, shape (|V| + k, 2)
        The polygon's vertices, then the sites.  Not modified.
    triangles : array_like, shape (M, 3)
        A valid triangulation of ``points`` (its edges are the ones measured).
    edges : array_like of int, shape (k,)
        The polygon edge (``polygon_edges(..., constraints=True)`` order) each
        site lies on, -1 inside.
    field : SizeField
        The size field (its scale does not matter).
    iterations : int
        L-BFGS iterations, at most.

    Returns
    -------
    points : ndarray, shape (|V| + k, 2)
    triangles : ndarray, shape (M', 3), int64
        The exact constrained Delaunay triangulation of the moved points, or
        the input's points and triangles if the stage did not lower the CV of q
        (the line search never lets a triangle of ``triangles`` turn over, so
        the moved points stay inside P, in order along its edges).
    info : dict
        ``kept`` (bool), ``cv`` and ``ratio`` before and after (the input's
        figures twice when not kept), ``iterations`` made.

    Examples
    --------
    >>> from uniform2d.triangulation import triangulate
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = SizeField([0, 1], [0, 1], [[1.0, 2.0], [1.0, 2.0]])
    >>> pts, tri = triangulate(sq, [(0.3, 0.3), (0.4, 0.7), (0.7, 0.5), (0.5, 0.0)])
    >>> p2, t2, info = lower_variance(sq, pts, tri, [-1, -1, -1, 0], f)
    >>> info["kept"], info["cv"][1] < info["cv"][0], len(p2) == len(pts)
    (True, True, True)
    """
    X0 = np.array(points, dtype=np.float64)
    T0 = np.asarray(triangles, dtype=np.int64)
    eid = np.asarray(edges, dtype=np.int64)
    E = unique_edges(T0, len(X0))
    before = q_spread(X0, E, field)
    fun, x0, unpack = _problem(polygon, X0, T0, E, eid, field)
    x, made = lbfgs(fun, x0, iterations)
    X = unpack(x)
    info = {"kept": False, "cv": (before[0], before[0]), "ratio": (before[1], before[1]),
            "iterations": made}
    moved = retriangulated(polygon, X, T0, eid)
    if moved is None:
        return X0, T0, info
    P2, T2 = moved
    after = q_spread(P2, unique_edges(T2, len(P2)), field)
    if after[0] < before[0] and after[1] <= before[1] * (1 + RATIO_SLACK):
        info.update(kept=True, cv=(before[0], after[0]), ratio=(before[1], after[1]))
        return P2, T2, info
    return X0, T0, info


def _dot(a, b) -> float:
    """a . b without BLAS: its threaded dot products neither add up the same way
    on every thread count (the mesh must not depend on it) nor stay fast on a
    loaded machine (16000-long ones took some 2 ms each there)."""
    return float(np.multiply(a, b).sum())


def retriangulated(polygon: Polygon, X, T0, eid):
    """(points, triangles): the exact constrained Delaunay triangulation of
    the points ``X`` (N, 2), moved with the triangulation ``T0`` held and
    the sites on the polygon edges ``eid``; None if a triangle of ``T0`` has
    turned over (or flat), the points then possibly outside P."""
    if not np.all(areas(X, T0) > 0):
        return None
    return triangulate(polygon, X[len(polygon.vertices):], eid)


def areas(X, T):
    """Twice the signed area of every triangle of T (M, 3) on the points X (N, 2), shape (M,)."""
    a, b, c = X[T[:, 0]], X[T[:, 1]], X[T[:, 2]]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def sliding_variables(polygon: Polygon, X0, eid, scale):
    """(start, unpack, pull) of the coordinates a stage moves with the triangulation held.

    Polygon vertices stay; a site with ``eid`` -1 has two variables, its
    coordinates in units of ``scale`` (one value per point, shape (N,)), a
    site on polygon edge ``eid`` one, its distance along that edge in units of
    its ``scale``.  ``unpack(x)`` gives the points (N, 2), ``pull(G)`` turns
    a gradient by the points (N, 2) into one by the variables.

    Examples
    --------
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> X0 = np.array([(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5), (0.25, 0.0)])
    >>> x0, unpack, pull = sliding_variables(sq, X0, np.array([-1, 0]), np.full(6, 0.5))
    >>> len(x0), bool(np.array_equal(unpack(x0), X0))
    (3, True)
    """
    nV = len(polygon.vertices)
    a, d, _ = polygon_edges(polygon, constraints=True)
    slide = eid >= 0
    free = np.flatnonzero(~slide) + nV
    sl = np.flatnonzero(slide) + nV
    e = eid[slide]
    cf = scale[free][:, None]
    Ld = np.hypot(d[e, 0], d[e, 1]) / scale[sl]
    t0 = ((X0[sl] - a[e]) * d[e]).sum(1) / (d[e] ** 2).sum(1)
    nf = len(free)

    def unpack(x):
        X = X0.copy()
        X[free] = x[: 2 * nf].reshape(-1, 2) * cf
        X[sl] = a[e] + (x[2 * nf:] / Ld)[:, None] * d[e]
        return X

    def pull(G):
        return np.concatenate([(G[free] * cf).ravel(), (G[sl] * d[e]).sum(1) / Ld])

    return np.concatenate([(X0[free] / cf).ravel(), t0 * Ld]), unpack, pull


def _problem(polygon: Polygon, X0, T0, E, eid, field):
    """(objective with gradient, start, unpack) of :func:`lower_variance`.
    Each site's variables are in units of the mean length of its edges (the
    graded mesh's local scale: L-BFGS's steps then suit the small and the large
    triangles alike; :func:`sliding_variables`).
    A point where a triangle of ``T0`` has turned over (or flat) has the value
    infinity, so that the line search steps back from it."""
    N, K = len(X0), len(E)
    L0 = np.hypot(*(X0[E[:, 1]] - X0[E[:, 0]]).T)
    ell = (np.bincount(E.ravel(), np.repeat(L0, 2), N)
           / np.maximum(np.bincount(E.ravel(), minlength=N), 1))
    x0, unpack, pull = sliding_variables(polygon, X0, eid, ell)

    def logq(X):
        dv = X[E[:, 1]] - X[E[:, 0]]
        L2 = (dv**2).sum(1)
        h, gh = field.with_gradient(0.5 * (X[E[:, 0]] + X[E[:, 1]]))
        return 0.5 * libm.log(L2) - libm.log(h), dv, L2, h, gh

    lq0 = logq(X0)[0]
    lo, hi = lq0.min(), lq0.max()

    def fun(x):
        X = unpack(x)
        if not np.all(areas(X, T0) > 0):
            return np.inf, None
        lq, dv, L2, h, gh = logq(X)
        q = libm.exp(lq)
        qm = q.mean()
        var = ((q - qm) ** 2).mean()
        over, under = np.maximum(lq - hi, 0.0), np.minimum(lq - lo, 0.0)
        F = var / qm**2 + PENALTY * ((over**2).sum() + (under**2).sum()) / K
        gp = 2 * PENALTY * (over + under) / K
        g = q * (2 * (q - qm) / K / qm**2 - 2 * var / qm**3 / K) + gp
        # d log q / d b = (b - a) / |b - a|² - grad h / (2 h), and for a the same with -(b - a)
        u, w = dv / L2[:, None], gh / (2 * h)[:, None]
        gb, ga = g[:, None] * (u - w), g[:, None] * (-u - w)
        G = np.stack([np.bincount(E[:, 0], ga[:, k], N) + np.bincount(E[:, 1], gb[:, k], N)
                      for k in range(2)], axis=1)
        return F, pull(G)

    return fun, x0, unpack


def lbfgs(fun, x, iterations: int, memory: int | None = None):
    """Minimise ``fun(x) -> (value, gradient)`` from ``x`` by L-BFGS with a
    backtracking (Armijo) line search: (x reached, iterations made).  The first
    step moves the variable of largest gradient by ``FIRST_STEP``; a value of
    infinity (a point ``fun`` excludes) makes the line search step back.

    Written here rather than taken from :func:`scipy.optimize.minimize`: its
    line searches do not step back from a value of infinity (the turned-over
    triangles this stage must exclude), and L-BFGS-B's bound handling cost
    more per iteration than the objective at these sizes.

    Examples
    --------
    >>> x, made = lbfgs(lambda x: (((x - 3.0) ** 2).sum(), 2 * (x - 3.0)), np.zeros(4), 50)
    >>> np.allclose(x, 3.0)
    True
    """
    memory = MEMORY if memory is None else int(memory)
    f, g = fun(x)
    S, Y, R = [], [], []  # steps, gradient changes, 1 / (y . s)
    for it in range(int(iterations)):
        r = g.copy()
        alphas = []
        for s, y, rho in zip(reversed(S), reversed(Y), reversed(R)):
            a = rho * _dot(s, r)
            r -= a * y
            alphas.append(a)
        if S:
            r *= 1.0 / (R[-1] * _dot(Y[-1], Y[-1]))
        else:
            r *= FIRST_STEP / max(float(np.abs(g).max()), 1e-300)
        for s, y, rho, a in zip(S, Y, R, reversed(alphas)):
            r += s * (a - rho * _dot(y, r))
        slope = -_dot(g, r)
        if not slope < 0:
            return x, it
        step = 1.0
        while True:
            xn = x - step * r
            fn, gn = fun(xn)
            if fn <= f + ARMIJO * step * slope:
                break
            step *= 0.5
            if step < MIN_STEP:
                return x, it
        s, y = xn - x, gn - g
        sy = _dot(s, y)
        x, f, g = xn, fn, gn
        if sy > 0:
            rho = 1.0 / sy
            if not 0.0 < rho * _dot(y, y) < math.inf:
                # the step's curvature is below rounding (y . y underflows) or
                # beyond range: the next direction would be zero or undefined
                return x, it + 1
            S.append(s)
            Y.append(y)
            R.append(rho)
            if len(S) > memory:
                del S[0], Y[0], R[0]
    return x, int(iterations)
