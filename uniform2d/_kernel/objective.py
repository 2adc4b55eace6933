"""The optimiser's objectives: their codes and their one formula.

Compiled code (:mod:`uniform2d._kernel.relax`) and the Python side
(:mod:`uniform2d.optimize.objective`) both evaluate an objective from three
measures of a mesh, each made scale-free by the caller:

* ``ratio``: longest edge / shortest edge;
* ``edge``: longest edge / target edge length;
* ``perimeter``: largest triangle perimeter / its target (three target lengths).

:func:`combine` is plain Python so that both can use it: the kernel compiles it,
the optimiser calls it directly.
"""

from __future__ import annotations

__all__ = ["BALANCED", "RATIO", "MAX_EDGE", "MAX_PERIMETER", "combine"]

#: Objective codes, in the order of :data:`uniform2d.optimize.OBJECTIVES`.
BALANCED, RATIO, MAX_EDGE, MAX_PERIMETER = 0, 1, 2, 3


def combine(objective, ratio, edge, perimeter):
    """The value minimised for objective code ``objective`` (lower is better).

    ``BALANCED`` is the geometric mean of the three measures, so that none of
    them drowns the others.
    """
    if objective == RATIO:
        return ratio
    if objective == MAX_EDGE:
        return edge
    if objective == MAX_PERIMETER:
        return perimeter
    return (ratio * edge * perimeter) ** (1.0 / 3.0)
