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

import dataclasses
import logging
import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from .geometry import unique_edges
from .polygon import Polygon

__all__ = ["quality", "Quality", "Bound", "edge_lengths"]

log = logging.getLogger(__name__)

#: Every lower bound is lowered by this relative amount, far more than the
#: floating-point rounding in its evaluation, so rounding cannot lift a bound
#: above the true value it stands for.
BOUND_SLACK = 1e-9

_SQRT3 = math.sqrt(3.0)


# -- input checks --------------------------------------------------------------
def _as_points(points) -> np.ndarray:
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ValueError(f"points: expected a (N, 2) array, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        i = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise ValueError(f"points: point {i} has a non-finite coordinate {pts[i].tolist()}")
    return pts


def _as_triangles(triangles, n_points: int) -> np.ndarray:
    tri = np.asarray(triangles)
    if tri.ndim != 2 or tri.shape[1] != 3:
        raise ValueError(f"triangles: expected a (M, 3) array, got shape {tri.shape}")
    if tri.size and not np.issubdtype(tri.dtype, np.integer):
        raise ValueError(f"triangles: expected integer vertex indices, got dtype {tri.dtype}")
    tri = tri.astype(np.int64, copy=False)
    if tri.size and (tri.min() < 0 or tri.max() >= n_points):
        bad = int(np.flatnonzero(((tri < 0) | (tri >= n_points)).any(axis=1))[0])
        raise ValueError(
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
    """Unique undirected edges (E, 2) int64 with i < j, sorted, and how many triangles use each."""
    return unique_edges(tri, n_points, return_counts=True)


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
def _json_float(x):
    return float(x) if x is not None and math.isfinite(x) else None


@dataclass(frozen=True)
class Bound:
    """A lower bound on the optimum of one measure, and how this mesh compares.

    Attributes
    ----------
    value : float
        The lower bound: no triangulation of the polygon with at most
        ``n_steiner`` Steiner points does better than this.
    term : str
        Name of the term that gives ``value`` (the largest of ``terms``).
    terms : tuple of (str, float)
        Every term that applies, in a fixed order; ``value`` is their maximum.
    achieved : float
        The value this mesh achieves.
    factor : float
        ``achieved / value`` (at least 1): the mesh is provably within this
        factor of the optimum.
    """

    value: float
    term: str
    terms: tuple[tuple[str, float], ...]
    achieved: float
    factor: float

    def to_dict(self) -> dict:
        """Plain JSON-serialisable dict (non-finite numbers become ``None``)."""
        return {
            "value": _json_float(self.value),
            "term": self.term,
            "terms": {k: _json_float(v) for k, v in self.terms},
            "achieved": _json_float(self.achieved),
            "factor": _json_float(self.factor),
        }


def _histogram(values: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray]:
    """np.histogram over [min, max], widened to +-0.5 when the values (nearly) coincide."""
    lo, hi = float(values.min()), float(values.max())
    if hi - lo <= 1e-9 * max(1.0, abs(hi)):
        lo, hi = lo - 0.5, hi + 0.5
    return np.histogram(values, bins=bins, range=(lo, hi))


def _split_term(edges, n: int, t_max: int, K: float, c: float) -> float:
    """The ``split`` term: min over l of max(c l, sqrt(K / (T_max - k(l)))).

    ``k(l) = sum(ceil(L_e / l) - 1)`` is the least number of boundary Steiner
    points that cut every polygon edge (lengths ``edges``) into pieces of at most
    ``l`` (infinite if it exceeds n).  Both parts are monotone in l, so the
    minimum is at the smallest l where ``c l`` reaches the other part; it is
    found by bisection, and the lower end of the final bracket is returned (a
    value at or below the minimum).
    """
    edges = np.asarray(edges, dtype=np.float64)

    def area_part(ell):
        k = int(np.maximum(np.ceil(edges / ell) - 1.0, 0.0).sum())
        return math.inf if k > n else math.sqrt(K / (t_max - k))

    hi = float(edges.max())
    if c * hi < area_part(hi):  # no boundary point helps: the area term itself
        return math.sqrt(K / t_max)
    lo = 0.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if c * mid >= area_part(mid):
            hi = mid
        else:
            lo = mid
    return c * lo


def _make_bound(terms: list[tuple[str, float]], achieved: float) -> Bound:
    terms = [(k, float(v) * (1.0 - BOUND_SLACK)) for k, v in terms]
    best = max(range(len(terms)), key=lambda i: (terms[i][1], -i))  # ties: first listed
    name, value = terms[best]
    factor = achieved / value if value > 0 else math.inf
    return Bound(value, name, tuple(terms), float(achieved), float(factor))


@dataclass(frozen=True)
class Quality:
    """Quality measures of a triangle mesh (see :func:`quality`).

    Lengths are in the units of the points, angles in degrees.  The last seven
    fields are ``None`` when no polygon was given.

    Attributes
    ----------
    n_vertices, n_triangles, n_edges, n_boundary_edges : int
        Counts; an edge is a boundary edge when one triangle uses it.
    area : float
        Total area of the triangles.
    shortest_edge, longest_edge : float
        Shortest and longest edge (Problem 2 minimises the longest).
    edge_ratio : float
        ``longest_edge / shortest_edge`` (Problem 1); ``inf`` for a zero-length edge.
    mean_edge, std_edge, cv_edge : float
        Mean, population standard deviation and coefficient of variation
        (std / mean) of the edge lengths.
    min_angle, max_angle : float
        Smallest and largest angle of any triangle, degrees.
    max_perimeter : float
        Largest triangle perimeter (Problem 3).
    histogram_counts : tuple of int
        Number of edges in each bin of ``length / mean_edge``; sums to ``n_edges``.
    histogram_edges : tuple of float
        The ``len(histogram_counts) + 1`` bin edges, in units of ``mean_edge``.
    n_steiner : int or None
        Number n of Steiner points the bounds assume.
    t_max : int or None
        Most triangles a triangulation of the polygon with n Steiner points can have.
    convex : bool or None
        Whether the polygon is convex without holes (the packing terms apply).
    d_n : float or None
        The packing distance used by the packing terms, ``None`` if they were not used.
    longest_edge_bound, max_perimeter_bound, edge_ratio_bound : Bound or None
        Lower bounds on the optimum and the certified factors.
    """

    n_vertices: int
    n_triangles: int
    n_edges: int
    n_boundary_edges: int
    area: float
    shortest_edge: float
    longest_edge: float
    edge_ratio: float
    mean_edge: float
    std_edge: float
    cv_edge: float
    min_angle: float
    max_angle: float
    max_perimeter: float
    histogram_counts: tuple[int, ...]
    histogram_edges: tuple[float, ...]
    n_steiner: int | None = None
    t_max: int | None = None
    convex: bool | None = None
    d_n: float | None = None
    longest_edge_bound: Bound | None = None
    max_perimeter_bound: Bound | None = None
    edge_ratio_bound: Bound | None = None

    def to_dict(self) -> dict:
        """All fields as plain JSON-serialisable types.

        Bounds become nested dicts, tuples become lists, and non-finite numbers
        (an infinite edge ratio) become ``None``.
        """
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if isinstance(v, Bound):
                v = v.to_dict()
            elif isinstance(v, tuple):
                v = [_json_float(x) if isinstance(x, float) else x for x in v]
            elif isinstance(v, float):
                v = _json_float(v)
            out[f.name] = v
        return out

    def summary(self) -> str:
        """A text report in the spirit of Triangle's ``-V`` statistics."""
        g = "{:.6g}".format
        lines = [
            "Mesh quality",
            f"  Vertices: {self.n_vertices}   Triangles: {self.n_triangles}   "
            f"Edges: {self.n_edges}   Boundary edges: {self.n_boundary_edges}",
            f"  Area: {g(self.area)}",
            f"  Shortest edge: {g(self.shortest_edge)}   Longest edge: {g(self.longest_edge)}"
            f"   Ratio: {g(self.edge_ratio)}",
            f"  Mean edge: {g(self.mean_edge)}   Std: {g(self.std_edge)}   CV: {g(self.cv_edge)}",
            f"  Smallest angle: {self.min_angle:.4g} deg   Largest angle: {self.max_angle:.4g} deg",
            f"  Largest triangle perimeter: {g(self.max_perimeter)}",
            "  Edge length / mean histogram:",
        ]
        c, e = self.histogram_counts, self.histogram_edges
        for i in range(0, len(c), 4):
            cells = [f"{e[k]:5.3f} - {e[k + 1]:5.3f}: {c[k]:7d}" for k in range(i, min(i + 4, len(c)))]
            lines.append("    " + "   ".join(cells))
        if self.longest_edge_bound is not None:
            lines += [
                "",
                f"Lower bounds over all triangulations with n = {self.n_steiner} Steiner points "
                f"(at most {self.t_max} triangles"
                + (f", packing d_n = {g(self.d_n)}" if self.d_n is not None else "")
                + ")",
                f"  {'':20s}{'achieved':>12s}{'bound':>12s}{'factor':>10s}   active term",
            ]
            for label, b in (
                ("Longest edge", self.longest_edge_bound),
                ("Largest perimeter", self.max_perimeter_bound),
                ("Edge ratio", self.edge_ratio_bound),
            ):
                lines.append(
                    f"  {label:20s}{g(b.achieved):>12s}{g(b.value):>12s}"
                    f"{b.factor:>10.4g}   {b.term}"
                )
            if not self.convex:
                lines.append("  (packing terms not used: Lemma 9 needs a convex polygon without holes)")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


# -- the measures --------------------------------------------------------------
def _is_convex(polygon: Polygon) -> bool:
    if polygon.n_holes:
        return False
    r = polygon.outer  # counter-clockwise
    a = r - np.roll(r, 1, axis=0)
    b = np.roll(r, -1, axis=0) - r
    return bool((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] >= 0).all())


def _corner_ratio(theta: float) -> float:
    """Least longest/shortest side ratio of a triangle with an angle <= theta < 60 deg."""
    return min(2.0 * math.cos(theta), 1.0 / (2.0 * math.sin(theta / 2.0)))


def _packing_distance(polygon: Polygon, n: int) -> float:
    """d_n of Algorithm INSERT: the least distance among V and the n inserted points."""
    if n == 0:
        return polygon.min_vertex_distance()
    from .insert import insert

    sites = np.asarray(insert(polygon, n).mesh_points, dtype=np.float64)
    d, _ = cKDTree(sites).query(sites, k=2)
    return float(d[:, 1].min())


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
    ValueError
        If an array has the wrong shape, a non-finite coordinate or an index
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
    - ``corner``: g(theta) for the sharpest corner of P, if its angle theta is
      below 60 degrees, with g(a) = min(2 cos a, 1 / (2 sin(a/2))).  The
      triangles at that corner split theta, so one has an angle a <= theta there.
      Let its sides at that angle be 1 >= c and the third side x < 1; min(c, x)
      is largest at c = x = 1/(2 cos a) or at c = 1, x = 2 sin(a/2), so the
      triangle's ratio is >= g(a) >= g(theta) (g decreases).  Both shapes reach
      it: the isosceles triangle with angles a, a, 180 - 2a (a <= 36 deg) and
      the one with apex a (a >= 36 deg).
    - ``boundary``: (longest edge bound) / (shortest edge of P).  Every edge of
      P is cut into mesh edges no longer than itself.

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
    ('boundary', 1.0746)
    >>> print(q.summary())                          # doctest: +ELLIPSIS
    Mesh quality
      Vertices: 4   Triangles: 2   Edges: 5   Boundary edges: 4
    ...
      Longest edge            1.41421     1.07457     1.316   area
    ...
    """
    pts = _as_points(points)
    tri = _as_triangles(triangles, len(pts))
    if len(tri) == 0:
        raise ValueError("triangles: the mesh has no triangles")
    bins = int(bins)
    if bins < 1:
        raise ValueError(f"bins must be a positive integer, got {bins}")

    # Edges.
    edges, counts = _unique_edges(tri, len(pts))
    d = pts[edges[:, 1]] - pts[edges[:, 0]]
    lengths = np.hypot(d[:, 0], d[:, 1])
    shortest = float(lengths.min())
    longest = float(lengths.max())
    ratio = longest / shortest if shortest > 0 else math.inf
    mean = float(lengths.mean())
    std = float(lengths.std())
    cv = std / mean if mean > 0 else math.inf
    rel = lengths / mean if mean > 0 else np.zeros_like(lengths)
    hist_counts, hist_edges = _histogram(rel, bins)

    # Triangles: sides, angles, perimeters, areas.
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    sides = np.stack(
        [np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1)],
        axis=1,
    )
    max_perimeter = float(sides.sum(axis=1).max())

    def _angle(p, q, r):  # angle at p of triangle p, q, r
        u, v = q - p, r - p
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        return np.arctan2(np.abs(cross), (u * v).sum(axis=1))

    angles = np.degrees(np.stack([_angle(a, b, c), _angle(b, c, a), _angle(c, a, b)], axis=1))
    ab, ac = b - a, c - a
    area = float(0.5 * np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]).sum())

    fields = dict(
        n_vertices=len(pts),
        n_triangles=len(tri),
        n_edges=len(edges),
        n_boundary_edges=int((counts == 1).sum()),
        area=area,
        shortest_edge=shortest,
        longest_edge=longest,
        edge_ratio=ratio,
        mean_edge=mean,
        std_edge=std,
        cv_edge=cv,
        min_angle=float(angles.min()),
        max_angle=float(angles.max()),
        max_perimeter=max_perimeter,
        histogram_counts=tuple(int(x) for x in hist_counts),
        histogram_edges=tuple(float(x) for x in hist_edges),
    )
    if polygon is None:
        return Quality(**fields)

    # Lower bounds on the optimum.
    poly = _as_polygon(polygon)
    n_v = len(poly.vertices)
    if n_steiner is None:
        n = len(pts) - n_v
        if n < 0:
            raise ValueError(
                f"the mesh has {len(pts)} points but the polygon has {n_v} vertices; "
                "pass n_steiner explicitly"
            )
    else:
        n = int(n_steiner)
        if n < 0:
            raise ValueError(f"n_steiner must be >= 0, got {n_steiner}")
    if abs(area - poly.area) > 1e-6 * poly.area:
        log.warning(
            "the triangles cover area %.17g but the polygon has area %.17g: "
            "the bounds assume the mesh triangulates the polygon",
            area,
            poly.area,
        )
    A, B = poly.area, poly.perimeter
    t_max = 2 * n + n_v + 2 * poly.n_holes - 2
    convex = _is_convex(poly)

    dn = None
    if d_n is not False and d_n is not None:
        dn = float(d_n)
        if not (math.isfinite(dn) and dn > 0):
            raise ValueError(f"d_n must be a positive finite distance, got {d_n!r}")
        lvv = poly.min_vertex_distance()
        if dn > lvv * (1 + 1e-12):
            raise ValueError(
                f"d_n = {dn!r} exceeds l(V, V) = {lvv!r}, the least distance between polygon "
                "vertices; no packing reaches that, so it cannot be a valid d_n"
            )
        if not convex:
            log.info("d_n ignored: the packing bound (Lemma 9) needs a convex polygon without holes")
            dn = None
    elif d_n is None and convex:
        dn = _packing_distance(poly, n)

    per_edge = B / (n_v + n)
    pe = poly.edges
    dv = poly.vertices[pe[:, 1]] - poly.vertices[pe[:, 0]]
    polygon_edges = np.hypot(dv[:, 0], dv[:, 1])
    min_polygon_edge = float(polygon_edges.min())
    longest_terms = [("area", math.sqrt(4.0 * A / (_SQRT3 * t_max)))]
    perimeter_terms = [("area", math.sqrt(12.0 * _SQRT3 * A / t_max))]
    if dn is not None:
        longest_terms.append(("packing", _SQRT3 / 2.0 * dn))
        perimeter_terms.append(("packing", _SQRT3 * dn))
    longest_terms.append(("boundary", per_edge))
    perimeter_terms.append(("boundary", 2.0 * per_edge))
    longest_terms.append(("split", _split_term(polygon_edges, n, t_max, 4.0 * A / _SQRT3, 1.0)))
    perimeter_terms.append(
        ("split", _split_term(polygon_edges, n, t_max, 12.0 * _SQRT3 * A, 2.0))
    )
    longest_bound = _make_bound(longest_terms, longest)

    ratio_terms = [("trivial", 1.0)]
    theta = float(poly.interior_angles().min())
    if theta < math.pi / 3:
        ratio_terms.append(("corner", _corner_ratio(theta)))
    # longest_bound.value is already lowered by the slack; undo it to avoid applying it twice.
    ratio_terms.append(("boundary", longest_bound.value / (1.0 - BOUND_SLACK) / min_polygon_edge))

    return Quality(
        **fields,
        n_steiner=n,
        t_max=t_max,
        convex=convex,
        d_n=dn,
        longest_edge_bound=longest_bound,
        max_perimeter_bound=_make_bound(perimeter_terms, max_perimeter),
        edge_ratio_bound=_make_bound(ratio_terms, ratio),
    )
