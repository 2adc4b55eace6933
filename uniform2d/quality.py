"""Mesh quality measures and optimality certificates.

:func:`quality` measures a triangle mesh the way the paper's three problems do
(edge-length ratio, longest edge, largest triangle perimeter), adds the usual
angle and spread statistics, and, given the polygon, computes *lower bounds on
the optimum over every triangulation of the polygon with the same number of
Steiner points*.  Dividing what the mesh achieves by such a bound gives a
certified approximation factor for this instance: the mesh is provably within
that factor of the best possible one.

:func:`edge_lengths` returns the unique undirected edges of a mesh and their
lengths.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from ._kernel.edges import edges_by_vertex
from .bounds import BOUND_SLACK, Term, _is_convex, _packing_distance, lower_bound_terms
from .errors import InvalidArgumentError
from .polygon import Polygon
from .quality_result import Bound, Quality

__all__ = ["quality", "Quality", "Bound", "edge_lengths", "BOUND_SLACK"]

log = logging.getLogger(__name__)


# -- input checks --------------------------------------------------------------
def _as_points(points) -> np.ndarray:
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InvalidArgumentError(f"points: expected a (N, 2) array, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        i = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise InvalidArgumentError(f"points: point {i} has a non-finite coordinate {pts[i].tolist()}")
    return pts


def _as_triangles(triangles, n_points: int) -> np.ndarray:
    tri = np.asarray(triangles)
    if tri.ndim != 2 or tri.shape[1] != 3:
        raise InvalidArgumentError(f"triangles: expected a (M, 3) array, got shape {tri.shape}")
    if tri.size and not np.issubdtype(tri.dtype, np.integer):
        raise InvalidArgumentError(f"triangles: expected integer vertex indices, got dtype {tri.dtype}")
    tri = tri.astype(np.int64, copy=False)
    if tri.size and (tri.min() < 0 or tri.max() >= n_points):
        bad = int(np.flatnonzero(((tri < 0) | (tri >= n_points)).any(axis=1))[0])
        raise InvalidArgumentError(
            f"triangles: triangle {bad} {tri[bad].tolist()} refers to a point outside "
            f"0..{n_points - 1}"
        )
    return tri


def _as_polygon(polygon) -> Polygon:
    if isinstance(polygon, Polygon):
        return polygon
    if hasattr(polygon, "geom_type"):
        return Polygon.from_shapely(polygon)
    return Polygon(polygon)


# -- edges ---------------------------------------------------------------------
def _unique_edges(tri: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """Unique undirected edges (E, 2) int64 with i < j, sorted, and how many triangles use each.

    The same as :func:`uniform2d.geometry.unique_edges` with counts, bucketed by
    the smaller vertex instead of sorted as a whole (each bucket holds a vertex's
    few larger neighbours): at 1e6 points a tenth of the sort's time.  The
    kernel always gets a read-only view, so it is compiled once, not once for
    read-only triangles (a Mesh's) and once for writable ones."""
    view = np.ascontiguousarray(tri, dtype=np.int64).view()
    view.flags.writeable = False
    return edges_by_vertex(view, np.int64(n_points))


def edge_lengths(points, triangles) -> tuple[np.ndarray, np.ndarray]:
    """The unique undirected edges of a triangle mesh and their lengths.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Vertex coordinates, float64.
    triangles : array_like, shape (M, 3)
        Vertex indices of each triangle, integers in ``0..N-1``.

    Returns
    -------
    edges : ndarray, shape (E, 2), int64
        Each edge once, as ``(i, j)`` with ``i < j``, sorted lexicographically.
    lengths : ndarray, shape (E,), float64
        Euclidean length of each edge.

    Examples
    --------
    >>> from uniform2d.quality import edge_lengths
    >>> pts = [(0, 0), (1, 0), (1, 1), (0, 1)]
    >>> edges, lengths = edge_lengths(pts, [(0, 1, 2), (0, 2, 3)])
    >>> edges.tolist()
    [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
    >>> lengths.round(4).tolist()
    [1.0, 1.4142, 1.0, 1.0, 1.0]
    """
    pts = _as_points(points)
    tri = _as_triangles(triangles, len(pts))
    edges, _ = _unique_edges(tri, len(pts))
    d = pts[edges[:, 1]] - pts[edges[:, 0]]
    return edges, np.hypot(d[:, 0], d[:, 1])


# -- results -------------------------------------------------------------------
def _histogram(values: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray]:
    """np.histogram over [min, max], widened to +-0.5 when the values (nearly) coincide."""
    lo, hi = float(values.min()), float(values.max())
    if hi - lo <= 1e-9 * max(1.0, abs(hi)):
        lo, hi = lo - 0.5, hi + 0.5
    return np.histogram(values, bins=bins, range=(lo, hi))


def _make_bound(terms: list[Term], achieved: float) -> Bound:
    lowered = [(t.name, float(t.value) * (1.0 - BOUND_SLACK)) for t in terms]
    best = max(range(len(terms)), key=lambda i: (lowered[i][1], -i))  # ties: first listed
    name, value = lowered[best]
    factor = achieved / value if value > 0 else math.inf
    return Bound(value, name, tuple(lowered), float(achieved), float(factor), terms[best].detail)


# -- the measures --------------------------------------------------------------
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


#: Triangles measured at a time by :func:`_measures`.
TRIANGLE_BLOCK = 1 << 16


def _triangle_measures(pts: np.ndarray, tri: np.ndarray):
    """(largest perimeter, smallest and largest angle in degrees, |twice the area|
    of each triangle) of the triangles ``tri`` (K, 3)."""
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    sides = np.stack(
        [np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1)],
        axis=1,
    )

    def _angle(p, q, r):  # angle at p of triangle p, q, r
        u, v = q - p, r - p
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        return np.arctan2(np.abs(cross), (u * v).sum(axis=1))

    angles = np.degrees(np.stack([_angle(a, b, c), _angle(b, c, a), _angle(c, a, b)], axis=1))
    ab, ac = b - a, c - a
    cross = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    return float(sides.sum(axis=1).max()), float(angles.min()), float(angles.max()), cross


def _measures(pts: np.ndarray, tri: np.ndarray, bins: int) -> dict:
    """Every field of :class:`Quality` that does not need the polygon."""
    # Edges.
    edges, counts = _unique_edges(tri, len(pts))
    n_edges, n_boundary = len(edges), int((counts == 1).sum())
    # a coordinate at a time: no (E, 2) gathers
    i, j = edges[:, 0], edges[:, 1]
    dx, dy = pts[j, 0], pts[j, 1]
    dx -= pts[i, 0]
    dy -= pts[i, 1]
    del edges, counts, i, j  # only the lengths are used from here on
    lengths = np.hypot(dx, dy)
    del dx, dy
    shortest = float(lengths.min())
    longest = float(lengths.max())
    ratio = longest / shortest if shortest > 0 else math.inf
    mean = float(lengths.mean())
    std = float(lengths.std())
    cv = std / mean if mean > 0 else math.inf
    rel = lengths / mean if mean > 0 else np.zeros_like(lengths)
    hist_counts, hist_edges = _histogram(rel, bins)

    # Triangles: perimeters, angles, areas, in blocks (each needs a dozen (M, 2)
    # temporaries, hundreds of MB at 1e6 points at once); the areas are summed in
    # one go, so the total is the same to the bit
    max_perimeter, min_angle, max_angle = -math.inf, math.inf, -math.inf
    cross = np.empty(len(tri))
    for lo in range(0, len(tri), TRIANGLE_BLOCK):
        t = tri[lo:lo + TRIANGLE_BLOCK]
        p, a_min, a_max, cross[lo:lo + len(t)] = _triangle_measures(pts, t)
        max_perimeter = max(max_perimeter, p)
        min_angle, max_angle = min(min_angle, a_min), max(max_angle, a_max)
    area = float(0.5 * cross.sum())

    return dict(
        n_vertices=len(pts),
        n_triangles=len(tri),
        n_edges=n_edges,
        n_boundary_edges=n_boundary,
        area=area,
        shortest_edge=shortest,
        longest_edge=longest,
        edge_ratio=ratio,
        mean_edge=mean,
        std_edge=std,
        cv_edge=cv,
        min_angle=min_angle,
        max_angle=max_angle,
        max_perimeter=max_perimeter,
        histogram_counts=tuple(int(x) for x in hist_counts),
        histogram_edges=tuple(float(x) for x in hist_edges),
    )


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


def quality(points, triangles, polygon=None, *, n_steiner=None, d_n=None, bins=20) -> Quality:
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
    most n further points (h holes, area A, boundary length B).  Each is the
    largest of its terms; ``Bound.term`` names the one that is active.

    *Count.* Euler's formula gives |V| + 2 n_i + n_b + 2h - 2 triangles for
    n_i interior and n_b boundary Steiner points, at most
    T_max = 2n + |V| + 2h - 2.

    *Longest edge.*

    - ``area``: sqrt(4A / (sqrt(3) T_max)).  The largest triangle has area
      >= A / T_max, and a triangle with longest edge L has area <= sqrt(3)/4 L^2
      (its apex is within L of both ends of that edge).
    - ``boundary``: B / (|V| + n).  The boundary is made of |V| + n_b <= |V| + n
      mesh edges of total length B, so one of them is at least that long.
    - ``split``: the two above, combined over the number k of boundary Steiner
      points.  A mesh whose longest boundary edge is l has at least
      k(l) = sum over polygon edges e of (ceil(L_e / l) - 1) of them, so at most
      T_max - k(l) triangles, and its longest edge is at least
      max(l, sqrt(4A / (sqrt(3) (T_max - k(l))))).  The term is the least such
      value over l (bisection; at least ``area`` and ``boundary``).  Points on
      the boundary leave fewer, larger triangles; fewer of them leave longer
      boundary edges: no mesh escapes both.
    - ``packing`` (convex P without holes only): sqrt(3)/2 d_n.  Lemma 9 of the
      paper gives sqrt(3)/2 d_n* for the optimum, and d_n <= d_n*.  The lemma is
      proven for convex polygons only, so the term is not used otherwise.

    *Largest perimeter.*

    - ``area``: sqrt(12 sqrt(3) A / T_max).  The largest triangle has area
      >= A / T_max, and a triangle of perimeter p has area <= p^2 / (12 sqrt(3))
      (the equilateral one is largest).
    - ``boundary``: 2 B / (|V| + n).  The triangle holding the longest boundary
      edge has perimeter at least twice that edge (triangle inequality).
    - ``split``: as for the longest edge, with the perimeter parts
      max(2 l, sqrt(12 sqrt(3) A / (T_max - k(l)))).
    - ``packing`` (convex P without holes only): sqrt(3) d_n, twice the longest
      edge bound (Theorem 5 of the paper).

    *Edge ratio.*

    - ``trivial``: 1.
    - ``corner``: the largest, over every corner of every ring, of the least
      edge ratio the triangles at that corner can have
      (:func:`uniform2d.bounds.corner_ratio_floor`).  A corner of interior
      angle alpha (convex or reflex) is a vertex of every triangulation of P;
      the k triangles there split alpha (k >= floor(alpha / 180) + 1), so one
      has an angle <= alpha / k and one >= alpha / k, and a triangle with an
      angle b has ratio >= g(b) = min(2 cos b, 1 / (2 sin(b/2))) for
      b <= 60 degrees, 2 sin(b/2) above.  g falls to 1 at 60 degrees and rises
      after, so the corner forces min over k of g(alpha / k): 1.307 for 90
      degrees, 1.101 for 270, 1 for every multiple of 60.
    - ``euler``: an inner vertex with d != 6 triangles, or a boundary point
      with other than 3, forces a ratio >= 1.1524 (d = 7), 1.1756 (d = 5) or
      more; with none, Euler's formula fixes the sum of the numbers of
      triangles at the corners, and the term is the least ratio their floors
      allow (:func:`uniform2d.bounds.euler_ratio_floor`; at most 1.1756).
    - ``boundary``: (longest edge bound) / (shortest edge of P).  Every edge of
      P is cut into mesh edges no longer than itself.
    - ``sides``: a mesh with longest edge L >= (longest edge bound) cuts each
      polygon edge e into at least ceil(L_e / L) pieces, one at most
      L_e / ceil(L_e / L) long, so its ratio is >= L ceil(L_e / L) / L_e for
      every e; the term is the least such value over L (at least ``boundary``).

    With interior segments and fixed points every term still holds (the guide says
    why, term by term); T_max then counts the constraint vertices off the rings
    twice (they are inner vertices), and the packing terms are not used.

    Each bound is lowered by a relative :data:`BOUND_SLACK` (1e-9) so that
    floating-point rounding cannot lift it above the true value.

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
    pts = _as_points(points)
    tri = _as_triangles(triangles, len(pts))
    if len(tri) == 0:
        raise InvalidArgumentError("triangles: the mesh has no triangles")
    bins = int(bins)
    if bins < 1:
        raise InvalidArgumentError(f"bins must be a positive integer, got {bins}")

    fields = _measures(pts, tri, bins)
    if polygon is None:
        return Quality(**fields)

    # Lower bounds on the optimum.
    poly = _as_polygon(polygon)
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
    convex = _is_convex(poly)
    dn = _checked_d_n(d_n, poly, n, convex)
    terms = lower_bound_terms(poly, n, dn)
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
