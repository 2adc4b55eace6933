"""Moving the points of a mesh of P: the driver of the kernel :mod:`uniform2d._kernel.relax`.

A :class:`KernelMesh` is a mesh loaded into the kernel once (from a triangle
list, :meth:`KernelMesh.from_mesh`; as the CDT of P and some sites,
:meth:`KernelMesh.triangulated`; or built where the optimiser placed its own
sites, :meth:`KernelMesh.built`).  Its :meth:`~KernelMesh.advance` runs the
stages of a :class:`~uniform2d.optimize.schedule.Schedule` on it; the kernel
keeps the triangulation valid and constrained Delaunay by exact predicates and
flips while the points move.  Then either its points are read back and
triangulated afresh (:func:`improve`, :func:`finish`) or the kernel's own
triangulation is returned (:func:`improve_kept`, :meth:`KernelMesh.result`).
:func:`improve_best` moves the best of several starts.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._kernel import cdt, relax
from .._kernel.descent import GAIN, PATIENCE
from .._kernel.objective import BALANCED
from ..geometry import polygon_edges
from ..polygon import Polygon, as_polygon
from ..sites import edge_parameters
from ..threads import thread_map
from ..triangulation import load_mesh, triangulate
from ..triangulation import load as build
from . import schedule as S
from .halving import run_plan
from .objective import objective_code
from .boundary import target_size

__all__ = ["improve", "improve_kept", "improve_best", "KernelMesh", "Progress", "finish",
           "default_schedule"]


def improve(
    polygon: Polygon,
    sites,
    *,
    size=None,
    objective: str = "balanced",
    href: float | None = None,
    frozen=None,
    spring_rounds: int | None = None,
    sweeps: int | None = None,
    exponents=None,
    spread_sweeps: int | None = None,
    edges=None,
):
    """Move the Steiner points of a mesh of P to make it more uniform, exactly n kept.

    The mesh is the constrained Delaunay triangulation of P with ``sites``; the
    polygon's vertices stay, sites on its boundary slide along their edges,
    interior sites move freely, and the triangulation is kept valid and
    constrained Delaunay throughout (exact predicates; see
    :mod:`uniform2d._kernel.relax`).  First spring rounds towards equal
    (size-normalised) edge lengths, then descent on the p-norm energy of
    ``objective`` for each exponent in ``exponents``, keeping the best state;
    last, sweeps that lower the spread of the edge lengths with the
    objective's extremes held.

    Parameters
    ----------
    polygon : Polygon
    sites : array_like, shape (k, 2)
        Steiner points inside P or on its boundary.  Not modified.
    size : SizeField, optional
        Target sizes (relative: the overall scale follows the point count).
        None for a uniform mesh.
    objective : {"balanced", "ratio", "max_edge", "max_perimeter"}
    href : float, optional
        The uniform target edge length (default: from the point count, as
        :func:`~uniform2d.optimize.boundary.target_size`); ignored with a ``size`` field.
    frozen : array_like of bool, shape (k,), optional
        Sites that must not move (e.g. the deep interior of a lattice that is
        already uniform: the work then scales with the boundary band).
    spring_rounds, sweeps, exponents, spread_sweeps : optional
        Override the fields of the default
        :class:`~uniform2d.optimize.schedule.Schedule` (see
        :func:`~uniform2d.optimize.schedule.schedule_for`).
    edges : array_like of int, shape (k,), optional
        The polygon edge each site lies on, -1 for an interior site (the
        optimiser's own sites: placed by index, not judged by distance).
        Default: found by distance, as :func:`uniform2d.insert` does.

    Returns
    -------
    points : ndarray, shape (|V| + k, 2)
        The polygon's vertices exactly, then the moved sites (same order).
    triangles : ndarray, shape (M, 3), int64
        The exact constrained Delaunay triangulation of ``points`` (CCW).
    info : dict
        Spring rounds and sweeps made, the objective value reached, and
        ``edges``: the polygon edge of each returned site (-1 inside).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.optimize import improve
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> pts, tri, info = improve(sq, [(0.3, 0.4), (0.5, 0.0), (0.6, 0.7)])
    >>> pts.shape, np.allclose(pts[5, 1], 0.0)   # the boundary site stayed on y = 0
    ((7, 2), True)
    """
    polygon = as_polygon(polygon)
    st = KernelMesh.triangulated(polygon, sites, size=size, href=href, frozen=frozen, edges=edges)
    if st is None:
        return finish(polygon, None, Progress())
    sched = default_schedule(len(st.xy), size is not None, spring_rounds=spring_rounds,
                             sweeps=sweeps, exponents=exponents, spread_sweeps=spread_sweeps)
    run = st.advance(sched, objective_code(objective))
    unloaded = st.sites()
    del st
    return finish(polygon, unloaded, run)


def improve_kept(polygon: Polygon, sites, *, size=None, objective: str = "balanced", href=None,
                 frozen=None, edges=None, movable_short: bool = False, **overrides):
    """:func:`improve` for the optimiser's own sites: built in the kernel once
    (:meth:`KernelMesh.built`, with ``edges`` and no size field) and returned as
    the kernel's own triangulation of the moved points (:meth:`KernelMesh.result`)
    instead of triangulating them again; the optimiser checks the mesh it
    returns.  ``movable_short``: as :meth:`KernelMesh.built`'s.  ``overrides``:
    the schedule's fields, as :func:`improve`'s."""
    polygon = as_polygon(polygon)
    if size is not None or edges is None:
        st = KernelMesh.triangulated(polygon, sites, size=size, href=href, frozen=frozen,
                                     edges=edges)
    else:
        st = KernelMesh.built(polygon, sites, href=href, frozen=frozen, edges=edges,
                              movable_short=movable_short)
    if st is None:
        return finish(polygon, None, Progress())
    run = st.advance(default_schedule(len(st.xy), size is not None, **overrides),
                     objective_code(objective))
    return st.result(run)


class Progress(NamedTuple):
    """What the stages run on one loaded mesh made: spring rounds, descent sweeps
    and the objective value of the last descent stage (None before one)."""

    spring_rounds: int = 0
    sweeps: int = 0
    value: float | None = None


def default_schedule(n_points: int, graded: bool, winner: bool = False,
                     **overrides) -> S.Schedule:
    """:func:`~uniform2d.optimize.schedule.schedule_for` with the fields of
    ``overrides`` that are not None put in (a caller's ``sweeps`` hold for
    every stage: the schedule's own stage limits go)."""
    given = {k: v for k, v in overrides.items() if v is not None}
    if "sweeps" in given:
        given.setdefault("stages", ())
    return S.schedule_for(n_points, graded, winner)._replace(**given)


def finish(polygon: Polygon, unloaded: "tuple | None", run: Progress):
    """:func:`improve`'s result from :meth:`KernelMesh.sites` (None: no sites): the points
    in the caller's coordinates, their exact constrained Delaunay triangulation
    and the info dict.  Callers drop the kernel state first: at 1e6 points its
    arrays would otherwise stand beside the triangulation's own."""
    if unloaded is None:
        P0, T0 = triangulate(polygon, np.empty((0, 2)), None)
        return P0, T0, {"spring_rounds": 0, "sweeps": 0, "edges": np.empty(0, np.int64)}
    sites, edges = unloaded
    points, triangles = triangulate(polygon, sites, edges)
    info = {
        "spring_rounds": int(run.spring_rounds), "sweeps": int(run.sweeps),
        "objective_value": run.value, "edges": edges,
    }
    return points, triangles, info


def improve_best(polygon: Polygon, starts, *, objective: str = "balanced", href=None,
                 report=None, spring_rounds=None, sweeps=None, exponents=None,
                 spread_sweeps=None, movable_short: bool = False):
    """:func:`improve` from the best of several starts, found by successive halving.

    ``starts`` is an iterable of ``(sites, edges, frozen)``, as :func:`improve`'s
    arguments, or of those starts built already (:meth:`KernelMesh.built` with
    ``href`` and ``movable_short``, as here; None for no sites: the caller's
    threads can build each as soon as it is made; an iterator leaves the
    kernel states to this function alone, which drops the losers' as it goes).  Every start is built in the kernel once (:meth:`KernelMesh.built`)
    and runs the first schedule of ``schedule.TRIALS``; the best
    ``schedule.KEEP`` of them (by :meth:`KernelMesh.rank`; ``KEEP_LARGE``'s, one
    fraction a trial, above ``KEEP_MAX`` points) run the next, and so on (the first trial's spring
    rounds in two parts, the starts ranked after ``schedule.PRUNE_ROUNDS`` (``PRUNE_ROUNDS_LARGE``) of
    them and only those the next trial can take, and ``PRUNE_SPARE`` (``PRUNE_SPARE_LARGE``) more,
    running the rest: :func:`_trial_plan`; a later trial that one start would run alone ranks
    nothing and is left out); the winner's kernel state goes on into the full schedule
    (``schedule_for``'s with ``winner``, overridden as :func:`improve`'s) without being loaded again, from the stage
    ``schedule.AFTER_TRIALS`` on unless ``exponents`` is given.  A start
    fixes the mesh's structure, which the short runs already show; halving spends
    the long ones on the few that can win; a start's next trial starts as soon
    as it is certain to run it (:func:`~uniform2d.optimize.halving.run_plan`:
    no thread waits for a round's slowest start).  ``report(done, total)``, if
    given, is called before the first trial and after each round of trials.  The starts
    are built and their trials run on :func:`uniform2d.threads.get_threads`
    threads, each start on its own kernel state, the results ranked in the
    order of the starts: the same mesh on any number of threads.
    ``movable_short``: as :meth:`KernelMesh.built`'s.

    Returns (index of the winning start, points, triangles, info) as :func:`improve`,
    the triangles the kernel's own (:meth:`KernelMesh.result`).
    All starts are alive in the kernel at once until the first ranking: fine
    for what :func:`~uniform2d.optimize.seed.variants` gives (up to 12 starts
    of at most ``schedule.SMALL`` points, 2 of at most ``schedule.LARGE``, a
    few MB each), not for many starts of a huge mesh.
    """
    obj = objective_code(objective)
    def loaded(s):  # a start the caller built already stays as it is
        if s is None or isinstance(s, KernelMesh):
            return s
        return KernelMesh.built(polygon, s[0], href=href, frozen=s[2], edges=s[1],
                                movable_short=movable_short)

    built = thread_map(loaded, starts)
    alive = [(i, st, Progress()) for i, st in enumerate(built)]
    del built
    n_points = next((len(st.xy) for _, st, _ in alive if st is not None), 0)
    small = n_points <= S.KEEP_MAX
    plan = _trial_plan(len(alive), S.KEEP if small else S.KEEP_LARGE,
                       S.PRUNE_ROUNDS if small else S.PRUNE_ROUNDS_LARGE,
                       S.PRUNE_SPARE if small else S.PRUNE_SPARE_LARGE)
    # a later trial one start runs alone ranks nothing: the start that won the
    # ranking before it goes on into its own schedule at once (two starts,
    # above SMALL points: 12 descent sweeps fewer on the serial path)
    plan = plan[:1] + [p for p in plan[1:] if p[1] > 1]
    if report is not None:
        report(0, sum(size for _, size, _ in plan))
    # each start's next trial as soon as it is certain to run it (halving)
    alive = run_plan(plan, alive, lambda a, sched, resumed: _trial(a, sched, obj, resumed),
                     report)
    (i, st, run), = alive[:1]
    alive = None  # the losers' kernel states go now
    if st is None:
        return i, *finish(polygon, None, run)
    sched = default_schedule(len(st.xy), False, True, spring_rounds=spring_rounds,
                             sweeps=sweeps, exponents=exponents, spread_sweeps=spread_sweeps)
    if exponents is None:
        sched = sched._replace(exponents=tuple(k for k in sched.exponents if k >= S.AFTER_TRIALS))
    run = st.advance(sched, obj, run)
    return i, *st.result(run)


def _trial_plan(starts: int, keep, prune: int | None = None, spare: int | None = None) -> list:
    """The trials of :func:`improve_best` for ``starts`` starts: (schedule, how
    many of the best run it, spring rounds an earlier part of it asked).  The
    ``schedule.TRIALS`` with ``keep`` of the starts going on after each (a
    fraction, or one per trial after the first); the first trial's spring
    rounds split after ``prune`` of them (default ``schedule.PRUNE_ROUNDS``;
    0: no split) where that leaves starts out (the starts a split drops are
    those no later trial would have run), ``spare`` (default
    ``schedule.PRUNE_SPARE``) more than the next trial takes going on, and
    never fewer than two."""
    prune = S.PRUNE_ROUNDS if prune is None else prune
    spare = S.PRUNE_SPARE if spare is None else spare
    keeps = keep if isinstance(keep, tuple) else (keep,) * (len(S.TRIALS) - 1)
    sizes = [starts]
    for k in keeps:
        sizes.append(max(1, math.ceil(k * sizes[-1])))
    plan = [(sched, size, 0) for sched, size in zip(S.TRIALS, sizes)]
    first = S.TRIALS[0]
    cut = max(sizes[1] + spare, 2) if len(sizes) > 1 else starts
    if prune and first.spring_rounds > prune and cut < starts:
        plan[:1] = [(first._replace(spring_rounds=prune), starts, 0),
                    (first._replace(spring_rounds=first.spring_rounds - prune), cut, prune)]
    return plan


def _trial(alive, sched: S.Schedule, obj: int, resumed: int = 0):
    """One start's trial of :func:`improve_best`: (rank, index, state, progress)
    after running ``sched`` on it (its own kernel state: trials run at once on
    threads, :func:`uniform2d.threads.thread_map`).  ``resumed``: the spring
    rounds the part of the trial before this one asked; a start whose spring
    stopped before them (its moves below the tolerance) runs no more of them,
    as one run of all the rounds would have stopped there too."""
    i, st, run = alive
    if st is None:
        return 0.0, i, st, run
    if resumed and run.spring_rounds < resumed:
        sched = sched._replace(spring_rounds=0)
    run = st.advance(sched, obj, run)
    return st.rank(obj), i, st, run


class KernelMesh(NamedTuple):
    """A mesh of P loaded into the kernel, in normalised coordinates, with the role
    of every point: polygon vertices and ``frozen`` sites fixed, sites on the
    boundary sliding along their edge, the others free."""

    polygon: Polygon
    m: object  # cdt.Tri
    xy: np.ndarray  # (N, 2) its coordinate array
    role: np.ndarray  # (N,) int8 relax.FIXED / FREE / SLIDE
    eid: np.ndarray  # (N,) polygon edge of each SLIDE vertex
    t: np.ndarray  # (N,) its parameter on that edge
    ea: np.ndarray  # (E, 2) polygon edge starts, normalised
    ed: np.ndarray  # (E, 2) polygon edge vectors, normalised
    hv: np.ndarray  # (N,) size at each vertex (1 without a field)
    href: float  # target length (uniform) or field scale (graded), normalised
    centre: np.ndarray
    scale: float
    # the kernel passes cover only the triangles the moves can change (frozen
    # sites: the deep interior of a large lattice); False: every triangle, as
    # the surface layer's meshes were made
    restrict: bool = False
    # the descent's short-edge weight from the edges a move can change
    # (:func:`uniform2d._kernel.descent._weights`): the optimiser's angle
    # attempt (:meth:`built`), not its first one nor the surface layer's charts
    movable_short: bool = False

    @classmethod
    def from_mesh(cls, polygon: Polygon, points, triangles, *, size=None, href=None,
                  frozen=None, edges=None) -> "KernelMesh":
        """Load a mesh of P (its vertices first, then the sites) into the kernel;
        arguments as :func:`improve`'s."""
        T0 = np.asarray(triangles, dtype=np.int32)
        m, xy, centre, scale, boundary, graded = load_mesh(polygon, points, T0, size, edges)
        on = (np.array([i for i, _, _ in boundary], dtype=np.int64),
              np.array([e for _, e, _ in boundary], dtype=np.int64),
              np.array([t for _, _, t in boundary], dtype=np.float64))
        return _roles(polygon, m, xy, centre, scale, on, href, frozen, T0 if graded else None)

    @classmethod
    def triangulated(cls, polygon: Polygon, sites, *, size=None, href=None, frozen=None,
                     edges=None) -> "KernelMesh | None":
        """The constrained Delaunay triangulation of P with ``sites`` loaded into the
        kernel (arguments as :func:`improve`'s), or None if there are no sites."""
        P0, T0 = triangulate(polygon, sites, edges)
        if len(P0) == len(polygon.vertices):
            return None
        return cls.from_mesh(polygon, P0, T0, size=size, href=href, frozen=frozen, edges=edges)

    @classmethod
    def built(cls, polygon: Polygon, sites, *, href=None, frozen=None,
              edges=None, movable_short: bool = False) -> "KernelMesh | None":
        """:meth:`triangulated` for the optimiser's own sites (``edges`` given, no
        size field), kept in the kernel the triangulation was built in: no
        triangle list read out, checked and loaded into a second kernel (the
        mesh returned is checked at the end; with ``movable_short`` the descent
        weighs the short edges a move can change: the optimiser's angle
        attempt, :mod:`~uniform2d.optimize.pipeline`).  The kernel's slots then come in
        the order the build made them, not that of a triangle list, so the moves
        can take other (equally valid) turns than after :meth:`triangulated`."""
        if len(sites) == 0:
            return None
        built = build(polygon, sites, edges=edges)
        edges = built.edges
        on = np.flatnonzero(edges >= 0)
        tb = edge_parameters(polygon, built.sites[on], edges[on])  # each site's own
        return _roles(polygon, built.m, built.xy, built.centre, built.scale,
                      (on, edges[on], tb), href, frozen)._replace(movable_short=movable_short)

    def advance(self, sched: S.Schedule, obj: int, before: Progress = Progress()) -> Progress:
        """Run the stages of ``sched``, in place; returns ``before`` with this run's
        rounds and sweeps added.  The kernel's triangulation is the constrained
        Delaunay one of its points again at the end, so a later call may go on
        from here."""
        args = (self.m, self.role, self.eid, self.t, self.ea, self.ed, self.hv, self.href)
        rounds, done, value = before
        restrict = self.restrict
        if sched.spring_rounds:
            rounds += relax.spring(
                *args, iters=sched.spring_rounds, dt=S.SPRING_STEP, pressure=S.SPRING_PRESSURE,
                tol=S.SPRING_TOL, cap=S.SPRING_CAP, flat=S.FLAT, restrict=restrict,
            )
        for k in sched.exponents:
            # each stage ends in its best state, the next goes on from there
            st = sched.stage(int(k))
            made, value = relax.descend(
                *args, objective=obj, sweeps=st.sweeps, k=int(k), step0=S.SEARCH_STEP,
                flat=S.FLAT, restrict=restrict, movable_short=self.movable_short,
                patience=PATIENCE if st.patience is None else int(st.patience),
                gain=GAIN if st.gain is None else float(st.gain),
            )
            done += made
        if sched.spread_sweeps:
            relax.spread(
                *args, objective=obj, sweeps=sched.spread_sweeps, step0=S.SEARCH_STEP,
                flat=S.FLAT, restrict=restrict,
            )
        return Progress(rounds, done, value)

    def rank(self, obj: int) -> float:
        """How good this start is, lower better: its objective value, from the
        kernel's own measures; with ``"balanced"``, times the edge CV to the power
        ``schedule.CV_WEIGHT`` (the start fixes the structure, and with it the CV
        the moves can reach, which the extremes alone do not see)."""
        val = relax.objective_of(obj, *relax.measure(self.m, self.hv, self.href))
        if obj == BALANCED and S.CV_WEIGHT:
            val *= relax.edge_cv(self.m, self.hv, self.href) ** S.CV_WEIGHT
        return float(val)

    def points(self) -> np.ndarray:
        """The kernel's points in the caller's coordinates, exactly: the kernel rounds
        every place to what these coordinates hold (:func:`uniform2d._kernel.cdt.snap`)."""
        out = self.xy * self.scale + self.centre
        out[: len(self.polygon.vertices)] = self.polygon.vertices
        return out

    def sites(self) -> tuple:
        """(sites, edges): the points after P's vertices, in the caller's
        coordinates, and the polygon edge each slides along (-1: none)."""
        nV = len(self.polygon.vertices)
        return self.points()[nV:], self.eid[nV:].copy()

    def result(self, run: Progress):
        """:func:`finish`'s result from the kernel's own triangulation of its points.

        The kernel keeps its mesh the exact constrained Delaunay triangulation of
        its points after every round, and its points are exactly the ones
        returned (:meth:`points`), so this is a CDT of them without a second one
        built from scratch (at 1e6 points that build costs seconds).  Where four
        points are cocircular it may pick the other diagonal than a fresh build
        would."""
        nV = len(self.polygon.vertices)
        points = self.points()
        triangles = cdt.triangle_list(self.m)
        info = {
            "spring_rounds": int(run.spring_rounds), "sweeps": int(run.sweeps),
            "objective_value": run.value, "edges": self.eid[nV:].copy(),
        }
        return points, triangles, info


def _roles(polygon, m, xy, centre, scale, boundary, href, frozen, graded=None) -> KernelMesh:
    """The :class:`KernelMesh` of a mesh in kernel ``m`` (coordinates ``xy``): the
    roles, edges and sizes of its points.  ``boundary``: (the sites on P's
    boundary, by index among the sites; their polygon edges; their parameters
    along them), three arrays.  ``graded``: the mesh's triangles
    where the kernel reads a size field (None without one)."""
    nV = len(polygon.vertices)
    N = len(xy)
    a, d, _ = polygon_edges(polygon, constraints=True)
    role = np.full(N, relax.FREE, np.int8)
    role[:nV] = relax.FIXED
    eid = np.full(N, -1, np.int64)
    t = np.zeros(N)
    if frozen is not None:
        role[nV:][np.asarray(frozen, dtype=bool)] = relax.FIXED
    on, e, ti = boundary
    role[nV + on] = relax.SLIDE
    eid[nV + on] = e
    t[nV + on] = ti
    hv = np.ones(N)
    relax.refresh_sizes(m, hv, np.ones(N, np.bool_))
    if graded is not None:  # the field's shape, scaled to the edges present
        E = np.concatenate([graded[:, [0, 1]], graded[:, [1, 2]], graded[:, [2, 0]]])
        Ls = np.hypot(*(xy[E[:, 1]] - xy[E[:, 0]]).T)
        hs = 0.5 * (hv[E[:, 0]] + hv[E[:, 1]])
        href_n = float(np.sqrt((Ls**2).mean() / (hs**2).mean()))
    else:
        href_n = (target_size(polygon, N - nV) if href is None else href) / scale
    restrict = frozen is not None and bool(np.any(frozen))
    return KernelMesh(polygon, m, xy, role, eid, t, (a - centre) / scale, d / scale, hv, href_n,
                      centre, scale, restrict)
