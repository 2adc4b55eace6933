"""The quality certificate: a mesh's measures against lower bounds on the optimum.

:func:`quality` measures a triangle mesh the way the paper's three problems do
(edge-length ratio, longest edge, largest triangle perimeter, with the usual
angle and spread statistics: :mod:`uniform2d.measures`) and, given the polygon,
compares them with *lower bounds on the optimum over every triangulation of the
polygon with the same number of Steiner points* (:mod:`uniform2d.bounds`).
Dividing what the mesh achieves by such a bound gives a certified approximation
factor for this instance: the mesh is provably within that factor of the best
possible one.  The packing terms need INSERT's d_n, so this module sits above
:mod:`uniform2d.insert`.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from .bounds import BOUND_SLACK, Term, is_convex, lower_bound_terms
from .errors import InvalidArgumentError
from .insert import min_distance_after
from .lattice_bound import lattice_ratio_floor
from .measures import as_points, as_triangles, mesh_measures
from .polygon import Polygon, as_polygon
from .quality_result import Bound, Quality
from .relative import relative_measures

__all__ = ["quality", "Quality", "Bound", "BOUND_SLACK"]

log = logging.getLogger(__name__)


def _make_bound(terms: list[Term], achieved: float) -> Bound:
    lowered = [(t.name, float(t.value) * (1.0 - BOUND_SLACK)) for t in terms]
    best = max(range(len(terms)), key=lambda i: (lowered[i][1], -i))  # ties: first listed
    name, value = lowered[best]
    factor = achieved / value if value > 0 else math.inf
    return Bound(value, name, tuple(lowered), float(achieved), float(factor), terms[best].detail)


# -- the bounds' inputs ---------------------------------------------------------
def _packing_distance(polygon: Polygon, n: int) -> float:
    """d_n of Algorithm INSERT: the least distance among V and the n inserted points."""
    if n == 0:
        return polygon.min_vertex_distance()
    return min_distance_after(polygon, n)


def _checked_d_n(d_n, poly: Polygon, n: int, convex: bool) -> float | None:
    """The packing distance the packing terms use, or None when they do not apply."""
    if d_n is False:
        return None
    if d_n is None:
        return _packing_distance(poly, n) if convex else None
    dn = float(d_n)
    if not (math.isfinite(dn) and dn > 0):
        raise InvalidArgumentError(f"d_n must be a positive finite distance, got {d_n!r}")
    lvv = poly.min_vertex_distance()
    if dn > lvv * (1 + 1e-12):
        raise InvalidArgumentError(
            f"d_n = {dn!r} exceeds l(V, V) = {lvv!r}, the least distance between polygon "
            "vertices; no packing reaches that, so it cannot be a valid d_n"
        )
    if not convex:
        log.info("d_n ignored: the packing bound (Lemma 9) needs a convex polygon without holes")
        return None
    return dn


def _steiner_count(n_steiner, n_points: int, n_v: int) -> int:
    """The n the bounds assume: ``n_steiner``, or the mesh's points beyond V."""
    if n_steiner is None:
        n = n_points - n_v
        if n < 0:
            raise InvalidArgumentError(
                f"the mesh has {n_points} points but the polygon has {n_v} vertices; "
                "pass n_steiner explicitly"
            )
        return n
    n = int(n_steiner)
    if n < 0:
        raise InvalidArgumentError(f"n_steiner must be >= 0, got {n_steiner}")
    return n


def quality(points, triangles, polygon=None, *, n_steiner=None, d_n=None, bins=20,
            size=None) -> Quality:
    """Measure a triangle mesh and, given its polygon, certify how close to optimal it is.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Vertex coordinates, float64.  Not modified.
    triangles : array_like, shape (M, 3)
        Vertex indices of each triangle, integers.  Not modified.
    polygon : Polygon, optional
        The polygon P the mesh triangulates (a :class:`~uniform2d.Polygon`, a
        shapely Polygon, or an outer ring).  When given, lower bounds on the
        optimum are computed (see Notes).
    n_steiner : int, optional
        Number n of Steiner points the bounds compare against.  Defaults to
        ``N - |V|``.
    d_n : float or False, optional
        A packing distance for the packing terms: the least distance among V and
        *any* n points of P (so that d_n <= d_n*).  If not given and P is convex
        without holes, it is computed by running Algorithm INSERT
        (:func:`uniform2d.insert`) for n points (for n = 0 it is l(V, V)).
        ``False`` turns the packing terms off.  Ignored for other polygons.
    bins : int, optional
        Number of histogram bins of ``length / mean_edge`` (default 20).
    size : callable, optional
        A size field h (a :class:`~uniform2d.SizeField` or ``h(points (k, 2)) ->
        (k,)``): ``Quality.relative`` then holds the measures relative to it
        (:func:`uniform2d.relative.relative_measures`: q = length / h(midpoint)).
        The certificates stay those of the absolute measures: they bound every
        triangulation with n Steiner points, graded or not, but say nothing about q.

    Returns
    -------
    Quality
        Frozen dataclass of measures; see :class:`Quality`.

    Raises
    ------
    InvalidArgumentError
        (a :class:`~uniform2d.Uniform2dError` and ``ValueError``) If an array has the wrong shape, a non-finite coordinate or an index
        out of range, if there are no triangles, if ``N < |V|`` and
        ``n_steiner`` is not given, or if ``d_n`` exceeds l(V, V) (no packing
        can).

    Notes
    -----
    The bounds hold for every triangulation of P whose vertices are V and at
    most n further points; each is the largest of its terms
    (:func:`uniform2d.bounds.lower_bound_terms`), lowered by a relative
    :data:`BOUND_SLACK` (1e-9) so that rounding cannot lift it above the true
    value, and ``Bound.term`` names the active one.  One edge-ratio term,
    ``lattice`` (:func:`uniform2d.lattice_bound.lattice_ratio_floor`), holds
    for exactly n further points and is used only for a mesh with exactly
    |V| + n points.  The terms and their proofs,
    with interior segments and fixed points too, are in the user guide,
    ``docs/guide.md``, section 6 ("The quality report and its certificates").

    Examples
    --------
    A unit square cut by one diagonal (n = 0 Steiner points):

    >>> from uniform2d import Polygon
    >>> from uniform2d.quality import quality
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> q = quality(sq.vertices, [(0, 1, 2), (0, 2, 3)], sq)
    >>> q.n_edges, q.n_boundary_edges, round(q.edge_ratio, 4), q.max_angle
    (5, 4, 1.4142, 90.0)
    >>> q.t_max, round(q.longest_edge_bound.value, 4), q.longest_edge_bound.term
    (2, 1.0746, 'area')
    >>> round(q.longest_edge_bound.factor, 3)      # certified: at most 1.316 x the optimum
    1.316
    >>> q.edge_ratio_bound.term, round(q.edge_ratio_bound.value, 4)
    ('corner', 1.3066)
    >>> q.edge_ratio_bound.active
    'corner (90 deg at (0, 0), best split in 2)'
    >>> print(q.summary())                          # doctest: +ELLIPSIS
    Certified against every triangulation of the polygon with n = 0 Steiner points:
      Longest edge       within 31.6 % of the best possible   bound: area (2 triangles at most)
    ...
      Edge ratio         within 8.24 % of the best possible   bound: corner (90 deg at (0, 0), best split in 2)
    <BLANKLINE>
    Mesh quality
      Vertices: 4   Triangles: 2   Edges: 5   Boundary edges: 4
    ...
      Longest edge            1.41421     1.07457     1.316   area
    ...
    """
    pts = as_points(points)
    tri = as_triangles(triangles, len(pts))
    if len(tri) == 0:
        raise InvalidArgumentError("triangles: the mesh has no triangles")
    bins = int(bins)
    if bins < 1:
        raise InvalidArgumentError(f"bins must be a positive integer, got {bins}")

    fields = mesh_measures(pts, tri, bins)
    if size is not None:
        fields["relative"] = relative_measures(pts, tri, size)
    if polygon is None:
        return Quality(**fields)

    # Lower bounds on the optimum.
    poly = as_polygon(polygon)
    n = _steiner_count(n_steiner, len(pts), len(poly.vertices))
    area = fields["area"]
    if abs(area - poly.area) > 1e-6 * poly.area:
        log.warning(
            "the triangles cover area %.17g but the polygon has area %.17g: "
            "the bounds assume the mesh triangulates the polygon",
            area,
            poly.area,
        )
    t_max = 2 * n + len(poly.vertices) + 2 * poly.n_holes - 2
    convex = is_convex(poly)
    dn = _checked_d_n(d_n, poly, n, convex)
    terms = lower_bound_terms(poly, n, dn)
    if len(pts) == len(poly.vertices) + n:  # the lattice term: exactly n Steiner points
        lattice = lattice_ratio_floor(poly, n)
        if lattice is not None and len(np.unique(tri)) == len(pts):  # all in the triangles
            terms["edge_ratio"].append(lattice)
    return Quality(
        **fields,
        n_steiner=n,
        t_max=t_max,
        convex=convex,
        d_n=dn,
        longest_edge_bound=_make_bound(terms["longest_edge"], fields["longest_edge"]),
        max_perimeter_bound=_make_bound(terms["max_perimeter"], fields["max_perimeter"]),
        edge_ratio_bound=_make_bound(terms["edge_ratio"], fields["edge_ratio"]),
    )
