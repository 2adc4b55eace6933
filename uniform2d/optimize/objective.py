"""What the optimiser minimises: the objectives, by name, for Python callers.

The formula and the codes the compiled kernel uses live in
:mod:`uniform2d._kernel.objective`; this module maps the public names onto
them and evaluates a mesh.
"""

from __future__ import annotations

import numpy as np

from .._kernel.objective import BALANCED, MAX_EDGE, MAX_PERIMETER, RATIO, combine
from ..errors import InvalidArgumentError

__all__ = ["OBJECTIVES", "objective_code", "objective_value", "extremes", "quality_objective"]

#: The objectives by name: ``"ratio"`` (longest / shortest edge), ``"max_edge"``,
#: ``"max_perimeter"`` and ``"balanced"`` (the geometric mean of the three).
OBJECTIVES = ("balanced", "ratio", "max_edge", "max_perimeter")
_CODES = {"balanced": BALANCED, "ratio": RATIO, "max_edge": MAX_EDGE, "max_perimeter": MAX_PERIMETER}


def objective_code(objective: str) -> int:
    """The kernel's code for ``objective``; InvalidArgumentError for an unknown name."""
    if objective not in _CODES:
        raise InvalidArgumentError(f"objective must be one of {OBJECTIVES}, got {objective!r}")
    return _CODES[objective]


def objective_value(objective: str, longest: float, shortest: float, perimeter: float, h: float):
    """Scalar the objective pass minimises (lower is better); h makes it scale-free."""
    return combine(objective_code(objective), longest / shortest, longest / h, perimeter / (3 * h))


def extremes(points, tri):
    """(longest edge, shortest edge, largest perimeter) of a triangle mesh."""
    q = points[tri]
    L = np.linalg.norm(q - q[:, [1, 2, 0]], axis=2)
    return L.max(), L.min(), L.sum(axis=1).max()


def quality_objective(objective: str, q, h: float):
    """:func:`objective_value` of a :class:`~uniform2d.Quality`."""
    return objective_value(objective, q.longest_edge, q.shortest_edge, q.max_perimeter, h)
