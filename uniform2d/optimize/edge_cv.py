"""The edge CV of a uniform mesh lowered, its extremes and worst angle held.

The descent's spread sweeps (:mod:`~uniform2d.optimize.moves`) stop short
of the lowest edge CV the triangulation allows.  :func:`lower_edge_cv` takes
the mesh's triangulation as it is and minimises the squared edge CV over the
free coordinates (the same variables as the polish,
:func:`uniform2d.optimize.variance.sliding_variables`: a boundary point
slides along its polygon edge) by a short run of L-BFGS
(:func:`uniform2d.optimize.variance.lbfgs`).  The mesh's extremes hold in
three ways:

* the points of the elements within ``HOLD`` of an extreme (edges near the
  longest or the shortest, triangles near the largest perimeter, corners
  near the worst angle) stay where they are: the extremes are often tied (a
  polygon side split evenly, a row of lattice edges), and no move of a point
  between two tied edges keeps both within the limit;
* the limits are walls: a point of the search where an edge is longer or
  shorter than the mesh's longest or shortest, a perimeter larger than its
  largest or a watched angle smaller than its worst has the value infinity,
  and the line search steps back from it (as from a triangle turned over);
* penalties, as the polish's (:mod:`~uniform2d.optimize.polish`), push the
  elements back from a margin inside those limits, so that the search seldom
  meets a wall (without them the line search stepped back so often that the
  stage took two to three times as long and gained less on ``star10``).

The moved points are triangulated afresh (the exact constrained Delaunay
triangulation); the result is kept only if its edge CV is lower and none of
the edge ratio, longest edge, largest perimeter and worst angle got worse;
else the input comes back.
"""

from __future__ import annotations

import numpy as np

from ..polygon import Polygon
# the polish's margins: both stages' penalties are soft in the same way
from .polish import (ANGLE_MARGIN, LENGTH_MARGIN, NEAR_ANGLE, accumulate, corner_angles, kept_if,
                     mesh_parts, stage_input)
from .schedule import SMALL
from .variance import areas, lbfgs, sliding_variables

__all__ = ["ITERATIONS", "PENALTY", "CV_STAGE_MIN", "CV_STAGE_MAX", "lower_edge_cv"]

#: The optimiser lowers the edge CV of meshes of more than CV_STAGE_MIN and up
#: to CV_STAGE_MAX points this way.  Meshes of up to 600 points get the polish
#: (:data:`uniform2d.optimize.polish.POLISH_MAX`), which leaves this stage
#: little (0.01-0.2 % of the CV at n = 300); at n = 1000 it would gain 0-7 %
#: for some 5 % more time, where the time is tight.
CV_STAGE_MIN = 1200
#: Above ``schedule.SMALL`` points the optimiser tries fewer starts and the
#: mesh costs less per point: there this stage would add 17-27 % of the CPU
#: time at n = 10000 (5-9 % at 1500 to 5000), where the speed goal is tight.
CV_STAGE_MAX = SMALL
#: L-BFGS iterations, at most.
ITERATIONS = 10
#: Weight of the penalties (the objective itself is near 1).
PENALTY = 3000.0
#: The points of the elements within HOLD (relative; the angles: in
#: radians) of an extreme stay where they are: the extremes are often tied (a
#: polygon side split evenly, a row of lattice edges) and no move of a point
#: between two tied edges keeps both within the limit.
HOLD = 1e-2


def _problem(polygon: Polygon, X0, T0, eid):
    """(``fun(x)`` with gradient, start, unpack) of :func:`lower_edge_cv`."""
    N = len(X0)
    E, TE, C, L0 = mesh_parts(X0, T0)
    lo, hi, top = L0.min(), L0.max(), L0[TE].sum(axis=1).max()
    lmin, lcap, pcap = lo * (1 + LENGTH_MARGIN), hi * (1 - LENGTH_MARGIN), top * (1 - LENGTH_MARGIN)
    cv2 = (L0.std() / L0.mean()) ** 2
    A0 = corner_angles(X0, C)[0]
    worst = A0.min()
    amin = worst + ANGLE_MARGIN
    held = np.zeros(N, dtype=bool)
    held[E[(L0 >= hi * (1 - HOLD)) | (L0 <= lo * (1 + HOLD))].ravel()] = True
    held[T0[L0[TE].sum(axis=1) >= top * (1 - HOLD)].ravel()] = True
    held[C[A0 <= worst + HOLD].ravel()] = True
    C = C[A0 < amin + NEAR_ANGLE]
    K = len(E)
    ends, corners = np.concatenate([E[:, 1], E[:, 0]]), C.T.ravel()
    x0, unpack, pull = _held_variables(polygon, X0, eid, np.full(N, L0.mean()), held)

    def fun(x):
        X = unpack(x)
        if not np.all(areas(X, T0) > 0):
            return np.inf, None
        dv = X[E[:, 1]] - X[E[:, 0]]
        L = np.hypot(dv[:, 0], dv[:, 1])
        P = L[TE].sum(axis=1)
        A, grads = corner_angles(X, C)
        if L.max() > hi or L.min() < lo or P.max() > top or (len(A) and A.min() < worst):
            return np.inf, None
        m = L.mean()
        var = ((L - m) ** 2).mean()
        above = np.maximum(P / pcap - 1, 0)
        under, over = np.minimum(L / lmin - 1, 0), np.maximum(L / lcap - 1, 0)
        # powers of the mean as products (see polish._problem: libm's pow)
        F = var / (m * m) / cv2 + PENALTY * ((under**2).sum() + (over**2).sum() + (above**2).sum())
        gl = ((2 * (L - m) / K / (m * m) - 2 * var / (m * m * m) / K) / cv2
              + 2 * PENALTY * (under / lmin + over / lcap)
              + np.bincount(TE.ravel(), np.repeat(2 * PENALTY * above / pcap, 3), K))
        gb = gl[:, None] * dv / L[:, None]
        G = accumulate(N, ends, np.concatenate([gb, -gb]))
        low = np.minimum(A - amin, 0)
        if low.any():
            F += PENALTY * (low**2).sum()
            G += accumulate(N, corners, 2 * PENALTY * np.tile(low, 3)[:, None] * np.concatenate(grads))
        return F, pull(G)

    return fun, x0, unpack


def _held_variables(polygon: Polygon, X0, eid, scale, held):
    """:func:`~uniform2d.optimize.variance.sliding_variables` without those of
    the points ``held`` (N,) bool, which stay at ``X0`` bit for bit."""
    nV = len(polygon.vertices)
    x_all, unpack_all, pull_all = sliding_variables(polygon, X0, eid, scale)
    free, slide = np.flatnonzero(eid < 0) + nV, np.flatnonzero(eid >= 0) + nV
    owner = np.concatenate([np.repeat(free, 2), slide])
    moving = ~held[owner]
    stay = np.flatnonzero(held)

    def unpack(x):
        y = x_all.copy()
        y[moving] = x
        X = unpack_all(y)
        X[stay] = X0[stay]
        return X

    def pull(G):
        return pull_all(G)[moving]

    return x_all[moving], unpack, pull


def lower_edge_cv(polygon: Polygon, points, triangles, edges, *, iterations: int = ITERATIONS):
    """Lower the edge CV of a uniform mesh, its extremes and worst angle held (see the module).

    Parameters
    ----------
    polygon : Polygon
    points : array_like, shape (|V| + k, 2)
        The polygon's vertices, then the sites.  Not modified.
    triangles : array_like, shape (M, 3)
        A valid triangulation of ``points`` (held while the points move).
    edges : array_like of int, shape (k,)
        The polygon edge (``polygon_edges(..., constraints=True)`` order) each
        site lies on, -1 inside (:func:`uniform2d.sites.site_edges` finds it).
    iterations : int
        L-BFGS iterations, at most.

    Returns
    -------
    points : ndarray, shape (|V| + k, 2)
    triangles : ndarray, shape (M', 3), int64
        The exact constrained Delaunay triangulation of the moved points, or
        the input's points and triangles if that is not better (module
        docstring).
    info : dict
        ``kept`` (bool); ``before`` and ``after``: (edge ratio, longest edge,
        largest perimeter, edge CV, worst angle), the same twice when not kept.

    Examples
    --------
    >>> from uniform2d.triangulation import triangulate
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> sites = [(0.3, 0.3), (0.7, 0.35), (0.5, 0.7), (0.5, 0.0), (1.0, 0.5),
    ...          (0.5, 1.0), (0.0, 0.5)]
    >>> pts, tri = triangulate(sq, sites, [-1, -1, -1, 0, 1, 2, 3])
    >>> p2, t2, info = lower_edge_cv(sq, pts, tri, [-1, -1, -1, 0, 1, 2, 3])
    >>> info["kept"], info["after"][3] < info["before"][3], len(p2) == len(pts)
    (True, True, True)
    """
    X0, T0, eid, info = stage_input(points, triangles, edges)
    if iterations <= 0:
        return X0, T0, info
    fun, x, unpack = _problem(polygon, X0, T0, eid)
    if not len(x):  # every point held
        return X0, T0, info
    x, _ = lbfgs(fun, x, iterations)
    return kept_if(polygon, X0, T0, eid, unpack(x), info, _better)


def _better(after, before) -> bool:
    """The edge CV lower, and none of the other measures worse."""
    return after[3] < before[3] and all(a <= b for a, b in zip(after[:3], before[:3])) \
        and after[4] >= before[4]
