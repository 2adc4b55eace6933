"""A polish of a uniform mesh: its edge extremes lowered, the triangulation held.

The last stage of :func:`uniform2d.optimize.optimize_mesh` for meshes of up
to :data:`POLISH_MAX` points (docs/optimizer.md); :func:`polish_mesh`
polishes any uniform mesh made.  With the triangulation held, the
longest edge and the largest triangle perimeter are convex functions of the
free coordinates (maxima of norms and of sums of norms; a boundary point
sliding on its edge is a linear parametrisation).  :func:`polish_extremes`
minimises their smooth maxima (log-sum-exp, with its sharpness raised
through ``BETAS``) and that of minus the shortest edge, each over the mesh's
own value and in the proportions of the balanced objective (the longest edge
twice: it is in the edge ratio too), by L-BFGS
(:func:`uniform2d.optimize.variance.lbfgs`, the same variables as the graded
path's last stage, :func:`uniform2d.optimize.variance.sliding_variables`),
with penalties that keep every edge between the mesh's shortest and longest
edges, every perimeter below its largest, every angle above its worst angle
and the edge CV below its own.  The
moved points are triangulated afresh (the exact constrained Delaunay
triangulation); the result is kept only if none of the edge ratio, longest
edge, largest perimeter and edge CV got worse, the worst angle did not drop
and one of the first three got smaller; else the input comes back.
"""

from __future__ import annotations

import numpy as np

from .. import libm
from ..errors import InvalidArgumentError
from ..geometry import unique_edges
from ..mesh import Mesh
from ..polygon import Polygon
from ..quality import quality
from ..sites import site_edges
from .variance import areas, lbfgs, retriangulated, sliding_variables

__all__ = ["BETAS", "ITERATIONS", "PENALTY", "POLISH_MAX", "accumulate", "corner_angles", "kept_if", "measured", "mesh_parts",
           "polish_extremes", "polish_mesh"]

#: Meshes of up to POLISH_MAX points get the polish in
#: :func:`uniform2d.uniform_mesh` (its cost grows with the mesh, its gain does
#: not: at n = 1000 it would take longer than the whole optimiser).
POLISH_MAX = 600
#: Sharpness of the smooth maxima, raised in turn (each a run of L-BFGS from
#: where the last one stopped; one value: 300 then 1000 gains a tenth more
#: for twice the time).
BETAS = (1000.0,)
#: L-BFGS iterations per sharpness, at most.
ITERATIONS = 300
#: Weight of the penalties (the objective itself is near 4): a stiffer one
#: slows L-BFGS down (1e4 gained a fifth less in the same iterations), a
#: softer one ends outside the limits (300: the meshes of plate_zones at
#: n = 300 and of the bolt plate at 500 vertices were not kept).
PENALTY = 3000.0
#: The penalties hold the edges, the CV and the angles this far inside the
#: mesh's own limits (relative; the angles in radians): they are soft, and
#: their optimum lies a hair outside the limit they state.
LENGTH_MARGIN = 1e-3
CV_MARGIN = 1e-3
ANGLE_MARGIN = 1e-3
#: The angle penalty watches the corners within NEAR_ANGLE (radians) of the
#: worst angle at the start (the polish moves points by a fraction of a
#: percent of an edge; a corner it would take below the worst angle anyway
#: shows in the measures of the result, which is then not kept).
NEAR_ANGLE = 0.1


def _smooth_max(v, beta: float):
    """(log-sum-exp of ``beta * v`` over ``beta``, its gradient by ``v``)."""
    m = v.max()
    w = libm.exp(beta * (v - m))
    s = w.sum()
    return m + libm.log(s) / beta, w / s


def corner_angles(X, C):
    """The angle at the first point of every corner ``C`` (3M, 3) and its
    gradients by the three points, each (3M, 2)."""
    u = X[C[:, 1]] - X[C[:, 0]]
    w = X[C[:, 2]] - X[C[:, 0]]
    A = libm.arctan2(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0], (u * w).sum(axis=1))
    # the angle is arg(w) - arg(u); d arg(v) / dv = perp(v) / |v|²
    gw = np.stack([-w[:, 1], w[:, 0]], axis=1) / (w * w).sum(axis=1)[:, None]
    gu = -np.stack([-u[:, 1], u[:, 0]], axis=1) / (u * u).sum(axis=1)[:, None]
    return A, (-(gu + gw), gu, gw)


def accumulate(N: int, index, g):
    """Sum of the rows of ``g`` (m, 2) into (N, 2) by ``index`` (m,)."""
    return np.stack([np.bincount(index, g[:, 0], N), np.bincount(index, g[:, 1], N)], axis=1)


def mesh_parts(X, T):
    """The parts the polish and the CV stage build their objectives from: the
    mesh's edges E (K, 2) (:func:`uniform2d.geometry.unique_edges`), the edge of
    every triangle side TE (M, 3), the corners C (3M, 3) (each triangle three
    times, turned so that each point comes first once) and the edge lengths (K,)."""
    N = len(X)
    E = unique_edges(T, N)
    key = E[:, 0] * N + E[:, 1]

    def edge_of(i, j):
        return np.searchsorted(key, np.minimum(i, j) * N + np.maximum(i, j))

    TE = np.stack([edge_of(T[:, k], T[:, (k + 1) % 3]) for k in range(3)], axis=1)
    C = np.concatenate([T[:, [k, (k + 1) % 3, (k + 2) % 3]] for k in range(3)])
    return E, TE, C, np.hypot(*(X[E[:, 1]] - X[E[:, 0]]).T)


def _problem(polygon: Polygon, X0, T0, eid):
    """(``fun(x, beta)`` with gradient, start, unpack) of :func:`polish_extremes`."""
    N = len(X0)
    E, TE, C, L0 = mesh_parts(X0, T0)
    lmax, lmin, pmax = L0.max(), L0.min() * (1 + LENGTH_MARGIN), L0[TE].sum(axis=1).max()
    lcap, pcap = lmax * (1 - LENGTH_MARGIN), pmax * (1 - LENGTH_MARGIN)
    cv2 = (L0.std() / L0.mean() * (1 - CV_MARGIN)) ** 2
    A0 = corner_angles(X0, C)[0]
    amin = A0.min() + ANGLE_MARGIN
    # only the corners that can reach the worst angle by these small moves
    C = C[A0 < amin + NEAR_ANGLE]
    K = len(E)
    ends, corners = np.concatenate([E[:, 1], E[:, 0]]), C.T.ravel()
    x0, unpack, pull = sliding_variables(polygon, X0, eid, np.full(N, L0.mean()))

    def fun(x, beta):
        X = unpack(x)
        if not np.all(areas(X, T0) > 0):
            return np.inf, None
        dv = X[E[:, 1]] - X[E[:, 0]]
        L = np.hypot(dv[:, 0], dv[:, 1])
        P = L[TE].sum(axis=1)
        sL, wL = _smooth_max(L / lmax, beta)
        sP, wP = _smooth_max(P / pmax, beta)
        sS, wS = _smooth_max(-L / lmin, beta)
        above = np.maximum(P / pcap - 1, 0)
        # the balanced objective's proportions: the longest edge is in the ratio too
        gP = wP / pmax + 2 * PENALTY * above / pcap
        gl = 2 * wL / lmax - wS / lmin + np.bincount(TE.ravel(), np.repeat(gP, 3), K)
        under, over = np.minimum(L / lmin - 1, 0), np.maximum(L / lcap - 1, 0)
        F = 2 * sL + sS + sP + PENALTY * ((under**2).sum() + (over**2).sum() + (above**2).sum())
        gl += 2 * PENALTY * (under / lmin + over / lcap)
        m = L.mean()
        var = ((L - m) ** 2).mean()
        # powers of the mean as products: a float's ``**`` is libm's pow, not
        # always correctly rounded, and the mesh must scale by powers of two exactly
        spread = var / (m * m) / cv2 - 1
        if spread > 0:
            F += PENALTY * spread**2
            gl += 2 * PENALTY * spread / cv2 * (2 * (L - m) / K / (m * m) - 2 * var / (m * m * m) / K)
        gb = gl[:, None] * dv / L[:, None]
        G = accumulate(N, ends, np.concatenate([gb, -gb]))
        A, grads = corner_angles(X, C)
        low = np.minimum(A - amin, 0)
        if low.any():  # most points meet the angle floor: no term
            F += PENALTY * (low**2).sum()
            G += accumulate(N, corners, 2 * PENALTY * np.tile(low, 3)[:, None] * np.concatenate(grads))
        return F, pull(G)

    return fun, x0, unpack


def measured(points, triangles) -> tuple:
    """(edge ratio, longest edge, largest perimeter, edge CV, worst angle) of a
    mesh: what the polish and the CV stage hold or lower."""
    q = quality(points, triangles)
    return q.edge_ratio, q.longest_edge, q.max_perimeter, q.cv_edge, q.min_angle


def polish_extremes(polygon: Polygon, points, triangles, edges, *, iterations: int = ITERATIONS):
    """Lower the edge ratio, longest edge and largest perimeter of a mesh, its triangulation held.

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
        L-BFGS iterations per sharpness of :data:`BETAS`, at most.

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
    >>> pts, tri = triangulate(sq, [(0.45, 0.5), (0.5, 0.0), (1.0, 0.55), (0.5, 1.0), (0.0, 0.5)],
    ...                        [-1, 0, 1, 2, 3])
    >>> p2, t2, info = polish_extremes(sq, pts, tri, [-1, 0, 1, 2, 3])
    >>> info["kept"], info["after"][2] < info["before"][2], len(p2) == len(pts)
    (True, True, True)
    """
    X0, T0, eid, info = stage_input(points, triangles, edges)
    if iterations <= 0:
        return X0, T0, info
    fun, x, unpack = _problem(polygon, X0, T0, eid)
    for beta in BETAS:
        x, _ = lbfgs(lambda y, b=beta: fun(y, b), x, iterations)
    return kept_if(polygon, X0, T0, eid, unpack(x), info, _better)


def _better(after, before) -> bool:
    """No measure worse, and one of ratio, longest edge, largest perimeter lower."""
    no_worse = all(a <= b for a, b in zip(after[:4], before[:4])) and after[4] >= before[4]
    return no_worse and any(a < b for a, b in zip(after[:3], before[:3]))


def stage_input(points, triangles, edges) -> tuple:
    """(points, triangles, edges, info) as a stage that moves the points with
    the triangulation held starts: fresh arrays (the caller's are never
    changed) and ``info`` saying nothing kept yet, its ``before`` and
    ``after`` :func:`measured`'s tuple of the input."""
    X0 = np.array(points, dtype=np.float64)
    T0 = np.array(triangles, dtype=np.int64)
    before = measured(X0, T0)
    return X0, T0, np.array(edges, dtype=np.int64), {"kept": False, "before": before, "after": before}


def kept_if(polygon: Polygon, X0, T0, eid, X, info: dict, better) -> tuple:
    """(points, triangles, info) after a stage that moved the points ``X0`` of
    the mesh ``T0`` to ``X``: the exact constrained Delaunay triangulation of
    ``X`` if ``better(after, before)`` on :func:`measured`'s tuples (``info``
    then says ``kept`` and ``after``), else the input as it was."""
    moved = retriangulated(polygon, X, T0, eid)
    if moved is None:
        return X0, T0, info
    after = measured(*moved)
    if not better(after, info["before"]):
        return X0, T0, info
    return moved[0], moved[1], {**info, "kept": True, "after": after}


def polish_mesh(mesh: Mesh, *, iterations: int = ITERATIONS) -> Mesh:
    """:func:`polish_extremes` of a uniform :class:`~uniform2d.Mesh`: a new mesh
    (the same one if nothing was gained), its ``info`` the input's with
    ``polish``, the dict :func:`polish_extremes` returns.

    Raises :class:`~uniform2d.errors.InvalidArgumentError` for a graded mesh
    (its edges are measured against its size field, which the polish does not
    know).

    Examples
    --------
    >>> import uniform2d
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> m = uniform2d.uniform_mesh(sq, 60)
    >>> p = polish_mesh(m)
    >>> p.n_steiner == m.n_steiner, p.quality().max_perimeter <= m.quality().max_perimeter
    (True, True)
    """
    if mesh.size is not None:
        raise InvalidArgumentError(
            "polish_mesh polishes uniform meshes; this one follows a size field "
            "(graded: its last stage, uniform2d.optimize.variance, evens q instead)")
    nV = len(mesh.polygon.vertices)
    _, edges = site_edges(mesh.polygon, mesh.points[nV:])
    pts, tri, info = polish_extremes(mesh.polygon, mesh.points, mesh.triangles, edges,
                                     iterations=iterations)
    return Mesh(pts, tri, mesh.polygon, mesh.n_steiner, {**mesh.info, "polish": info})
