"""The recommended entry point: :func:`uniform_mesh`."""

from __future__ import annotations

import math
import numbers

from .errors import InsufficientPointsError, InvalidArgumentError
from .geometry import vertex_count
from .mesh import Mesh
from .optimize import optimize_mesh
from .partitioned import partitioned_mesh
from .polygon import Polygon
from .resources import check_point_count

__all__ = ["uniform_mesh", "steiner_count_for_size"]


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
    objective: str = "balanced",
    progress=None,
    parts: int | None = None,
    jobs: int = 1,
    scheduler=None,
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

    ``parts=K`` makes the mesh in K parts meshed apart, in ``jobs`` local
    processes or on the Dask cluster of ``scheduler`` (an address or a
    ``distributed.Client``), and stitched (:mod:`uniform2d.partitioned`; see
    docs/partitioned.md): still exactly n points, the same bytes whatever ran
    the parts, but a different (equally valid) mesh for every K.

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
    if parts is not None:
        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
            raise InsufficientPointsError(f"n must be a positive integer, got {n!r}")
        return partitioned_mesh(polygon, int(n), parts, jobs=jobs, scheduler=scheduler,
                                objective=objective)
    # optimize_mesh checks the mesh it makes (ensure_valid); its fallback, T+, was checked
    return optimize_mesh(polygon, n, objective=objective, progress=progress)
