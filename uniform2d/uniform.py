"""The recommended entry point: :func:`uniform_mesh`."""

from __future__ import annotations

import dataclasses
import logging
import math
import numbers

import numpy as np

from .errors import InsufficientPointsError, InvalidArgumentError
from .geometry import vertex_count
from .graded import graded_mesh
from .graded_outline import resample_for_field
from .grading import as_field, count_for_field, field_integrals
from .corner_merge import corner_policy
from .mesh import Mesh
from .optimize import optimize_mesh
from .outline import (
    COARSE_SPACING,
    CORNER_ANGLE,
    is_coarse,
    resample_polygon,
    short_edge_warning,
)
from .partitioned import partitioned_mesh
from .polygon import Polygon
from .resources import check_point_count
from .ring_nudge import nudged
from .ring_relocate import relocated
from .ring_shorten import shortened
from .ring_split import (
    SPLIT_RATIO, better_angle, better_mesh, edges_for_angle, edges_to_halve, halve_edges,
)
from .short_edges import resampled_warning

__all__ = ["uniform_mesh", "steiner_count_for_size", "resampled_outline"]

log = logging.getLogger(__name__)

#: With ``resample``, the optimised mesh is kept over T+'s when its objective is at
#: most this fraction above T+'s and its edge CV lower (``optimize_mesh``'s
#: ``near_tie``): a resampled outline's T+ mesh can win the objective by a hair
#: with a CV more than twice the optimised mesh's.
NEAR_TIE = 0.01


def steiner_count_for_size(polygon: Polygon, size: float) -> int:
    """Number of Steiner points n for a target edge length ``size``.

    n = N − |V| (at least 0), N the vertex count of a mesh of equilateral
    triangles of side ``size`` (:func:`uniform2d.geometry.vertex_count`).

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> steiner_count_for_size(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), 0.1)
    132
    """
    if not (isinstance(size, numbers.Real) and math.isfinite(size) and size > 0):
        raise InvalidArgumentError(f"size must be a positive finite number, got {size!r}")
    N = vertex_count(polygon.area, polygon.perimeter, size, polygon.n_holes)
    return max(0, round(N) - len(polygon.vertices))


def uniform_mesh(
    polygon: Polygon,
    n: int | None = None,
    *,
    size=None,
    resample: float | None = None,
    corner_angle: float = CORNER_ANGLE,
    resample_corners: str = "keep",
    objective: str = "balanced",
    progress=None,
    parts: int | None = None,
    jobs: int = 1,
    scheduler=None,
) -> Mesh:
    """The most uniform mesh uniform2d makes, with exactly ``n`` Steiner points.

    Give ``n`` (Steiner points, boundary and interior), ``size`` or both.
    ``size`` is a target edge length (a number: the mesh is uniform, and without
    ``n`` its count is :func:`steiner_count_for_size`), or a size field for a
    graded mesh: a :class:`~uniform2d.SizeField` or a callable ``h(points (k, 2))
    -> (k,)`` (sampled on a grid, :func:`uniform2d.grading.as_field`).  With a
    field and ``n``, h's shape is kept and its scale follows from n; without
    ``n``, h is absolute and n is the count it implies
    (:func:`uniform2d.grading.count_for_field`).  A graded mesh is made by
    :func:`uniform2d.graded.graded_mesh` (guide: ``docs/graded.md``): its edges
    are as uniform as possible *relative to h* and ``mesh.quality().relative``
    measures that.  With a number, ``n`` and ``size`` together are an error.
    The mesh is optimised (:func:`uniform2d.optimize.optimize_mesh`) for
    ``objective``: ``"ratio"`` (longest / shortest edge), ``"max_edge"``,
    ``"max_perimeter"`` or ``"balanced"`` (all three), and is never worse on it than
    the paper's T+ (:func:`uniform2d.tplus`), which it falls back to otherwise.
    Any n >= 1 works, also one too small for T+ (there is then nothing to compare
    with, and ``mesh.info["start"]`` is None).  An n whose mesh cannot fit in this
    machine's memory is refused at once
    (:class:`~uniform2d.errors.TooManyPointsError`, also a ``MemoryError``).

    ``progress``, if given, is a callable ``progress(phase, done, total)`` told
    how the run advances through its phases (``"T+"``: INSERT and T+ to compare
    with; ``"seed"``: the starts tried; ``"relaxation"``; ``"relocation"``), for a
    progress bar; the library itself never prints, it logs the phases (INFO).

    ``parts=K`` makes the mesh in K parts meshed apart, in ``jobs`` local
    processes or on the Dask cluster of ``scheduler`` (an address or a
    ``distributed.Client``), and stitched (:mod:`uniform2d.partitioned`; see
    docs/partitioned.md): still exactly n points, the same bytes whatever ran
    the parts, but a different (equally valid) mesh for every K.

    ``resample=tol`` (a fraction of the mesh spacing, e.g. 0.05 or 0.25) first
    resamples the polygon's rings at the mesh spacing, every boundary point within
    ``tol`` x spacing of the outline and the outline within that of the rings
    (:func:`uniform2d.outline.resample_polygon`): corners turning by more than
    ``corner_angle`` degrees, and ring vertices that segments or fixed points
    touch, stay; the other input ring vertices go, and the boundary points that
    replace them count in n (they are slid along the outline to even out the ring
    edges, within the tolerance: :mod:`uniform2d.ring_slide`); where the mesh's
    edge ratio is above 2, whole ring edges that set its longest edge are halved
    (:mod:`uniform2d.ring_split`), points relocated into corners with one
    triangle (:mod:`uniform2d.ring_relocate`) and ring points at the ends of
    its too-short edges moved off them within the tolerance, the mesh relaxed
    there (:mod:`uniform2d.ring_nudge`), then those at the ends of its too-long
    edges moved towards them (:mod:`uniform2d.ring_shorten`), each kept only if
    the ratio drops. Where the worst angle is below 35 degrees on a whole ring
    edge of 1.25 mean edges or more (also on a polygon meshed as given), the
    long whole ring edges are halved and the mesh kept if its worst angle is
    larger (:func:`uniform2d.ring_split.edges_for_angle`).
    ``resample_corners="merge"`` lets a corner with a ring point less than 0.6
    spacings away merge with it into one point on the outline between them where
    the tolerance still holds (:mod:`uniform2d.corner_merge`: that corner is then
    followed within the tolerance, not kept as a vertex; the default ``"keep"``
    keeps every corner).  So ``len(mesh.points)`` is n plus the kept vertices,
    ``mesh.polygon`` is the resampled polygon (``mesh.n_steiner`` counts the points
    beyond its vertices), and ``mesh.info["resample"]`` says the tolerance, the
    deviation reached (a length, and as a fraction of the spacing), the kept
    vertices and ``"n"``.  A polygon with no edge shorter than 0.6 of the
    spacing is meshed as given (``info["resample"]["resampled"]`` False); a
    coarse one (edges of a third to 0.6 of it, none shorter) is resampled with
    its boundary points at 1.05 spacings (``info["resample"]["boundary_spacing"]``,
    :func:`uniform2d.outline.is_coarse`).  With a size field the rings are
    resampled at its local spacing and always, then meshed graded
    (:func:`uniform2d.graded_outline.resample_for_field`; ``info["resample"]
    ["spacing"]`` is then the finest local spacing on the rings).  With ``parts``
    it is refused (not supported yet).  Without it
    (the default, the paper's mode) every vertex is kept; when that makes a
    uniform mesh impossible (an edge shorter than a third of the spacing)
    ``mesh.info["warning"]`` says so, and it is logged (a warning if the edge
    ratio it forces is 10 or more, information otherwise).

    Examples
    --------
    >>> from uniform2d import Polygon, uniform_mesh
    >>> mesh = uniform_mesh(Polygon([(0, 0), (2, 0), (2, 1), (0, 1)]), size=0.25)
    >>> mesh.n_steiner
    46
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    field = as_field(polygon, size)
    if corner_policy(resample_corners) and (resample is None or field is not None):
        raise InvalidArgumentError(
            "resample_corners='merge' works with resample= and a uniform size only (it "
            "merges corners of the resampled outline); add resample=TOL or drop it")
    if resample is not None and parts is not None:
        raise InvalidArgumentError("resample= works with a mesh in one part: parts= with it "
                                   "is not supported yet; drop one of them")
    if field is not None:
        if parts is not None:
            raise InvalidArgumentError("parts= makes a uniform mesh in parts; a size field "
                                       "(graded mesh) cannot be split yet: drop one of them")
        return _graded(polygon, n, field, objective, progress, resample, corner_angle)
    if (n is None) == (size is None):
        raise InvalidArgumentError("give exactly one of n (number of Steiner points) and size")
    if resample is not None:
        return _resampled_mesh(polygon, n, size, resample, corner_angle, objective, progress,
                               resample_corners)
    n, what = _count(n, lambda: steiner_count_for_size(polygon, size), f"size {size!r}",
                     "use a smaller size")
    if isinstance(n, numbers.Integral) and not isinstance(n, bool):
        check_point_count(n + len(polygon.vertices), what)
    if parts is not None:
        return partitioned_mesh(polygon, _positive_count(n), parts, jobs=jobs, scheduler=scheduler,
                                objective=objective)
    # optimize_mesh checks the mesh it makes (ensure_valid); its fallback, T+, was checked
    mesh = optimize_mesh(polygon, n, objective=objective, progress=progress)
    warning = short_edge_warning(polygon, n)
    if warning is not None:
        log.log(warning[1], "%s", warning[0])
        mesh.info["warning"] = warning[0]
    return mesh


def _resampled_mesh(polygon, n, size, tol, corner_angle, objective, progress,
                    corners="keep") -> Mesh:
    """:func:`uniform_mesh` with ``resample=tol``: the rings resampled, then meshed."""
    res, left = resampled_outline(polygon, n, size=size, resample=tol, corner_angle=corner_angle,
                                  resample_corners=corners)
    n_total = left + res.n_boundary
    what = f"n = {n}" if size is None else f"size {size!r} (n = {n_total})"
    if left < 1:
        raise InsufficientPointsError(
            f"{what} leaves no point inside once the boundary is resampled ({res.n_boundary} "
            f"boundary points at spacing {res.spacing:.4g}); ask for more points (a larger n "
            "or a smaller size)")
    check_point_count(left + len(res.polygon.vertices), what)
    log.info("resampled outline: %d vertices kept, %d boundary points, deviation %.3g "
             "(%.3f of the spacing %.4g)", res.n_kept, res.n_boundary, res.deviation,
             res.deviation / res.spacing, res.spacing)
    tie = NEAR_TIE if res.resampled else 0.0  # as given: the mesh without resample
    mesh = optimize_mesh(res.polygon, left, objective=objective, progress=progress, near_tie=tie)
    split = moves = nudge = short = 0
    if res.resampled:
        res, left, mesh, split = _halved(res, left, mesh, objective)
    res, left, mesh, for_angle = _halved_for_angle(res, left, mesh, objective)
    if res.resampled:
        mesh, moves = relocated(mesh, objective)
        res, mesh, nudge = nudged(polygon, res, mesh, objective)
        if nudge:  # the moved rings may leave chords relocation can break now
            mesh, more = relocated(mesh, objective)
            moves += more
        res, mesh, short = shortened(polygon, res, mesh, objective)
        if short:
            mesh, more = relocated(mesh, objective)
            moves += more
    out = Mesh(mesh.points, mesh.triangles, mesh.polygon, mesh.n_steiner,
               {**mesh.info, "resample": {**res.info(), "n": n_total, "halved_edges": split,
                                          "halved_for_angle": for_angle,
                                          "relocated": moves, "nudged": nudge,
                                          "shortened": short}})
    warning = resampled_warning(out, res.kept)
    if warning is not None:
        log.log(warning[1], "%s", warning[0])
        out.info["warning"] = warning[0]
    return out


def _halved(res, left, mesh, objective):
    """(res, left, mesh, edges halved): the mesh again with the ring edges
    :func:`uniform2d.ring_split.edges_to_halve` names halved, if it is the
    better one (:func:`uniform2d.ring_split.better_mesh`);
    tried only where the first mesh's ratio is above ``SPLIT_RATIO`` and the
    shortest ring edge allows one that low."""
    q = mesh.quality()
    V, E = res.polygon.vertices, res.polygon.edges
    ring_edge = float(np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T).min())
    if q.edge_ratio <= SPLIT_RATIO or q.mean_edge > SPLIT_RATIO * ring_edge:
        return res, left, mesh, 0
    pairs = edges_to_halve(res.polygon, mesh.points, mesh.triangles)
    return _with_halves(res, left, mesh, q, pairs, objective, better_mesh, "edge_ratio")


def _halved_for_angle(res, left, mesh, objective):
    """(res, left, mesh, edges halved): the mesh again with the whole ring edges
    :func:`uniform2d.ring_split.edges_for_angle` names halved (a worst angle
    below 35 degrees on a long ring edge), if it is the better one
    (:func:`uniform2d.ring_split.better_angle`).  Also for an outline meshed
    as given: its own long edges are as much a thin triangle's long side."""
    pairs = edges_for_angle(res.polygon, mesh.points, mesh.triangles)
    return _with_halves(res, left, mesh, None, pairs, objective, better_angle, "min_angle")


def _with_halves(res, left, mesh, q, pairs, objective, better, measure: str):
    """(res, left, mesh, edges halved): the mesh made again with the ring edges
    ``pairs`` halved if ``better(its quality, q)`` (``q``: ``mesh``'s quality,
    measured here if None), else the inputs and 0; ``measure``: the quality
    field the log names."""
    if not len(pairs) or len(pairs) >= left:
        return res, left, mesh, 0
    res2 = halve_edges(res, pairs)
    left2 = left - len(pairs)
    mesh2 = optimize_mesh(res2.polygon, left2, objective=objective, near_tie=NEAR_TIE)
    q = mesh.quality() if q is None else q
    q2 = mesh2.quality()
    if better(q2, q):
        log.info("outline: %d ring edges halved, %s %.4g (%.4g with them whole)", len(pairs),
                 measure, getattr(q2, measure), getattr(q, measure))
        return res2, left2, mesh2, len(pairs)
    return res, left, mesh, 0


def resampled_outline(polygon: Polygon, n: int | None = None, *, size=None, resample: float,
                      corner_angle: float = CORNER_ANGLE, resample_corners: str = "keep"):
    """The outline ``uniform_mesh(polygon, n, size=size, resample=resample)`` meshes.

    Cheap next to the mesh: it says how many input vertices stay vertices
    (``n_kept``) before meshing, e.g. to ask for a total vertex count.

    Returns
    -------
    uniform2d.outline.Resampled
        The polygon the mesher gets (the input as given when no edge is too short
        for the spacing: ``resampled`` False).
    int
        The Steiner points left for the interior.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    >>> res, left = resampled_outline(Polygon(np.c_[np.cos(t), np.sin(t)]), 500, resample=0.25)
    >>> res.n_kept, res.n_boundary + left
    (0, 500)
    """
    field = as_field(polygon, size)
    if field is not None:
        if corner_policy(resample_corners):
            raise InvalidArgumentError("resample_corners='merge' works with a uniform size "
                                       "only, not a size field; drop it")
        n = count_for_field(polygon, field) if n is None else _positive_count(n)
        res, left, _ = resample_for_field(polygon, n, field, tolerance=resample,
                                          corner_angle=corner_angle)
        return res, left
    if size is not None:
        steiner_count_for_size(polygon, size)  # the same checks of size
    else:
        _positive_count(n)
    res, left = resample_polygon(polygon, n, size=size, tolerance=resample,
                                 corner_angle=corner_angle, corners=resample_corners)
    if res.resampled and is_coarse(polygon, res.spacing):  # see uniform2d.outline.COARSE_SPACING
        res, left = resample_polygon(polygon, n, size=size, tolerance=resample,
                                     corner_angle=corner_angle, boundary_spacing=COARSE_SPACING,
                                     corners=resample_corners)
    if not res.resampled:  # no edge too short for this spacing: the paper's mode, as given
        res = dataclasses.replace(res, polygon=polygon)
        left = n if size is None else steiner_count_for_size(polygon, size)
    return res, left


def _graded(polygon: Polygon, n, field, objective: str, progress, tol=None,
            corner_angle=CORNER_ANGLE) -> Mesh:
    """:func:`uniform_mesh` with a size field: n checked or implied, the rings
    resampled at the local spacing if ``tol`` is given, then graded_mesh."""
    integrals = field_integrals(polygon, field)
    n, what = _count(n, lambda: count_for_field(polygon, field), "the size field",
                     "use smaller sizes or give n")
    n = _positive_count(n)
    check_point_count(n + len(polygon.vertices), what)
    if tol is None:
        return graded_mesh(polygon, n, field, objective=objective, progress=progress,
                           integrals=integrals)
    res, left, integrals = resample_for_field(polygon, n, field, tolerance=tol,
                                              corner_angle=corner_angle)
    if left < 1:
        raise InsufficientPointsError(
            f"{what} leaves no point inside once the boundary is resampled at the size "
            f"field's local spacing ({res.n_boundary} boundary points); ask for more points")
    log.info("resampled outline at the local spacing: %d vertices kept, %d boundary points, "
             "deviation %.3g (%.3f of the finest spacing %.4g)", res.n_kept, res.n_boundary,
             res.deviation, res.deviation / res.spacing, res.spacing)
    mesh = graded_mesh(res.polygon, left, field, objective=objective, progress=progress,
                       integrals=integrals)
    return Mesh(mesh.points, mesh.triangles, mesh.polygon, mesh.n_steiner,
                {**mesh.info, "resample": {**res.info(), "n": n}}, size=mesh.size)


def _count(n, implied, source: str, fix: str) -> tuple:
    """(n, how it was asked for): ``n`` as given, else ``implied()`` from
    ``source`` (a size or a size field), refused if that asks for no point."""
    if n is not None:
        return n, f"n = {n}"
    n = implied()
    if n < 1:
        raise InsufficientPointsError(
            f"{source} is larger than the polygon needs: it asks for no Steiner points; {fix}")
    return n, f"{source} (n = {n})"


def _positive_count(n) -> int:
    """``n`` as an int, or InsufficientPointsError if it is not a positive integer."""
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InsufficientPointsError(f"n must be a positive integer, got {n!r}")
    return int(n)
