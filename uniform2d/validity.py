"""The check every mesh passes before the library returns it.

:func:`ensure_valid` runs the kernel's exact, cheap checks
(:func:`uniform2d._kernel.validity.mesh_problem`) with the polygon's boundary
tolerance, and turns a failure into an :class:`~uniform2d.errors.InternalError`
asking for a report: a mesh that fails is a bug, never the caller's input.
"""

from __future__ import annotations

from ._kernel.validity import mesh_problem
from .errors import InternalError
from .polygon import Polygon
from .tolerance import boundary_tol

__all__ = ["ensure_valid"]


def ensure_valid(points, triangles, polygon: Polygon, n_steiner: int, what: str) -> None:
    """Raise :class:`~uniform2d.errors.InternalError` unless the mesh is a valid
    triangulation of P with exactly ``n_steiner`` Steiner points (the checks of
    :mod:`uniform2d._kernel.validity`; cheap enough to run on every mesh returned)."""
    problem = mesh_problem(points, triangles, polygon, n_steiner, boundary_tol(polygon))
    if problem is not None:
        raise InternalError(
            f"{what} made an invalid mesh ({problem}). This is a bug in uniform2d, not a "
            f"problem with the input: please report it with the polygon "
            f"({len(polygon.vertices)} vertices, {polygon.n_holes} holes) and n = {n_steiner}"
        )
