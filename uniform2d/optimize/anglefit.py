"""The optimiser's last step: the worst angles raised together, the edges held.

:func:`~uniform2d.optimize.angles.raise_worst_angle` and the shift
(:mod:`~uniform2d.optimize.shift`) move one point at a time; where the worst
triangles sit side by side (``star10`` at n = 300: six of them within 1.5
degrees along the reflex corners) no single move raises the worst angle, since
every move that mends one triangle worsens its neighbour.  :func:`fit_worst_angle`
moves the points of a whole neighbourhood at once: the points of the triangles
whose smallest angle is within ``BAND`` degrees of the worst, and their
neighbours, are placed (interior points freely, boundary points along their
edge) so that the smallest angle ``t`` of the triangles around them is largest
(sequential quadratic programming, :func:`scipy.optimize.minimize` SLSQP), with
the mesh's edges as constraints: no edge longer than the longest edge or
shorter than the shortest one, no perimeter above the largest, and the spread
of the moved edges about the mesh's mean edge length not larger than before.
The program states first only the constraints near binding at its start
(:data:`NEAR_ANGLE`, :data:`NEAR_LENGTH`), and all of them only where its
result breaks one left out.  The moved points are triangulated afresh (the exact constrained Delaunay
triangulation) and the round is kept only if the worst angle rose by
``MIN_GAIN`` and none of the edge ratio, longest edge and largest perimeter
grew and the edge CV grew by at most ``CV_SLACK``.

Where the worst angle is still poor-ish after that (below
:data:`~uniform2d.optimize.angles.ANGLE_FINE`), the worst angle comes first:
*loose* rounds may give those limits a little each (:data:`LOOSE_STEP`), at a
price the program pays against the angle (:data:`GIVE_COST`), so that a
limit gives only as far as the angle needs; within a budget over the mesh
they start from (:data:`LOOSE_BUDGET`), until the worst angle reaches
:data:`ANGLE_GOOD`, or the angle a mesh of the target size is forced to at
its worst triangle if less (:func:`~uniform2d.optimize.angles.forced_angle`: next to a piece of P much
shorter than the size).  A finite-element user's mesh is not to be worse in
its worst angle than a frontal mesher's of the same count, whose edges are
less even than the loose rounds leave ours.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize
from threadpoolctl import threadpool_limits

from ..geometry import polygon_edges, unique_edges
from ..polygon import Polygon
from ..quality import quality
from ..triangulation import triangulate
from .angles import (ANGLE_FINE, ANGLE_POOR, ANGLES_MAX, MIN_GAIN, angle_corners, angles_and_gradients,
                     forced_angle, min_angles, worth_its_edges)

__all__ = ["ANGLE_GOOD", "BAND", "CV_SLACK", "FIT_BELOW", "FIT_MAX", "FIT_MIN", "GIVES",
           "GIVE_COST", "GIVE_UNIT", "LOOSE_BUDGET", "LOOSE_ROUNDS", "LOOSE_STEP", "REGION_MAX",
           "ROUNDS", "WIDE_BAND", "fit_worst_angle", "loosen_worst_angle"]

#: Meshes whose worst angle is FIT_BELOW degrees or more are left as they are
#: (as for the shift: Gmsh's worst angles on the benchmark polygons at n = 300
#: are 40.6 to 43.7 degrees).
FIT_BELOW = 44.0
#: Meshes of more than FIT_MAX points are left as they are (each round
#: triangulates the whole mesh again; the region's program grows with the
#: triangles near the worst angle), unless their worst angle is below
#: ANGLE_GOOD degrees: those are fitted up to ANGLES_MAX points.  A peer's
#: frontal mesh of a uniform size has worst angles of 36 to 44 degrees on the
#: benchmark, constrained and bolt-plate cases (bench_angles,
#: bench_constrained); the benchmark polygons' meshes at n = 1000 to 5000,
#: 41 to 49 degrees, are not fitted (the time of an everyday mesh).
FIT_MAX = 1000
ANGLE_GOOD = 40.0
#: Above FIT_MAX points a round whose region has more than REGION_MAX free
#: points is not made: the program's time grows with the cube of its
#: variables and more when it finds no feasible rise (the bolt plate at 8000
#: points: 305 free points 0.36 s, 406 2.7 s; a resampled outline at 2000
#: points, ``triangle_A`` of bench_real: 199 free points 1.2 s for no round
#: kept).  ``plate_zones`` at n = 1000 has 51 to 79.
REGION_MAX = 100
#: Meshes of fewer than FIT_MIN sites are left as they are (the region is
#: then the whole mesh).
FIT_MIN = 50
#: Triangles within BAND degrees of the worst angle, their points and those
#: points' neighbours, make the region moved: on star10 at n = 300 a band of
#: 1.5 or 3 degrees stops at 42.99 degrees (a neighbour outside holds it), 4
#: reaches 43.6 in one round.
BAND = 4.0
#: Rounds, at most (each a program and a fresh triangulation; they stop once
#: the worst angle reaches FIT_BELOW).
ROUNDS = 3
#: The program's goal for a round, in degrees above the worst angle: a
#: program without one pushes t on until its iterations run out, and its last
#: iterate then need not meet the constraints.
RISE = 1.0
#: Iterations of the program, at most: the rounds kept on the benchmark
#: polygons converged in 3 to 11; a round that runs on has found no feasible
#: rise (star10 at n = 200: its third round ran 60, 72 s on a loaded machine,
#: and was not kept).
ITERATIONS = 15
#: How far a point may move, as a fraction of the region's shortest edge (a
#: trust region: the angles are smooth only while no triangle turns).
REACH = 0.3
#: The relative growth of the edge CV a round may cost (the spread of the
#: moved edges is held about the old mean length, which itself moves a
#: little).
CV_SLACK = 1e-3
#: The program states first only the constraints near binding at its start:
#: the angles within NEAR_ANGLE degrees of the worst, the edges and perimeters
#: within the fraction NEAR_LENGTH of their limit (SLSQP's time grows with
#: the constraints times the variables squared); where its result breaks one
#: left out, the program with all of them runs instead.
NEAR_ANGLE = 10.0
NEAR_LENGTH = 0.05
#: A mesh of up to FIT_MAX points whose worst angle is still below ANGLE_FINE
#: degrees (or below its forced angle if less, :func:`~uniform2d.optimize.angles.forced_angle`, but at
#: least ANGLE_POOR) after the rounds above (the edges held) gets up to
#: LOOSE_ROUNDS more (:func:`loosen_worst_angle`) in which the worst angle
#: comes first, until it reaches ANGLE_GOOD (or that forced angle if less):
#: held rounds in a wider region while they gain (WIDE_BAND), then rounds
#: that may lengthen the longest edge and the largest perimeter, shorten the
#: shortest edge and widen the spread by the fraction LOOSE_STEP each, at a
#: price (GIVE_COST), and all of them together never by more than
#: LOOSE_BUDGET over the mesh they started from; of the rounds made, the last
#: whose mesh is worth its edges against the start's is kept
#: (:func:`~uniform2d.optimize.angles.worth_its_edges`: 1 %, or 2 % a degree
#: gained if more).  ``mixed`` of bench_constrained at n = 300: 31.1 -> 39.4
#: degrees (Gmsh 38.7), the edge ratio 2.41 -> 2.55 (Gmsh 2.99).
LOOSE_ROUNDS = 20
LOOSE_STEP = 0.01
LOOSE_BUDGET = 0.25
#: The constraints are met with this relative margin, so that rounding in the
#: program's last step cannot lengthen the longest edge.
MARGIN = 1e-9
#: A loose round's program has a variable for each kind of limit (the
#: longest edge, the shortest, the largest perimeter, the spread: GIVES), the
#: fraction it gives, in units of GIVE_UNIT (of order one, as SLSQP wants its
#: variables), and maximises the worst angle less GIVE_COST degrees for each
#: whole give (5: 0.05 degrees for 1 %, so the angle still comes first, up to
#: its RISE, and no limit gives where the angle does not need it).  Without a
#: price the program left every limit at its most (``mixed`` at n = 300, the
#: same 39.4 degrees: edge ratio 2.77 against 2.60; 20: the rounds stop at 31.1,
#: 50 with WIDE_BAND at 31.2).
GIVES = 4
GIVE_UNIT = 0.01
GIVE_COST = 5.0
#: The loose rounds are held ones first, while they gain, in a region of the
#: triangles within WIDE_BAND degrees of the worst (``mixed`` at n = 300: the
#: held rounds of BAND stop at 31.1 degrees, of WIDE_BAND go on to 35.0, the
#: edges as they were); the rounds that give their limits have BAND (wider,
#: each program costs more than it saves).
WIDE_BAND = 8.0


def _region(points, triangles, nV, band: float = BAND):
    """(free points, the triangles they touch, the edges they touch): the
    region of the round (module docstring), of the triangles within ``band``
    degrees of the worst."""
    ang = min_angles(points, triangles)
    near = np.unique(triangles[ang < ang.min() + band])
    near = np.unique(triangles[np.isin(triangles, near).any(axis=1)])
    free = near[near >= nV]
    touched = triangles[np.isin(triangles, free).any(axis=1)]
    e = unique_edges(touched)
    return free, touched, e[np.isin(e, free).any(axis=1)]


def _jacobian_map(points, free, edges, nV, d, unit):
    """(D, reach): ``D`` (N, 2, k) the derivative of every point by the k
    variables (interior points two, moves in ``unit``s; boundary points one,
    along the edge vector ``d``), and the variables' bounds for a reach of
    one length unit."""
    k = int(sum(1 if edges[v - nV] >= 0 else 2 for v in free))
    D = np.zeros((len(points), 2, k))
    reach = []
    col = 0
    for v in free:
        e = edges[v - nV]
        if e < 0:
            D[v, 0, col] = D[v, 1, col + 1] = unit
            reach += [1.0 / unit, 1.0 / unit]
            col += 2
        else:
            D[v, :, col] = d[e]
            reach.append(1.0 / float(np.hypot(*d[e])))
            col += 1
    return D, np.array(reach)


def _rows(points, T, E, limits, t0, near: bool):
    """The constraints the program states: (angle rows into
    :func:`~uniform2d.optimize.angles.angle_corners` of T, edges held below the longest, edges held above the shortest,
    triangles whose perimeter is held).  With ``near`` only those near
    binding at the start (module docstring: :data:`NEAR_ANGLE`,
    :data:`NEAR_LENGTH`); else all."""
    lmax, lmin, pmax, _, _ = limits
    corners = np.arange(3 * len(T))
    if not near:
        return corners, E, E, T
    q = points[T]
    A, _ = angles_and_gradients(q)
    L = np.hypot(*(points[E[:, 0]] - points[E[:, 1]]).T)
    per = np.hypot(*(q - q[:, [1, 2, 0]]).transpose(2, 0, 1)).sum(axis=1)
    return (corners[A <= t0 + NEAR_ANGLE], E[L >= lmax * (1 - NEAR_LENGTH)],
            E[L <= lmin * (1 + NEAR_LENGTH)], T[per >= pmax * (1 - NEAR_LENGTH)])


def _program(points, T, E, D, limits, rows=None, give: bool = False):
    """(place, constraints, their Jacobian) of the program in the variables x
    (the moves, then t): every angle of T at least t, the edges E and
    perimeters of T within ``limits`` = (longest, shortest, largest
    perimeter, mean length, spread), all scaled to be of order one.
    ``rows``: :func:`_rows`, the angles, edges and perimeters stated (all
    if None; the spread is of every edge of E).  With ``give`` (a loose
    round) a variable g stands before t: the limits are given the fraction
    g (the longest edge and perimeter times 1 + g, the shortest edge over
    it, the spread times its square)."""
    lmax, lmin, pmax, mean, spread = limits
    angle_rows, E_hi, E_lo, T_per = rows if rows is not None else (None, E, E, T)
    corners = angle_corners(T) if angle_rows is None else angle_corners(T)[angle_rows]
    s = 100.0 / lmax
    k = D.shape[2]
    extra = 1 + GIVES * give  # variables after the moves

    def place(x):
        return points + np.einsum("nck,k->nc", D, x[:k])

    def through(idx, g):  # gradients by points (m, j, 2) -> by the variables (m, k)
        return np.einsum("mjc,mjck->mk", g, D[idx])

    def lengths(P, edges):
        return np.hypot(*(P[edges[:, 0]] - P[edges[:, 1]]).T)

    def fun(x):
        P = place(x)
        q = P[T]
        A, _ = angles_and_gradients(q)
        if angle_rows is not None:
            A = A[angle_rows]
        L = lengths(P, E)
        qp = P[T_per]
        per = np.hypot(*(qp - qp[:, [1, 2, 0]]).transpose(2, 0, 1)).sum(axis=1)
        # 1.0: the held limits exactly
        gh, gl, gp, gs = 1.0 + x[k:k + GIVES] * GIVE_UNIT if give else (1.0, 1.0, 1.0, 1.0)
        return np.concatenate([A - x[-1], (lmax * gh - lengths(P, E_hi)) * s,
                               (lengths(P, E_lo) - lmin / gl) * s, (pmax * gp - per) * s,
                               [(spread * gs * gs - ((L - mean) ** 2).sum()) * s * s]])

    def length_gradients(P, edges):
        dE = P[edges[:, 0]] - P[edges[:, 1]]
        u = dE / np.hypot(*dE.T)[:, None]
        return through(edges, np.stack([u, -u], axis=1))

    def jac(x):
        P = place(x)
        q = P[T]
        _, gA = angles_and_gradients(q)
        if angle_rows is not None:
            gA = gA[angle_rows]
        JA = np.concatenate([through(corners, gA), np.zeros((len(corners), extra - 1)),
                             -np.ones((len(corners), 1))], axis=1)
        L = lengths(P, E)
        gL = length_gradients(P, E)
        qp = P[T_per]
        side = qp - qp[:, [1, 2, 0]]
        unit = side / np.hypot(*side.transpose(2, 0, 1))[..., None]
        gP = through(T_per, unit - unit[:, [2, 0, 1]])
        gS = np.einsum("m,mk->k", 2.0 * (L - mean), gL)[None]
        rest = np.concatenate([-length_gradients(P, E_hi) * s, length_gradients(P, E_lo) * s,
                               -gP * s, -gS * s * s])
        cols = [rest]
        if give:  # the rows' derivatives by the gives, one for each kind of row
            gl, gs = 1.0 + x[k + 1] * GIVE_UNIT, 1.0 + x[k + 3] * GIVE_UNIT
            G = np.zeros((len(rest), GIVES))
            ends = np.cumsum([len(E_hi), len(E_lo), len(T_per), 1])
            G[:ends[0], 0] = lmax * s * GIVE_UNIT
            G[ends[0]:ends[1], 1] = lmin / (gl * gl) * s * GIVE_UNIT
            G[ends[1]:ends[2], 2] = pmax * s * GIVE_UNIT
            G[ends[2], 3] = 2.0 * spread * gs * s * s * GIVE_UNIT
            cols.append(G)
        cols.append(np.zeros((len(rest), 1)))
        return np.concatenate([JA, np.concatenate(cols, axis=1)])

    return place, fun, jac


def _fit(polygon, points, triangles, edges, a, d, slack: float = 0.0, band: float = BAND):
    """The sites after one round's program (None if the region is empty, or
    too large: :data:`REGION_MAX`); ``slack``: the fraction each kind of
    limit may give, at a price (a loose round: :data:`GIVE_COST`); ``band``:
    the region's (:func:`_region`)."""
    nV = len(polygon.vertices)
    free, T, E = _region(points, triangles, nV, band)
    if len(free) == 0 or (len(points) > FIT_MAX and len(free) > REGION_MAX):
        return None
    q = points[triangles]
    L_all = np.hypot(*(q - q[:, [1, 2, 0]]).transpose(2, 0, 1))
    all_edges = unique_edges(triangles)
    mean = float(np.hypot(*(points[all_edges[:, 0]] - points[all_edges[:, 1]]).T).mean())
    L = np.hypot(*(points[E[:, 0]] - points[E[:, 1]]).T)
    limits = (L_all.max() * (1 - MARGIN), L_all.min() * (1 + MARGIN),
              L_all.sum(axis=1).max() * (1 - MARGIN), mean,
              ((L - mean) ** 2).sum() * (1 - MARGIN))
    # moves in a power of two near the longest edge: the program's numbers,
    # and so the mesh, scale exactly with a power-of-two scaling of P
    unit = float(np.ldexp(1.0, int(np.frexp(limits[0])[1])))
    D, reach = _jacobian_map(points, free, edges, nV, d, unit)
    step = REACH * float(L.min())
    loose = bool(slack)
    x0 = np.zeros(D.shape[2] + 1 + GIVES * loose)
    x0[-1] = float(min_angles(points, T).min())
    bounds = ([(-step * r, step * r) for r in reach] + [(0.0, slack / GIVE_UNIT)] * (GIVES * loose)
              + [(None, x0[-1] + RISE)])
    # first the constraints near binding alone, then, if the result breaks one
    # left out, all of them
    for near in (True, False):
        rows = _rows(points, T, E, limits, x0[-1], near)
        place, fun, jac = _program(points, T, E, D, limits, rows, loose)
        res = _solve(x0, bounds, fun, jac, loose)
        if not near or _meets_all(_program(points, T, E, D, limits, None, loose)[1], fun, res.x):
            break
    P = place(res.x)
    for v in free[edges[free - nV] >= 0]:  # on its edge as the kernel places a sliding point
        e = edges[v - nV]
        r, de = P[v] - a[e], d[e]  # dot products written out: ``@`` is BLAS, per CPU
        P[v] = a[e] + ((r[0] * de[0] + r[1] * de[1]) / (de[0] * de[0] + de[1] * de[1])) * de
    return P[nV:]


def _solve(x0, bounds, fun, jac, loose: bool):
    """SLSQP's result for the program (:func:`_program`): t largest, less
    the gives' price in a loose round."""
    price = GIVE_COST * GIVE_UNIT
    if loose:
        def goal(x):
            return float(x[-1 - GIVES:-1].sum() * price - x[-1])

        grad = np.zeros(len(x0))
        grad[-1 - GIVES:-1] = price
        grad[-1] = -1.0
    else:
        def goal(x):
            return -x[-1]

        grad = np.r_[np.zeros(len(x0) - 1), -1.0]
    # SLSQP's BLAS sums in another order on more threads: one thread, the
    # same bytes on any thread count (not on any CPU: OpenBLAS's kernel for
    # the CPU sums in its own order, docs/architecture.md)
    with threadpool_limits(limits=1, user_api="blas"):
        return minimize(goal, x0, jac=lambda x: grad, bounds=bounds, method="SLSQP",
                        options={"maxiter": ITERATIONS},
                        constraints=[{"type": "ineq", "fun": fun, "jac": jac}])


def _meets_all(full, near, x) -> bool:
    """Whether moves ``x`` break none of the constraints of the full program
    (its constraint function ``full``) that the near one (``near``) left out
    further than the near one's own worst (SLSQP's last iterate may miss its
    constraints by a rounding)."""
    return bool(full(x).min() >= min(0.0, near(x).min()))


def _kept(q0, q, slack: float = 0.0) -> bool:
    """Whether a round's mesh (quality ``q``) is kept over ``q0`` (module
    docstring); ``slack``: what a loose round's edges may give."""
    grow = 1.0 + slack
    return (q.min_angle >= q0.min_angle + MIN_GAIN and q.edge_ratio <= q0.edge_ratio * grow * grow
            and q.longest_edge <= q0.longest_edge * grow
            and q.max_perimeter <= q0.max_perimeter * grow
            and q.cv_edge <= q0.cv_edge * (1.0 + CV_SLACK + 2.0 * slack))


def _within(start, q) -> bool:
    """Whether a loose round's mesh keeps within LOOSE_BUDGET of ``start``."""
    cap = 1.0 + LOOSE_BUDGET
    return (q.edge_ratio <= start.edge_ratio * cap and q.longest_edge <= start.longest_edge * cap
            and q.max_perimeter <= start.max_perimeter * cap and q.cv_edge <= start.cv_edge * cap)


def _round(polygon, points, triangles, edges, a, d, slack: float, band: float = BAND):
    """(points, triangles, quality) after one round of :func:`_fit`, or
    (None, None, None) where it makes none."""
    sites = _fit(polygon, points, triangles, edges, a, d, slack, band)
    if sites is None:
        return None, None, None
    P, T = triangulate(polygon, sites, edges)
    return P, T, quality(P, T)


def _rounds(polygon, points, triangles, edges, a, d, q0, rounds: int, stop: float,
            slack: float = 0.0, allowed=None):
    """(points, triangles, quality, rounds kept) after up to ``rounds`` rounds,
    until the worst angle reaches ``stop``; ``slack``: loose rounds, of which
    the last whose mesh is worth its edges against the start's is kept
    (:func:`~uniform2d.optimize.angles.worth_its_edges`: one round's gain is
    too small to judge the rate on, the first rounds' cost the most), and
    ``allowed`` (a test of its quality) if given."""
    start, kept, made = q0, 0, [(points, triangles, q0)]
    wide = bool(slack)  # loose rounds: first held ones in the wide band
    for _ in range(rounds):
        if q0.min_angle >= stop:
            break
        if wide:
            P, T, q = _round(polygon, points, triangles, edges, a, d, 0.0, WIDE_BAND)
            wide = q is not None and _kept(q0, q) and _within(start, q)
        if not wide:
            P, T, q = _round(polygon, points, triangles, edges, a, d, slack)
            # the fresh triangulation may join the moved points in triangles the
            # program did not bound: a loose round is judged with twice its slack
            if q is None or not (_kept(q0, q, 2.0 * slack)
                                 and (slack == 0.0 or _within(start, q))):
                break
        points, triangles, q0 = P, T, q
        made.append((points, triangles, q0))
        kept += 1
    if slack:
        kept = max((k for k in range(1, len(made)) if worth_its_edges(start, made[k][2])
                    and (allowed is None or allowed(made[k][2]))), default=0)
        points, triangles, q0 = made[kept]
    return points, triangles, q0, kept


def fit_worst_angle(polygon: Polygon, points: np.ndarray, triangles: np.ndarray, edges,
                    measured=None):
    """(points, triangles, rounds kept): the mesh after up to ``ROUNDS`` rounds
    of the module docstring, the edges held.

    ``points`` are P's vertices then the sites, ``edges`` the polygon edge of
    each site (-1 inside; a site on an edge slides along it); ``measured``:
    the mesh's :func:`~uniform2d.quality.quality`, if known.  Meshes whose
    worst angle is ``FIT_BELOW`` or more, of more than ``FIT_MAX`` points
    whose worst angle is ``ANGLE_GOOD`` or more, of more than ``ANGLES_MAX``
    points or of fewer than ``FIT_MIN`` sites are returned as they are.
    Inputs are not modified.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> pts, tri = triangulate(sq, [(0.5, 0.5)])
    >>> fit_worst_angle(sq, pts, tri, np.array([-1]))[2]  # too few sites: as it is
    0
    """
    def stop_at(points, triangles, q0):
        if q0.min_angle >= FIT_BELOW or (len(points) > FIT_MAX and q0.min_angle >= ANGLE_GOOD):
            return None
        return FIT_BELOW

    return _run(polygon, points, triangles, edges, measured, ANGLES_MAX, stop_at,
                (ROUNDS, 0.0, None))


def loosen_worst_angle(polygon: Polygon, points: np.ndarray, triangles: np.ndarray, edges,
                       measured=None, allowed=None):
    """(points, triangles, rounds kept): a mesh whose worst angle is below
    ``ANGLE_FINE`` and below its :func:`~uniform2d.optimize.angles.forced_angle` (at least
    ``ANGLE_POOR``) after up to ``LOOSE_ROUNDS`` loose rounds (module
    docstring), the worst angle first, until it reaches the smaller of
    ``ANGLE_GOOD`` and that forced angle;
    other meshes, and those of more than ``FIT_MAX`` points or fewer than
    ``FIT_MIN`` sites, as they are.
    Arguments as for :func:`fit_worst_angle`; ``allowed``: a test of a round's
    :class:`~uniform2d.quality_result.Quality` that the mesh kept must pass
    too (the optimiser's: its objective no higher than T+'s).  Inputs are not
    modified.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> pts, tri = triangulate(sq, [(0.5, 0.5)])
    >>> loosen_worst_angle(sq, pts, tri, np.array([-1]))[2]  # too few sites: as it is
    0
    """
    def stop_at(points, triangles, q0):
        # a worst angle below ANGLE_POOR is poor next to any piece (the bolt
        # plate at 500 vertices: forced 17.9 degrees, the rounds take it to 20.8)
        forced = max(ANGLE_POOR, forced_angle(polygon, points, triangles))
        return None if q0.min_angle >= min(ANGLE_FINE, forced) else min(ANGLE_GOOD, forced)

    return _run(polygon, points, triangles, edges, measured, FIT_MAX, stop_at,
                (LOOSE_ROUNDS, LOOSE_STEP, allowed))


def _run(polygon, points, triangles, edges, measured, most: int, stop_at, how):
    """(points, triangles, rounds kept) of :func:`_rounds` with ``how`` =
    (rounds, slack, allowed) until the worst angle reaches ``stop_at(points,
    triangles, quality)``, or the mesh as it is where it has more than
    ``most`` points, fewer than FIT_MIN sites, or ``stop_at`` is None."""
    edges = np.asarray(edges)
    if len(points) > most or len(points) - len(polygon.vertices) < FIT_MIN:
        return points, triangles, 0
    q0 = quality(points, triangles) if measured is None else measured
    stop = stop_at(points, triangles, q0)
    if stop is None:
        return points, triangles, 0
    rounds, slack, allowed = how
    a, d, _ = polygon_edges(polygon, constraints=True)
    points, triangles, _, kept = _rounds(polygon, points, triangles, edges, a, d, q0, rounds,
                                         stop, slack, allowed)
    return points, triangles, kept
