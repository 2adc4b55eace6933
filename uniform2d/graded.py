"""Graded meshes with exactly n points: :func:`graded_mesh`, what
:func:`uniform2d.uniform_mesh` runs when ``size`` is a field.

1. **Start.**  The boundary first (:func:`boundary_sites`): every edge of the
   rings and segments gets ``round(∫ ds / (s h))`` pieces, their ends spaced so
   that each piece has the same ``∫ ds / h``, with s the field's scale at n (see
   4.).  The moves slide boundary points along their own edge only, so these
   counts fix how the boundary follows h.  Then rows packed front by front
   from the boundary, each point at the apex of a triangle of sides s h on
   the front (:func:`uniform2d.optimize.packing.rows_start`), and Algorithm
   INSERT (:func:`uniform2d.insert`) with the field where the fronts leave
   gaps (or the most crowded row points dropped): exactly n.  The rows have
   far fewer irregular vertices than INSERT alone leaves.
2. **Lloyd.**  Weighted Lloyd iterations for the density 1 / h⁴, whose
   centroidal tessellation has cells following h
   (:func:`uniform2d.optimize.lloyd.weighted_lloyd`), even out where the
   fronts met; boundary and segment points stay.
3. **Moves.**  :func:`uniform2d.optimize.improve` with the field: the same moves
   as for a uniform mesh (springs, descent on the p-norm energy of the
   objective, here one stage at p = 32, spread sweeps), every edge measured
   against the mean of its end points' sizes, so the mesh becomes uniform
   relative to h.  The triangulation stays the exact constrained Delaunay one
   of its points.  Then once more (up to ``CYCLE_MAX_POINTS`` points), from the
   moved points: ``CYCLE_LLOYD_ITERATIONS`` Lloyd iterations and the moves
   (Lloyd after the moves still moves the irregular vertices the moves left,
   which more Lloyd iterations before them did not do).  Last (up to
   ``VARIANCE_MAX_POINTS`` points), the CV of q itself lowered with the
   triangulation held (:func:`uniform2d.optimize.variance.lower_variance`:
   L-BFGS on CV(q)², every log q kept within the band the moves left, so that
   max q / min q does not grow), kept only if it lowers the CV of q.
4. **Scale.**  The field's scale s at which it implies |V| + n vertices
   (:func:`uniform2d.grading.scale_for_count`) is recorded
   (``mesh.info["size_scale"]``) and ``mesh.size`` is the field times s, so
   that ``mesh.quality().relative`` measures q = length / (s h(midpoint)),
   which is about 1 when the count integral holds.

There is no T+ to compare with (T+ is built from a uniform spacing), hence no
fallback: the moves keep the triangulation valid, and the result is checked
(:func:`uniform2d.validity.ensure_valid`).
"""

from __future__ import annotations

import logging

import numpy as np

from .errors import PLEASE_REPORT, InternalError
from .geometry import polygon_edges
from .grading import check_range, field_integrals, scale_for_count
from .mesh import Mesh
from .optimize.lloyd import weighted_lloyd
from .optimize.moves import improve_kept
from .optimize.objective import objective_code
from .optimize.packing import rows_start
from .optimize.schedule import LARGE
from .optimize.variance import lower_variance
from .polygon import Polygon
from .sizefield import SizeField
from .validity import ensure_valid

__all__ = ["PHASES", "boundary_sites", "graded_mesh"]

log = logging.getLogger(__name__)

#: Weighted Lloyd iterations before the moves, their over-relaxation and the
#: power of their density 1 / h**power: 4 is the density whose centroidal
#: tessellation has cells following h (with 2, more iterations flattened the
#: grading and undid the rows; with 4, 10 to 50 iterations lower the CV of q
#: steadily, where the fronts met most; 80 lower it further at 2000 and 8000
#: points, beyond that the gain stops).
LLOYD_ITERATIONS = 80
LLOYD_OMEGA = 1.5
LLOYD_POWER = 4
#: Lloyd iterations of the second Lloyd-then-moves cycle (from the moves'
#: result): 40 lowered the CV of q on the three benchmark cases at 2000 and
#: 8000 points with max q / min q within 0.01 of one cycle's; more cycles went
#: on lowering it by less than the spread between neighbouring settings.
CYCLE_LLOYD_ITERATIONS = 40
#: Meshes up to this many points get the second cycle: it adds some 45 % to the
#: graded path's time, which at 2000 points stays within the uniform mesh's (0.6 to
#: 1.2 times it on the benchmark cases) but at 8000 took the L-shape from 2.2 to 3.0
#: times and the bracket from 1.5 to 2.5 times it (the uniform path's lattice is
#: fastest there), for a CV of q already under 0.06 without it.
CYCLE_MAX_POINTS = 5000
#: The moves' descent stages (p-norm exponents 2**k) up to ``schedule.LARGE``
#: points: one stage at p = 32.  The graded default (p = 4 to 64, for the
#: surface layer) trades the CV of q for the extremes; from the rows and Lloyd,
#: springs then one stage then the spread sweeps give the lowest CV of q with
#: max q / min q within 1.6 on the benchmark cases at p = 32 (p = 16 lowers the
#: CV further but leaves max q / min q above 1.6 on the bracket; p = 128 keeps
#: the extremes lower and the CV higher).
EXPONENTS = (5,)
#: Spring rounds before the moves' descent (``schedule.SCHEDULE_GRADED`` has 60,
#: for the surface layer's starts): after the weighted Lloyd iterations 20 do
#: what 60 did on the benchmark cases (the CV of q and max q / min q within
#: 0.2 %, lower on the L-shape at 8000 points) in less time; 10 or none leave
#: the CV of q higher.
SPRING_ROUNDS = 20
#: Iterations of the last stage, :func:`~uniform2d.optimize.variance.lower_variance`,
#: and the meshes that get it: on the benchmark cases at 2000 points, 200
#: iterations take the CV of q from the moves' 0.0527 / 0.0626 / 0.0549 to
#: 0.0513 / 0.0600 / 0.0536 (L-shape, bolt plate, bracket), max q / min q
#: within 0.1 % of the moves', in 0.25-0.35 s of CPU time; 150 left the plate at
#: 0.06003, 400 lower the CV by 0.0005 more at most.  At 8000 points it lowers the
#: CV of q by 0.0017 to 0.0024 where it is below 0.06 already, for about 1.3 s:
#: as much as the rest of the L-shape's graded path.
VARIANCE_ITERATIONS = 200
VARIANCE_MAX_POINTS = CYCLE_MAX_POINTS

#: Samples of the field along each boundary edge (:func:`boundary_sites`).
EDGE_SAMPLES = 64

#: The phases :func:`graded_mesh` reports to ``progress``.
PHASES = ("insert", "relaxation")


def graded_mesh(polygon: Polygon, n: int, field: SizeField, *, objective: str = "balanced",
                progress=None, integrals=None) -> Mesh:
    """The mesh with exactly ``n`` Steiner points whose edges follow ``field`` most evenly.

    Parameters
    ----------
    polygon : Polygon
        Constraints (segments, fixed points) and regions are kept as for a uniform mesh.
    n : int
        Steiner points, n >= 1.
    field : SizeField
        The size field; only its shape matters (its scale follows from n).
    objective : str
        As :func:`uniform2d.uniform_mesh`'s, on q = length / h.
    progress : callable, optional
        ``progress(phase, done, total)`` for the phases of :data:`PHASES`.
    integrals : tuple, optional
        :func:`uniform2d.grading.field_integrals` of the field, if known.

    Examples
    --------
    >>> from uniform2d import Polygon, SizeField
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = SizeField([0, 1], [0, 1], [[1.0, 3.0], [1.0, 3.0]])
    >>> m = graded_mesh(sq, 60, f)
    >>> m.n_steiner, len(m.points), m.info["method"]
    (60, 64, 'graded')
    """
    objective_code(objective)
    nV = len(polygon.vertices)
    integrals = field_integrals(polygon, field) if integrals is None else integrals
    check_range(polygon, field, n, integrals)
    s = scale_for_count(polygon, field, n, integrals)

    def report(phase, done, total):
        if done == 0:
            log.info("graded: %s", phase)
        if progress is not None:
            progress(phase, done, total)

    report("insert", 0, 1)
    bsites, bedges = boundary_sites(polygon, field, s, n)
    sites, fixed = rows_start(polygon, n, field, s, bsites, bedges)
    report("insert", 1, 1)
    report("relaxation", 0, 1)
    sites = weighted_lloyd(polygon, sites, fixed, field, iterations=LLOYD_ITERATIONS,
                           omega=LLOYD_OMEGA, power=LLOYD_POWER)
    exponents = EXPONENTS if nV + n <= LARGE else None
    pts, tri, run = improve_kept(polygon, sites, size=field, objective=objective,
                                 exponents=exponents, spring_rounds=SPRING_ROUNDS)
    first = {"spring_rounds": 0, "sweeps": 0}
    if CYCLE_LLOYD_ITERATIONS and nV + n <= CYCLE_MAX_POINTS:
        sites = weighted_lloyd(polygon, pts[nV:], run["edges"] >= 0, field,
                               iterations=CYCLE_LLOYD_ITERATIONS, omega=LLOYD_OMEGA,
                               power=LLOYD_POWER)
        first = run
        pts, tri, run = improve_kept(polygon, sites, size=field, objective=objective,
                                     exponents=exponents, spring_rounds=SPRING_ROUNDS)
    kept = False
    if VARIANCE_ITERATIONS and nV + n <= VARIANCE_MAX_POINTS:
        pts, tri, low = lower_variance(polygon, pts, tri, run["edges"], field,
                                       iterations=VARIANCE_ITERATIONS)
        kept = low["kept"]
    report("relaxation", 1, 1)
    if len(pts) != nV + n:
        raise InternalError(f"graded: {len(pts) - nV} Steiner points instead of {n} {PLEASE_REPORT}")
    ensure_valid(pts, tri, polygon, n, "uniform_mesh")
    info = {
        "method": "graded",
        "objective": objective,
        "d_n": None,
        "size_scale": s,
        "relax_iterations": first["spring_rounds"] + run["spring_rounds"],
        "sweeps": first["sweeps"] + run["sweeps"],
        "objective_value": run["objective_value"],
        "variance_stage": kept,
    }
    return Mesh(pts, tri, polygon, n, info, size=field.scaled(s))


def boundary_sites(polygon: Polygon, field: SizeField, scale: float, n: int):
    """Points on the rings' and segments' edges following ``scale * field``: (sites
    (k, 2), the edge of each in ``polygon.constraint_edges`` order), k <= n / 2.

    Edge e of length L gets ``m = round(∫_e ds / (scale h))`` pieces (at least
    one), so m - 1 points, placed where the running integral of 1 / h reaches
    j / m of the edge's (``EDGE_SAMPLES`` midpoint samples per edge).  If the
    boundary would take more than half of the n points the field is coarsened
    until it does not.

    Examples
    --------
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> sites, edges = boundary_sites(sq, SizeField.constant(sq.bounds, 1.0), 0.25, 40)
    >>> len(sites), edges.tolist()[:3]
    (12, [0, 0, 0])
    """
    a, d, L = polygon_edges(polygon, constraints=True)
    t = (np.arange(EDGE_SAMPLES) + 0.5) / EDGE_SAMPLES
    mids = a[:, None, :] + t[None, :, None] * d[:, None, :]
    inv = 1.0 / field(mids.reshape(-1, 2)).reshape(len(a), EDGE_SAMPLES)
    cum = np.concatenate([np.zeros((len(a), 1)), np.cumsum(inv, axis=1)], axis=1)
    cum *= (L / EDGE_SAMPLES)[:, None]
    for _ in range(64):
        m = np.maximum(1, np.rint(cum[:, -1] / scale)).astype(np.int64)
        if (m - 1).sum() <= n // 2:
            break
        scale *= 1.25
    sites, edges = [], []
    grid = np.linspace(0.0, 1.0, EDGE_SAMPLES + 1)
    for e in np.flatnonzero(m > 1):
        goal = cum[e, -1] * np.arange(1, m[e]) / m[e]
        te = np.interp(goal, cum[e], grid)
        sites.append(a[e] + te[:, None] * d[e])
        edges.append(np.full(len(te), e, np.int64))
    if not sites:
        return np.empty((0, 2)), np.empty(0, np.int64)
    return np.concatenate(sites), np.concatenate(edges)
