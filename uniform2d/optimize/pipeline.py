"""The optimiser's pipeline: :func:`optimize_mesh` (see the package docstring)."""

from __future__ import annotations

import logging
import math
import numbers
import threading
from concurrent.futures import Future, wait
from functools import partial

import numpy as np

from ..errors import InsufficientPointsError, InternalError, PLEASE_REPORT
from ..insert import min_distance_after
from ..mesh import Mesh
from ..polygon import Polygon
from ..quality import quality
from ..threads import get_threads, in_background, thread_map
from ..tplus import tplus_if_feasible
from ..validity import ensure_valid
from . import schedule as S
from .anglefit import fit_worst_angle, loosen_worst_angle
from .angles import ANGLE_FINE, ANGLES_MAX, angle_attempt_wins, raise_worst_angle
from .boundary import target_size
from .moves import KernelMesh, improve_best, improve_kept
from .objective import objective_code, quality_objective
from .polish import POLISH_MAX, polish_extremes
from .relocate import relocate
from .seed import start, start_parts, stripped, variants
from .shift import shift_worst
from .edge_cv import CV_STAGE_MAX, CV_STAGE_MIN, lower_edge_cv
from .transition import SMALL_PIECE

__all__ = ["optimize_mesh", "quality_summary"]

log = logging.getLogger(__name__)


class _Once:
    """``fn(*key)``, made once per key by the first caller, whichever thread it
    is on; the others wait for it.  The starts' shared parts (the rows, some
    half a millisecond of Python each) are made as the starts need them, beside
    other starts' kernels, not in a map of their own that every start waits for."""

    def __init__(self, fn):
        self._fn = fn
        self._made: dict = {}
        self._locks: dict = {}
        self._lock = threading.Lock()

    def __call__(self, *key):
        with self._lock:
            lock = self._locks.setdefault(key, threading.Lock())
        with lock:
            if key not in self._made:
                self._made[key] = self._fn(*key)
            return self._made[key]


def _best_start(polygon: Polygon, n: int, h: float, objective: str, options, report,
                angled: bool = False):
    """The mesh moved from the best start of :func:`~uniform2d.optimize.seed.variants`
    (successive halving when there are several, see
    :func:`~uniform2d.optimize.moves.improve_best`): (points, triangles, improve's
    info, frozen sites, boundary points, variant).  ``angled``: the starts with
    rows around small holes, the descent weighing the movable short edges
    (:func:`_finished`)."""
    tried = variants(polygon, n)
    # the rows of a spacing are the same for every lattice edge: made once,
    # by the first start that needs them
    shared = _Once(lambda c, lay: start_parts(polygon, n, h, c, lay, angled))
    ranked = len(tried) > 1
    free = stripped(polygon, n)

    def made_and_built(v):
        # each start built in the kernel on the thread that made it: one
        # start's Python (the lattice) runs beside another's build (nogil)
        made = start(polygon, n, h, v, angled, shared=shared(v[0], v[2]), free=free)
        if not ranked:
            return made, None
        return made, KernelMesh.built(polygon, made[0], href=h, frozen=made[2], edges=made[1],
                                      movable_short=angled)

    both = thread_map(made_and_built, tried)
    made = [m for m, _ in both]
    # handed on as an iterator: improve_best alone holds the kernel states,
    # and lets the losers' go as the trials drop them
    kernels = iter([b for _, b in both])
    del both
    options = {**options, "movable_short": angled}
    if len(made) == 1:  # nothing to rank
        report("seed", 0, 1)
        report("seed", 1, 1)
        sites, edges, frozen, _ = made[0]
        report("relaxation", 0, 1)
        pts, tri, run = improve_kept(
            polygon, sites, objective=objective, href=h, frozen=frozen, edges=edges, **options
        )
        i = 0
    else:
        i, pts, tri, run = improve_best(
            polygon, kernels, objective=objective, href=h,
            report=lambda done, total: _seed_then_relax(report, done, total), **options,
        )
    report("relaxation", 1, 1)
    return pts, tri, run, made[i][2], made[i][3], tried[i]


def _finished(polygon: Polygon, n: int, h: float, objective: str, options, report,
              angled: bool = False):
    """A finished mesh: the best start (:func:`_best_start`), relocation, the
    worst-angle pass, checked: (points, triangles, improve's info, k, variant,
    relocations, angle rounds, the sites' polygon edges).  ``angled``: the angle attempt, with rows
    around small holes and the movable short edges weighed (see
    :func:`~uniform2d.optimize.angles.angle_attempt_wins`)."""
    nV = len(polygon.vertices)
    pts, tri, run, frozen, k, variant = _best_start(polygon, n, h, objective, options, report,
                                                    angled)
    moved, edges = 0, run["edges"]
    if n + nV <= S.RELOCATE_MAX:
        report("relocation", 0, 1)
        pts, tri, moved, edges = relocate(polygon, pts, tri, frozen, objective, h, options, edges)
        report("relocation", 1, 1)
    raised = 0
    if n + nV <= ANGLES_MAX:
        pts, tri, raised = raise_worst_angle(polygon, pts, tri, edges)
        pts, tri, shifted, edges = shift_worst(polygon, pts, tri, frozen, objective, h, options,
                                               edges)
        if shifted:
            log.info("uniform: %d shift(s) for the worst angle", shifted)
    # the kernel's own triangles (moves.finish_kept), checked here once
    ensure_valid(pts, tri, polygon, len(pts) - nV, "uniform_mesh")
    return pts, tri, run, k, variant, moved, raised, edges


def _fitted(polygon: Polygon, pts, tri, edges, q, allowed):
    """The chosen mesh after :func:`~uniform2d.optimize.anglefit.fit_worst_angle`
    (the edges held) and then :func:`~uniform2d.optimize.anglefit.loosen_worst_angle`
    (the worst angle first, its meshes ``allowed``), checked if it moved:
    (points, triangles, quality, rounds kept of each)."""
    rounds = []
    for stage, what in ((fit_worst_angle, "the angle fit"),
                        (partial(loosen_worst_angle, allowed=allowed),
                         "the angle fit, the worst angle first")):
        pts, tri, made = stage(polygon, pts, tri, edges, q)
        if made:
            log.info("uniform: %d round(s) of %s", made, what)
            ensure_valid(pts, tri, polygon, len(pts) - len(polygon.vertices), "uniform_mesh")
            q = quality(pts, tri)
        rounds.append(made)
    return pts, tri, q, rounds


def _held_stage(stage, polygon: Polygon, pts, tri, edges, q, what: str):
    """The chosen mesh after ``stage`` (:func:`~uniform2d.optimize.polish.polish_extremes`
    or :func:`~uniform2d.optimize.edge_cv.lower_edge_cv`: the points move with the
    triangulation held, the result kept only if better), checked if it moved:
    (points, triangles, quality, whether it moved)."""
    pts, tri, made = stage(polygon, pts, tri, edges)
    if made["kept"]:
        log.info("uniform: %s (edge ratio, longest edge, largest perimeter, edge CV, worst "
                 "angle: %s -> %s)", what, *(", ".join(f"{v:.4g}" for v in made[k])
                                             for k in ("before", "after")))
        ensure_valid(pts, tri, polygon, len(pts) - len(polygon.vertices), "uniform_mesh")
        q = quality(pts, tri)
    return pts, tri, q, made["kept"]


def _last_stages(polygon: Polygon, pts, tri, edges, q, allowed):
    """The chosen mesh after the angle fit (:func:`_fitted`; ``allowed``: the
    loose rounds' meshes it may keep), the polish (up to ``POLISH_MAX``
    points) and the CV stage (more than ``CV_STAGE_MIN`` and up to
    ``CV_STAGE_MAX`` points): (points, triangles, quality, the angle fit's
    rounds (held, loose), polished, CV lowered)."""
    pts, tri, q, fitted = _fitted(polygon, pts, tri, edges, q, allowed)
    n, polished, lowered = len(pts), False, False
    if n <= POLISH_MAX:
        pts, tri, q, polished = _held_stage(polish_extremes, polygon, pts, tri, edges, q,
                                            "polished")
    if CV_STAGE_MIN < n <= CV_STAGE_MAX:
        pts, tri, q, lowered = _held_stage(lower_edge_cv, polygon, pts, tri, edges, q,
                                           "edge CV lowered")
    return pts, tri, q, fitted, polished, lowered


def _small_holes(polygon: Polygon, h: float) -> bool:
    """Whether some hole of P has every edge shorter than ``SMALL_PIECE * h``:
    the holes the angle attempt puts rows around
    (:func:`~uniform2d.optimize.transition.transition_rows`), where the first
    mesh's worst angle is poor (the bolt plate's at 500 to 8000 vertices)."""
    E = polygon.edges
    L = np.hypot(*(polygon.vertices[E[:, 1]] - polygon.vertices[E[:, 0]]).T)
    offsets = polygon.ring_offsets
    return any(L[offsets[r]:offsets[r + 1]].max() < SMALL_PIECE * h
               for r in range(1, len(polygon.rings)))


def _angle_attempt_ahead(polygon: Polygon, n: int, h: float, objective: str, options):
    """The angle attempt (:func:`_finished` with ``angled``) started on a
    thread of its own beside the first mesh, or None: where P has small holes
    (:func:`_small_holes`, the first mesh's worst angle then poor and the
    attempt made) and more than one thread is allowed.  It is the same mesh
    whenever it is made: only the time it is made in changes."""
    if get_threads() <= 1 or n + len(polygon.vertices) > ANGLES_MAX or not _small_holes(polygon, h):
        return None
    return in_background(lambda: _finished(polygon, n, h, objective, options, _quiet,
                                           angled=True))


def _quiet(phase: str, done: int, total: int) -> None:
    """The angle attempt's progress: not reported (its phases ran once)."""


def _seed_then_relax(report, done: int, total: int) -> None:
    """The trials' progress as the ``seed`` phase; after the last, the winner's
    full schedule starts (the ``relaxation`` phase)."""
    report("seed", done, total)
    if done == total:
        report("relaxation", 0, 1)


#: The phases :func:`optimize_mesh` reports, in order (relocation only for
#: meshes of up to ``schedule.RELOCATE_MAX`` points).
PHASES = ("T+", "seed", "relaxation", "relocation")


def _reporter(progress):
    """``report(phase, done, total)``: logs each phase as it starts and passes
    every step on to the caller's ``progress`` callable, if any."""

    def report(phase: str, done: int, total: int) -> None:
        if done == 0:
            log.info("uniform: %s (%d step%s)", phase, total, "" if total == 1 else "s")
        if progress is not None:
            progress(phase, done, total)

    return report


def _reference(polygon: Polygon, n: int, start):
    """(T+'s info or None, its quality or None, d_n) to compare the optimised mesh with.

    Only T+'s measures are compared and reported (:func:`quality_summary`), not its
    bounds; a T+ made here is not kept (at 1e6 points its arrays would stand
    through the whole optimisation): the rare fallback makes it again
    (:func:`_tplus_again`)."""
    tp = start
    if tp is None:
        tp = tplus_if_feasible(polygon, n)
        if tp is None:  # too few points for T+, not for this method
            log.info("uniform: n = %d is too small for T+; nothing to compare with", n)
    if tp is None:  # d_n for the certificates comes from INSERT alone
        return None, None, min_distance_after(polygon, n)
    return tp.info, quality(tp.points, tp.triangles), tp.info.get("d_n")


class _Later:
    """``fn()`` on a thread of its own from the first :meth:`start` on
    (:meth:`result` starts it if nothing did)."""

    def __init__(self, fn):
        self._fn = fn
        self._future: Future | None = None

    def start(self) -> None:
        if self._future is None:
            self._future = in_background(self._fn)

    def result(self):
        self.start()
        return self._future.result()

    def wait(self) -> None:
        """Until it has ended, if it was started."""
        if self._future is not None:
            wait([self._future])


def _reference_ahead(polygon: Polygon, n: int, start) -> _Later | None:
    """:func:`_reference` (T+ and its measures, or d_n alone) to be made on a
    thread of its own beside the optimisation, or None (then made at once):
    where T+ is to be made here (``start`` None), more than one thread is
    allowed and the mesh has at most ``schedule.LARGE`` points (beyond, T+'s
    arrays would stand beside the optimiser's at its peak).  Nothing of the
    optimisation reads it before the end, and it is the same whenever it is
    made: :func:`optimize_mesh` starts it when the winner's schedule starts
    (the ``relaxation`` phase), on the core that serial stage leaves idle,
    not beside the trials, which keep every core busy."""
    if start is not None or get_threads() <= 1 or n + len(polygon.vertices) > S.LARGE:
        return None
    return _Later(lambda: _reference(polygon, n, None))


def _starting(report, later: _Later | None):
    """``report`` that also starts ``later`` (if any) when the ``relaxation``
    phase starts (see :func:`_reference_ahead`)."""
    if later is None:
        return report

    def on(phase: str, done: int, total: int) -> None:
        if phase == "relaxation":
            later.start()
        report(phase, done, total)

    return on


def _tplus_again(polygon: Polygon, n: int, start) -> Mesh:
    """The T+ :func:`_reference` compared with: the caller's, or made again
    (T+ is deterministic: the same mesh)."""
    tp = start if start is not None else tplus_if_feasible(polygon, n)
    if tp is None:
        raise InternalError(f"uniform: T+ for n = {n} could not be made again {PLEASE_REPORT}")
    return tp


def _kept(v_new, v_tp, q_new, q_tp, near_tie: float, info: dict) -> bool:
    """Whether the optimised mesh is kept over T+'s: its objective is no higher
    (``v_tp`` is inf without a T+), or, with ``near_tie`` > 0, at most that
    fraction higher and its edge CV lower (then ``info["near_tie"]`` is True)."""
    if v_new <= v_tp:
        return True
    if near_tie and q_tp is not None and v_new <= v_tp * (1 + near_tie) \
            and q_new.cv_edge < q_tp.cv_edge:
        info["near_tie"] = True
        return True
    return False


def quality_summary(q) -> dict | None:
    """The five measures of a :class:`~uniform2d.quality_result.Quality` that
    ``info["before"]`` and ``info["after"]`` report (None for None)."""
    if q is None:
        return None
    return {
        "edge_ratio": q.edge_ratio,
        "longest_edge": q.longest_edge,
        "max_perimeter": q.max_perimeter,
        "cv_edge": q.cv_edge,
        "min_angle": q.min_angle,
    }


def _angle_choice(polygon: Polygon, n: int, h: float, objective: str, options, first, ahead):
    """(the finished mesh kept, its quality, whether it is the angle attempt's):
    ``first`` (a :func:`_finished` tuple), or, where its worst angle is below
    ``ANGLE_FINE``, the angle attempt (``ahead``'s, or made now) if it wins
    (:func:`~uniform2d.optimize.angles.angle_attempt_wins`)."""
    q = quality(first[0], first[1])  # the measures: as for T+ (_reference)
    if len(first[0]) > ANGLES_MAX or q.min_angle >= ANGLE_FINE:
        return first, q, False
    log.info("uniform: worst angle %.1f deg; the angle attempt too", q.min_angle)
    other = (ahead.result() if ahead is not None
             else _finished(polygon, n, h, objective, options, _quiet, angled=True))
    q_other = quality(other[0], other[1])
    if angle_attempt_wins(q, q_other):
        return other, q_other, True
    return first, q, False


def optimize_mesh(
    polygon: Polygon,
    n: int,
    *,
    objective: str = "balanced",
    start: Mesh | None = None,
    progress=None,
    near_tie: float = 0.0,
    **options,
) -> Mesh:
    """The most uniform mesh with exactly ``n`` Steiner points (see :mod:`uniform2d.optimize`).

    ``start`` is the T+ mesh to beat (computed if not given, beside the
    optimisation where more than one thread is allowed, see
    :func:`_reference_ahead`, and then made again only if it is returned); ``options`` go to
    :func:`~uniform2d.optimize.improve`.  If n is too small for T+
    (:func:`uniform2d.tplus` raises
    :class:`~uniform2d.errors.InsufficientPointsError`), there is nothing to
    compare with: the optimised mesh is returned with ``info["start"]`` None, and
    d_n for its certificates comes from :func:`uniform2d.insert`.

    ``progress``, if given, is called as ``progress(phase, done, total)`` when each
    phase of :data:`PHASES` starts (``done`` 0) and as it advances (``done`` up to
    ``total``); it must not raise, except to stop the run (e.g. a
    ``KeyboardInterrupt``).  The phases are logged at INFO level either way.

    ``near_tie`` (0: off, the default): the optimised mesh is also kept when its
    objective is at most this fraction above T+'s and its edge CV is lower
    (``info["near_tie"]`` True then); :func:`uniform2d.uniform_mesh` with
    ``resample`` uses it.
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InsufficientPointsError(f"n must be a positive integer, got {n!r}")
    objective_code(objective)
    n = int(n)
    nV = len(polygon.vertices)
    report = _reporter(progress)
    report("T+", 0, 1)
    reference = _reference_ahead(polygon, n, start)
    made = _reference(polygon, n, start) if reference is None else None
    report("T+", 1, 1)

    h = target_size(polygon, n)
    ahead = _angle_attempt_ahead(polygon, n, h, objective, options)
    try:
        first = _finished(polygon, n, h, objective, options, _starting(report, reference))
    finally:  # not left running beyond this call, whatever happens
        wait([ahead] if ahead is not None else [])
        if reference is not None:
            reference.wait()
    tp_info, q_tp, d_n = made if reference is None else reference.result()
    chosen, q_new, angled = _angle_choice(polygon, n, h, objective, options, first, ahead)
    pts, tri, run, k, (spacing, edge, layered), moved, raised, edges = chosen
    v_tp = quality_objective(objective, q_tp, h) if q_tp is not None else math.inf
    # the loose angle rounds may trade edges, never to an objective above T+'s
    pts, tri, q_new, (fitted, loosened), polished, cv_lowered = _last_stages(
        polygon, pts, tri, edges, q_new, lambda q: quality_objective(objective, q, h) <= v_tp)
    v_new = quality_objective(objective, q_new, h)

    info = {
        "method": "uniform",
        "objective": objective,
        "d_n": d_n,
        "h": h,
        "k": int(k),
        "boundary_spacing": spacing,
        "lattice_edge": edge,
        "boundary_rows": layered,
        "relax_iterations": run["spring_rounds"],
        "sweeps": run["sweeps"],
        "relocated": moved,
        "angle_rounds": raised,
        "angle_attempt": angled,
        "angle_fits": fitted,
        "angle_first_fits": loosened,
        "polished": polished,
        "cv_lowered": cv_lowered,
        "start": (None if tp_info is None
                  else {"method": tp_info.get("method"), **quality_summary(q_tp), "objective": v_tp}),
        "before": quality_summary(q_tp),
        "after": quality_summary(q_new),
        "objective_value": v_new,
    }
    if not _kept(v_new, v_tp, q_new, q_tp, near_tie, info) or len(pts) != nV + n:
        if tp_info is None:
            raise InternalError(
                f"uniform: {len(pts) - nV} Steiner points instead of {n} {PLEASE_REPORT}")
        info["fallback"] = "tplus"
        info["after"] = quality_summary(q_tp)
        info["objective_value"] = v_tp
        log.info("uniform: optimised mesh (%g) not better than T+ (%g); returning T+", v_new, v_tp)
        tp = _tplus_again(polygon, n, start)
        return Mesh(np.array(tp.points), np.array(tp.triangles), polygon, n, {**tp_info, **info})
    info["fallback"] = None
    return Mesh(pts, tri, polygon, n, info)
