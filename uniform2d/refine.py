"""Built-in size fields: refinement near parts of the domain, as one call.

:func:`refine` is Gmsh's Distance + Threshold fields in one: the size is
``ratio * H`` on the chosen part of the domain and grows linearly with the
distance d from it, at slope ``rate``, up to the base size H::

    h(x) = min(H, ratio * H + rate * d(x))

``near`` names the part: ``"holes"`` (the hole boundaries), ``"corners"``
(re-entrant corners, :func:`reentrant_corners`: runs of consecutive reflex ring
vertices turning by at least ``CORNER_ANGLE - 180`` degrees in all, so that a
sharp corner is a run of one vertex and a filleted one, an arc of slightly
reflex vertices, is one corner too, while a ring all of whose vertices are
reflex, a polygonised round hole, is none), ``"points"`` (the polygon's fixed
points: supports, loads), ``"segments"`` (its interior segments: members,
interfaces) or ``"boundary"`` (the outer boundary); or it is an (k, 2) array of
points.  :func:`minimum` combines fields (the smallest size wins).  With :func:`uniform2d.uniform_mesh`
``n=`` only the field's shape matters, so H may stay at its default (the size
of a uniform mesh of 1000 points); without n it is the absolute coarse size.

Fields are :class:`~uniform2d.SizeField` grids (:func:`uniform2d.grading.as_field`).
"""

from __future__ import annotations

import math
import numbers

import numpy as np
import shapely

from ._kernel.predicates import orient2d
from .errors import InvalidArgumentError
from .geometry import size_for_count
from .grading import as_field
from .polygon import Polygon, as_polygon
from .sizefield import SizeField

__all__ = ["CORNER_ANGLE", "NEAR", "minimum", "parse_refine", "reentrant_corners", "refine"]

#: The parts of the domain :func:`refine` refines near.
NEAR = ("holes", "corners", "points", "segments", "boundary")
#: Interior angle (degrees) from which a run of reflex ring vertices (one vertex for a
#: sharp corner, a short arc for a filleted one) is a re-entrant corner: the run's total
#: turning is at least ``CORNER_ANGLE - 180``.
CORNER_ANGLE = 200.0
#: Default grading rate: the size grows by this times the distance.
RATE = 0.3
#: Points of a uniform mesh whose size is the default base size H.
BASE_POINTS = 1000


def _target(polygon: Polygon, near):
    """The shapely geometry whose distance drives the field."""
    if not isinstance(near, str):
        pts = np.asarray(near, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) == 0 or not np.isfinite(pts).all():
            raise InvalidArgumentError(
                f"refine: near must be one of {NEAR} or a (k, 2) array of points")
        return shapely.MultiPoint(pts)
    if near == "holes":
        geoms = [shapely.LinearRing(h) for h in polygon.holes]
    elif near == "boundary":
        geoms = [shapely.LinearRing(polygon.outer)]
    elif near == "corners":
        geoms = [shapely.Point(c[0]) if len(c) == 1 else shapely.LineString(c)
                 for c in reentrant_corners(polygon)]
    elif near == "points":
        geoms = [shapely.Point(p) for p in polygon.points]
    elif near == "segments":
        geoms = [shapely.LineString(s) for s in polygon.segments]
    else:
        raise InvalidArgumentError(f"refine: near must be one of {NEAR}, got {near!r}")
    if not geoms:
        why = " (a round hole has none: use \"holes\")" if near == "corners" else ""
        raise InvalidArgumentError(f"refine: the polygon has no {near} to refine near{why}; "
                                   f"name another part or pass (k, 2) points")
    return shapely.GeometryCollection(geoms)


def _runs(turn: np.ndarray) -> list[np.ndarray]:
    """Maximal cyclic runs of non-convex vertices (``turn``: -1 convex, 0 straight,
    1 reflex) that hold a reflex one, each as vertex indices from its first reflex
    vertex to its last."""
    k = len(turn)
    if (turn >= 0).all():
        return []  # every vertex reflex or straight: a polygonised round hole, no corner
    start = int(np.flatnonzero(turn < 0)[-1]) + 1  # just after a convex vertex
    out, run = [], []
    for i in range(start, start + k + 1):
        j = i % k
        if i < start + k and turn[j] >= 0:
            run.append(j)
            continue
        reflex = [m for m, v in enumerate(run) if turn[v] > 0]
        if reflex:
            out.append(np.array(run[reflex[0]: reflex[-1] + 1], dtype=np.int64))
        run = []
    return out


def reentrant_corners(polygon) -> list[np.ndarray]:
    """The polygon's re-entrant corners, each as the (k, 2) vertices of its run.

    A run is a maximal sequence of consecutive ring vertices none of which is convex
    (exact orientation of the vertex and its neighbours), from its first reflex vertex
    to its last; it is a corner when its total turning, the sum of its interior angles
    minus 180 degrees each, is at least ``CORNER_ANGLE - 180`` degrees.  A sharp corner
    is a run of one vertex, a filleted corner the arc's vertices; a ring with no convex
    vertex (a hole's ring all of whose vertices turn the same way, such as a polygonised
    circle) has no corner: holes are :func:`refine`'s ``"holes"``.

    Parameters
    ----------
    polygon : Polygon

    Returns
    -------
    list of ndarray, each (k, 2) float64
        Ring by ring, in ring order.

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> ell = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    >>> [c.tolist() for c in reentrant_corners(ell)]
    [[[1.0, 1.0]]]
    >>> t = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    >>> hole = np.column_stack([2 + np.cos(t), 2 - np.sin(t)])
    >>> reentrant_corners(Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], holes=[hole]))
    []
    """
    polygon = as_polygon(polygon)
    threshold = math.radians(CORNER_ANGLE - 180.0)
    angles = polygon.interior_angles() - math.pi
    out = []
    for r, ring in enumerate(polygon.rings):
        off = polygon.ring_offsets[r]
        nxt, prv = np.roll(ring, -1, axis=0), np.roll(ring, 1, axis=0)
        # interior on the left of every ring edge: a right turn is a reflex vertex
        turn = np.array([-np.sign(orient2d(a[0], a[1], b[0], b[1], c[0], c[1]))
                         for a, b, c in zip(prv, ring, nxt)])
        for run in _runs(turn):
            if angles[off + run].sum() >= threshold:
                out.append(ring[run].copy())
    return out


def _positive(name: str, value, upper=None) -> float:
    ok = isinstance(value, numbers.Real) and math.isfinite(value) and value > 0
    if not ok or (upper is not None and value > upper):
        rng = f"in (0, {upper:g}]" if upper is not None else "positive"
        raise InvalidArgumentError(f"refine: {name} must be a finite number {rng}, got {value!r}")
    return float(value)


def refine(polygon, near="holes", *, ratio: float = 0.25, rate: float = RATE,
           size: float | None = None) -> SizeField:
    """The size field ``min(H, ratio * H + rate * distance to near)``.

    Parameters
    ----------
    polygon : Polygon
    near : str or array_like, shape (k, 2)
        One of :data:`NEAR`, or points.
    ratio : float
        Size on ``near`` relative to the base size H, in (0, 1].
    rate : float
        Grading rate: how fast the size grows with the distance (dh / dd > 0).
    size : float, optional
        The base size H (default: that of a uniform mesh with ``BASE_POINTS`` points).

    Returns
    -------
    SizeField

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> sq = Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], holes=[[(1, 1), (1, 2), (2, 2), (2, 1)]])
    >>> f = refine(sq, "holes", ratio=0.1, rate=0.5, size=1.0)
    >>> f([(2.0, 1.5), (2.5, 1.5), (4.0, 4.0)]).round(3).tolist()
    [0.1, 0.35, 1.0]
    """
    polygon = as_polygon(polygon)
    ratio = _positive("ratio", ratio, 1.0)
    rate = _positive("rate", rate)
    if size is None:
        H = size_for_count(polygon.area, polygon.perimeter, BASE_POINTS, polygon.n_holes)
    else:
        H = _positive("size", size)
    target = _target(polygon, near)
    shapely.prepare(target)

    def h(p):
        d = shapely.distance(shapely.points(p), target)
        return np.minimum(H, ratio * H + rate * d)

    return as_field(polygon, h)


def minimum(polygon, *fields) -> SizeField:
    """The smallest of several size fields at every point, as one field.

    Examples
    --------
    >>> from uniform2d import Polygon, SizeField
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = minimum(sq, SizeField.constant(sq.bounds, 0.5), lambda p: 0.1 + p[:, 0])
    >>> f([(0.0, 0.5), (1.0, 0.5)]).round(6).tolist()
    [0.1, 0.5]
    """
    polygon = as_polygon(polygon)
    if not fields:
        raise InvalidArgumentError("minimum: give at least one size field")
    fs = [as_field(polygon, f) if not isinstance(f, numbers.Real) else
          SizeField.constant(polygon.bounds, f) for f in fields]
    if len(fs) == 1:
        return fs[0]
    return as_field(polygon, lambda p: np.min([f(p) for f in fs], axis=0))


def parse_refine(text: str) -> dict:
    """``"near:ratio[:rate]"`` (the command's ``--refine``) as :func:`refine`'s keywords.

    Examples
    --------
    >>> parse_refine("holes:0.25")
    {'near': 'holes', 'ratio': 0.25}
    >>> parse_refine("corners:0.1:0.5")
    {'near': 'corners', 'ratio': 0.1, 'rate': 0.5}
    """
    parts = text.split(":")
    if not 2 <= len(parts) <= 3 or parts[0] not in NEAR:
        raise InvalidArgumentError(
            f"--refine {text!r}: expected near:ratio[:rate] with near one of {', '.join(NEAR)} "
            "(e.g. holes:0.25 or corners:0.1:0.5)")
    try:
        nums = [float(x) for x in parts[1:]]
    except ValueError:
        raise InvalidArgumentError(
            f"--refine {text!r}: ratio and rate must be numbers (e.g. holes:0.25:0.3)") from None
    out = {"near": parts[0], "ratio": nums[0]}
    if len(nums) == 2:
        out["rate"] = nums[1]
    return out
