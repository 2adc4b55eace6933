"""The recommended entry point: :func:`uniform_mesh`."""

from __future__ import annotations

import dataclasses
import logging
import math
import numbers

from .errors import InsufficientPointsError, InvalidArgumentError
from .geometry import vertex_count
from .mesh import Mesh
from .optimize import optimize_mesh
from .outline import CORNER_ANGLE, resample_polygon, short_edge_warning
from .polygon import Polygon
from .resources import check_point_count

__all__ = ["uniform_mesh", "steiner_count_for_size"]

log = logging.getLogger(__name__)


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
    size: float | None = None,
    resample: float | None = None,
    corner_angle: float = CORNER_ANGLE,
    objective: str = "balanced",
    progress=None,
) -> Mesh:
    """The most uniform mesh uniform2d makes, with exactly ``n`` Steiner points.

    Give exactly one of ``n`` (Steiner points, boundary and interior) and ``size``
    (a target edge length; n is derived by :func:`steiner_count_for_size`).
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

    ``resample=tol`` (a fraction of the mesh spacing, e.g. 0.05 or 0.25) first
    resamples the polygon's rings at the mesh spacing, every boundary point within
    ``tol`` x spacing of the outline and the outline within that of the rings
    (:func:`uniform2d.outline.resample_polygon`): corners turning by more than
    ``corner_angle`` degrees, and ring vertices that segments or fixed points
    touch, stay; the other input ring vertices go, and the boundary points that
    replace them count in n.  So ``len(mesh.points)`` is n plus the kept vertices,
    ``mesh.polygon`` is the resampled polygon (``mesh.n_steiner`` counts the points
    beyond its vertices), and ``mesh.info["resample"]`` says the tolerance, the
    deviation reached (a length, and as a fraction of the spacing), the kept
    vertices and ``"n"``.  A polygon with no edge shorter than a third of the
    spacing is meshed as given (``info["resample"]["resampled"]`` False).  Without it (the default, the paper's mode) every vertex
    is kept; when that makes a uniform mesh impossible (an edge shorter than a
    third of the spacing) a warning is logged and kept in ``mesh.info["warning"]``.

    Examples
    --------
    >>> from uniform2d import Polygon, uniform_mesh
    >>> mesh = uniform_mesh(Polygon([(0, 0), (2, 0), (2, 1), (0, 1)]), size=0.25)
    >>> mesh.n_steiner
    46
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    if (n is None) == (size is None):
        raise InvalidArgumentError("give exactly one of n (number of Steiner points) and size")
    if resample is not None:
        return _resampled_mesh(polygon, n, size, resample, corner_angle, objective, progress)
    what = f"n = {n}"
    if n is None:
        n = steiner_count_for_size(polygon, size)
        what = f"size {size!r} (n = {n})"
        if n < 1:
            raise InsufficientPointsError(
                f"size {size!r} is larger than the polygon needs: it asks for no Steiner "
                "points; use a smaller size"
            )
    if isinstance(n, numbers.Integral) and not isinstance(n, bool):
        check_point_count(n + len(polygon.vertices), what)
    # optimize_mesh checks the mesh it makes (ensure_valid); its fallback, T+, was checked
    mesh = optimize_mesh(polygon, n, objective=objective, progress=progress)
    warning = short_edge_warning(polygon, n)
    if warning is not None:
        log.log(warning[1], "%s", warning[0])
        mesh.info["warning"] = warning[0]
    return mesh


def _resampled_mesh(polygon, n, size, tol, corner_angle, objective, progress) -> Mesh:
    """:func:`uniform_mesh` with ``resample=tol``: the rings resampled, then meshed."""
    if size is not None:
        steiner_count_for_size(polygon, size)  # the same checks of size
    elif isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InsufficientPointsError(f"n must be a positive integer, got {n!r}")
    res, left = resample_polygon(polygon, n, size=size, tolerance=tol, corner_angle=corner_angle)
    if not res.resampled:  # no edge too short for this spacing: the paper's mode, as given
        res = dataclasses.replace(res, polygon=polygon)
        left = n if size is None else steiner_count_for_size(polygon, size)
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
    mesh = optimize_mesh(res.polygon, left, objective=objective, progress=progress)
    return Mesh(mesh.points, mesh.triangles, mesh.polygon, mesh.n_steiner,
                {**mesh.info, "resample": {**res.info(), "n": n_total}})
