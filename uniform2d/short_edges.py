"""When a polygon's own edges make a uniform mesh impossible (the paper's mode).

The paper keeps every polygon vertex, so a polygon edge much shorter than the
mesh spacing is a mesh edge and sets the edge ratio; :func:`short_edge_warning`
says so, and suggests resampling the outline (:mod:`uniform2d.outline`).
"""

from __future__ import annotations

import logging

import numpy as np

from .geometry import size_for_count
from .polygon import Polygon

__all__ = ["SEVERE", "SHORT_EDGE", "short_edge_warning"]

#: A polygon edge shorter than this fraction of the mesh spacing makes a uniform
#: mesh impossible: the mesh keeps it, so its edge ratio is at least about 1 / SHORT_EDGE.
SHORT_EDGE = 1 / 3
#: The edge ratio the polygon's own edges force from which that is a warning (below,
#: information kept in ``Mesh.info``).
SEVERE = 10.0


def short_edge_warning(polygon: Polygon, n: int) -> tuple[str, int] | None:
    """Why ``polygon``'s own edges make a uniform mesh of n points impossible, or None.

    The criterion: a constraint edge (ring or segment piece) shorter than
    :data:`SHORT_EDGE` of the spacing h of an equilateral mesh with |V| + n
    vertices; the mesh keeps that edge, so its edge ratio is at least about h
    over it.  Returns the message and its logging level: ``WARNING`` when that
    ratio is at least :data:`SEVERE` (a digitised outline far finer than the
    mesh), ``INFO`` below (a small hole's chords at a coarse n, say).

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> print(short_edge_warning(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), 100))
    None
    """
    h = size_for_count(polygon.area, polygon.perimeter, n + len(polygon.vertices), polygon.n_holes)
    E = polygon.constraint_edges
    V = polygon.vertices
    L = np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T)
    short = int((L < SHORT_EDGE * h).sum())
    if not short:
        return None
    ratio = h / L.min()
    message = (f"{short} of the polygon's {len(L)} edges are shorter than a third of the mesh "
               f"spacing {h:.4g} (the shortest {L.min():.3g}, spacing / {ratio:.3g}): the mesh "
               f"keeps every polygon vertex, so its edge ratio is at least about {ratio:.3g}; "
               "resample the outline (resample=0.25, or --resample 0.25 on the command line)")
    return message, logging.WARNING if ratio >= SEVERE else logging.INFO
