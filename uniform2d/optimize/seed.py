"""The optimiser's starts: which it tries (:func:`variants`) and the sites of each (:func:`start`).

Boundary counts, lattice orientation and the seed's first layer fix the mesh's
structure, which moving points cannot change.  A start is the boundary split
evenly (:mod:`~uniform2d.optimize.boundary`), optionally a first row along it
(:mod:`~uniform2d.optimize.rows`), and a lattice for the rest
(:mod:`~uniform2d.optimize.lattice`, topped up by :mod:`~uniform2d.optimize.fill`,
shared among regions by :mod:`~uniform2d.optimize.shares`).
"""

from __future__ import annotations

import numpy as np

from .. import libm
from .._kernel.distance import to_segments
from ..geometry import is_vertex, polygon_edges
from ..polygon import Polygon
from . import schedule
from .boundary import boundary_counts, boundary_points, target_size
from .lattice import Fit, seed_interior
from .rows import boundary_rows
from .transition import with_transition

__all__ = ["start", "start_parts", "stripped", "variants"]


def variants(polygon: Polygon, n: int):
    """The starts tried: (boundary spacing / h, lattice edge, boundary rows).

    Boundary counts, lattice orientation and the seed's first layer decide the
    mesh's structure, which the point moves cannot change, and the best choice
    depends on the polygon.  Small meshes (up to ``schedule.SMALL`` points) try
    the lattice aligned with the longest edge and with the longest one at
    another angle (modulo 60 degrees), each with every boundary spacing of
    ``schedule.SPACINGS``, with and without a row of points on every edge
    (:func:`boundary_rows`); up to ``schedule.LARGE`` points the
    ``schedule.SPACINGS_MEDIUM`` with rows; beyond, where a start costs most,
    one start.  Meshes of more than ``schedule.STRIPS_MIN`` and up to
    ``schedule.SMALL`` points of a polygon without holes, segments or fixed
    points, whose edges are ``schedule.STRIP_PIECES`` target sizes long on
    average, add *strip starts* last: ``schedule.STRIP_DEPTHS`` rows along every
    edge (the third item is then that depth, an int).
    """
    _, d, L = polygon_edges(polygon)
    first = int(np.argmax(L))
    if n + len(polygon.vertices) > schedule.LARGE:
        return [(1.0, first, schedule.LAYERED_LARGE)]
    ang = np.degrees(libm.arctan2(d[:, 1], d[:, 0]))
    off = np.abs((ang - ang[first] + 30.0) % 60.0 - 30.0)
    other = [e for e in np.lexsort((np.arange(len(L)), -L)) if off[e] > 5.0]
    edges = [first] + ([int(other[0])] if other else [])
    strips = []
    if n + len(polygon.vertices) <= schedule.SMALL:
        spacings, layers = schedule.SPACINGS, schedule.LAYERED
        if stripped(polygon, n):
            strips = [(c, e, depth) for depth in schedule.STRIP_DEPTHS for e in edges
                      for c in schedule.STRIP_SPACINGS]
    else:
        spacings, layers = schedule.SPACINGS_MEDIUM, schedule.LAYERED_MEDIUM
    return [(c, e, lay) for lay in layers for e in edges for c in spacings] + strips


def stripped(polygon: Polygon, n: int) -> bool:
    """Whether the starts of a mesh of P with n Steiner points include strip
    starts (:func:`variants`): more than ``schedule.STRIPS_MIN`` and up to
    ``schedule.SMALL`` points, no holes, segments or fixed points, edges
    ``schedule.STRIP_PIECES`` target sizes long on average.  There every
    start of the optimiser leaves its deep lattice free (:func:`start`'s
    ``free``): the points a count off the lattice's puts near the boundary
    spread into it."""
    total = n + len(polygon.vertices)
    return (schedule.STRIPS_MIN < total <= schedule.SMALL and not polygon.n_holes
            and not polygon.has_constraints and polygon.perimeter
            >= schedule.STRIP_PIECES * len(polygon.vertices) * target_size(polygon, n))


def start_parts(polygon: Polygon, n: int, h: float, spacing: float, layered: bool,
                transition: bool = False):
    """What the starts of one boundary spacing and ``layered`` share, whatever
    their lattice: (boundary points, their polygon edges, first rows or None,
    rows around small holes or None), as :func:`start` makes them."""
    # points on the rings' edges and on the interior segment pieces (after them)
    a, d, L = polygon_edges(polygon, constraints=True)
    m = boundary_counts(L, spacing * h, n)
    bpts, beid, _ = boundary_points(a, d, m)
    if polygon.has_constraints:
        keep = ~is_vertex(polygon, bpts)
        bpts, beid = bpts[keep], beid[keep]
    rows = boundary_rows(polygon, m, spacing * h, depth=int(layered)) if layered else None
    held = None
    if transition:
        held, rows = with_transition(polygon, m, h, rows)
    return bpts, beid, rows, held


def start(polygon: Polygon, n: int, h: float, variant, transition: bool = False, lattice=None,
          shared=None, free: bool = False):
    """The sites of one start (boundary points, then the lattice), the polygon edge of
    each (-1 inside) and which stay put.  With ``transition``, rows around small
    holes first (:mod:`~uniform2d.optimize.transition`, held in place);
    ``lattice``: a shared lattice, as :func:`seed_interior`'s; ``shared``:
    :func:`start_parts` for this start's spacing, ``layered`` and ``transition``
    (made here if not given: the starts of two lattice edges share it);
    ``free``: no site stays put, the deep lattice included (the optimiser's
    starts where :func:`stripped`)."""
    spacing, edge, layered = variant
    if shared is None:
        shared = start_parts(polygon, n, h, spacing, layered, transition)
    bpts, beid, rows, held = shared
    a, d, _ = polygon_edges(polygon, constraints=True)
    # a large start's short schedule cannot close holes where lattice points
    # were dropped: it fills a few too few instead (Fit.BELOW)
    large = n + len(polygon.vertices) > schedule.LARGE
    ipts = seed_interior(polygon, n - len(bpts), h, bpts, edge, rows, beid,
                         Fit.BELOW if large else Fit.ABOVE, held, lattice)
    # the lattice deeper than BAND sizes inside P is uniform already: it stays,
    # unless ``free`` (see stripped: the count's defects near the boundary
    # spread into it)
    if free:
        deep = np.zeros(len(ipts), bool)
    else:
        deep = to_segments(ipts, a, a + d, 2.0 * schedule.BAND * h) > schedule.BAND * h
    if held is not None and len(held) < n - len(bpts):  # seed_interior puts them first
        deep[: len(held)] = True  # the rows around small holes stay
    frozen = np.concatenate([np.zeros(len(bpts), bool), deep])
    edges = np.concatenate([beid, np.full(len(ipts), -1, np.int64)])
    return np.concatenate([bpts, ipts]), edges, frozen, len(bpts)
