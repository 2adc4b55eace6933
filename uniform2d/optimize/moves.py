"""Moving the points of a mesh of P: the driver of the kernel :mod:`uniform2d._kernel.relax`.

:func:`improve` loads a mesh into the kernel once (:func:`_load`), runs the
stages of a :class:`~uniform2d.optimize.schedule.Schedule` on it and reads the
points back (:func:`_unload`); the kernel keeps the triangulation valid and
constrained Delaunay by exact predicates and flips while the points move.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._kernel import cdt, relax
from ..geometry import polygon_edges
from ..polygon import Polygon
from ..segment_chains import piece_chains, rebuild
from ..triangulation import boundary_tol, load_mesh, triangulate
from . import schedule as S
from .objective import objective_code
from .seed import target_size

__all__ = ["improve"]


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
        :func:`~uniform2d.optimize.seed.target_size`); ignored with a ``size`` field.
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
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    obj = objective_code(objective)
    P0, T0 = triangulate(polygon, sites, edges)
    nV = len(polygon.vertices)
    if len(P0) == nV:
        return P0, T0, {"spring_rounds": 0, "sweeps": 0, "edges": np.empty(0, np.int64)}
    st = _load(polygon, P0, T0, size, href, frozen, edges)
    del P0, T0  # loaded: the kernel holds the mesh now
    sched = S.schedule_for(len(st.xy), size is not None)._replace(
        **{k: v for k, v in dict(spring_rounds=spring_rounds, sweeps=sweeps, exponents=exponents,
                                 spread_sweeps=spread_sweeps).items() if v is not None}
    )
    rounds, done, value = _run(st, sched, obj)
    edges = st.eid[nV:].copy()
    sites = _unload(polygon, st)[nV:]
    del st  # the kernel's arrays go before the final triangulation builds its own
    points, triangles = triangulate(polygon, sites, edges)
    info = {
        "spring_rounds": int(rounds), "sweeps": int(done), "objective_value": value, "edges": edges,
    }
    return points, triangles, info


def _run(st: "_Loaded", sched: S.Schedule, obj: int):
    """The stages of ``sched`` on a loaded mesh: (spring rounds, sweeps, objective value)."""
    m, xy, t = st.m, st.xy, st.t
    args = (m, st.role, st.eid, t, st.ea, st.ed, st.hv, st.href)
    rounds = relax.spring(
        *args, iters=sched.spring_rounds, dt=S.SPRING_STEP, pressure=S.SPRING_PRESSURE,
        tol=S.SPRING_TOL, cap=S.SPRING_CAP, flat=S.FLAT,
    )
    done = 0
    value = None
    for k in sched.exponents:
        best_xy, best_t = xy.copy(), t.copy()
        best_tv = cdt.triangle_list(m).astype(np.int32).ravel()
        made, value = relax.descend(
            *args, objective=obj, sweeps=sched.sweeps, k=int(k), step0=S.SEARCH_STEP,
            best_xy=best_xy, best_t=best_t, best_tv=best_tv, flat=S.FLAT,
        )
        done += made
        # continue from the best state of this stage
        xy[:] = best_xy
        t[:] = best_t
        rebuild(m, best_tv.reshape(-1, 3), st.pieces)
    if sched.spread_sweeps:
        best_xy, best_t = xy.copy(), t.copy()
        best_tv = cdt.triangle_list(m).astype(np.int32).ravel()
        relax.spread(
            *args, objective=obj, sweeps=sched.spread_sweeps, step0=S.SEARCH_STEP,
            best_xy=best_xy, best_t=best_t, best_tv=best_tv, flat=S.FLAT,
        )
        xy[:] = best_xy
        t[:] = best_t
    return rounds, done, value


class _Loaded(NamedTuple):
    """A mesh loaded into the kernel (normalised coordinates; see :func:`_load`)."""

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
    pieces: tuple  # (us, vs): the segment pieces split at the points on them


def _load(polygon: Polygon, points, triangles, size, href, frozen, edges=None) -> _Loaded:
    """Load a mesh of P (its vertices first, then the sites) into the kernel, with
    the role of every point: polygon vertices and ``frozen`` sites fixed, sites
    on the boundary sliding along their edge, the others free; ``edges`` as
    :func:`improve`'s."""
    nV = len(polygon.vertices)
    T0 = np.asarray(triangles, dtype=np.int32)
    m, xy, centre, scale, boundary, graded = load_mesh(polygon, points, T0, size, edges)
    N = len(xy)
    a, d, _ = polygon_edges(polygon, constraints=True)
    role = np.full(N, relax.FREE, np.int8)
    role[:nV] = relax.FIXED
    eid = np.full(N, -1, np.int64)
    t = np.zeros(N)
    if frozen is not None:
        role[nV:][np.asarray(frozen, dtype=bool)] = relax.FIXED
    for i, e, ti in boundary:
        role[nV + i] = relax.SLIDE
        eid[nV + i] = e
        t[nV + i] = ti
    hv = np.ones(N)
    relax.refresh_sizes(m, hv, np.ones(N, np.bool_))
    if graded:  # the field's shape, scaled to the edges present
        E = np.concatenate([T0[:, [0, 1]], T0[:, [1, 2]], T0[:, [2, 0]]])
        Ls = np.hypot(*(xy[E[:, 1]] - xy[E[:, 0]]).T)
        hs = 0.5 * (hv[E[:, 0]] + hv[E[:, 1]])
        href_n = float(np.sqrt((Ls**2).mean() / (hs**2).mean()))
    else:
        href_n = (target_size(polygon, N - nV) if href is None else href) / scale
    return _Loaded(m, xy, role, eid, t, (a - centre) / scale, d / scale, hv, href_n, centre, scale,
                   piece_chains(polygon, boundary, boundary_tol(polygon)))


def _unload(polygon: Polygon, st: _Loaded) -> np.ndarray:
    """The kernel's points in the caller's coordinates, exactly: the kernel rounds
    every place to what these coordinates hold (:func:`uniform2d._kernel.cdt.snap`)."""
    out = st.xy * st.scale + st.centre
    out[: len(polygon.vertices)] = polygon.vertices
    return out
