"""The polygon model: one outer ring, zero or more holes, and interior constraints.

A :class:`Polygon` is immutable.  Its rings are normalised on construction: the
outer ring counter-clockwise, holes clockwise, so the interior of the polygon is
always on the left of every ring edge.  Consecutive collinear vertices are legal:
they are sites of the construction like any other vertex.  Interior segments and
fixed points (:mod:`uniform2d.constraints`) add vertices after the rings' ones.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import constraints as _constraints
from . import libm
from . import regions as _regions
from .errors import InvalidConstraintError, InvalidPolygonError
from .geometry import check_finite, signed_area, xy_array

__all__ = ["Polygon", "as_polygon"]


def _fmt(p) -> str:
    return f"({p[0]:.17g}, {p[1]:.17g})"


def _collinear(ring: np.ndarray) -> bool:
    """Are all vertices on one line?  Decided exactly (rational arithmetic)."""
    p = [(Fraction(float(x)), Fraction(float(y))) for x, y in ring]
    far = max(p, key=lambda q: abs(q[0] - p[0][0]) + abs(q[1] - p[0][1]))
    ux, uy = far[0] - p[0][0], far[1] - p[0][1]
    return all((x - p[0][0]) * uy == (y - p[0][1]) * ux for x, y in p)


#: Coordinates float64 geometry can carry here: every length must square to a
#: normal float (areas, perimeters, the quality measures), so a ring may be no
#: larger than COORD_MAX in any coordinate and no smaller than COORD_MIN across.
COORD_MAX = 1e100
COORD_MIN = 1e-100


def _as_ring(coords, name: str) -> np.ndarray:
    """Convert one ring to a float64 (k, 2) array, checking everything local to it."""
    ring = xy_array(coords, name, InvalidPolygonError)
    if ring.size == 0:
        raise InvalidPolygonError(f"{name}: the ring has no vertices; give at least 3 (x, y) points")
    if ring.ndim != 2 or ring.shape[1] != 2:
        raise InvalidPolygonError(
            f"{name}: expected a (k, 2) array of (x, y) coordinates, got shape {ring.shape}"
        )
    check_finite(ring, name, InvalidPolygonError, "; remove NaN/inf values")
    big = float(np.abs(ring).max())
    if big > COORD_MAX:
        raise InvalidPolygonError(
            f"{name}: a coordinate is {big:.3g}, beyond the {COORD_MAX:g} that float64 "
            "geometry can square; rescale the polygon (other units)"
        )
    across = float(np.ptp(ring, axis=0).max())
    if 0.0 < across < COORD_MIN:
        raise InvalidPolygonError(
            f"{name}: the ring is {across:.3g} across, below the {COORD_MIN:g} whose square "
            "float64 can hold; rescale the polygon (other units)"
        )
    # An explicitly closed ring (first vertex repeated at the end) is accepted.
    if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    if len(np.unique(ring, axis=0)) < 3:
        raise InvalidPolygonError(
            f"{name}: needs at least 3 distinct vertices, got {len(np.unique(ring, axis=0))}"
        )
    same = np.all(ring == np.roll(ring, -1, axis=0), axis=1)
    if same.any():
        i = int(np.flatnonzero(same)[0])
        j = (i + 1) % len(ring)
        raise InvalidPolygonError(
            f"{name}: vertices {i} and {j} are the same point {_fmt(ring[i])}; "
            "remove the repeated vertex"
        )
    if signed_area(ring) == 0.0 and _collinear(ring):
        raise InvalidPolygonError(f"{name}: the ring has zero area (all vertices are collinear)")
    lr = shapely.LinearRing(ring)
    if not lr.is_simple:
        reason = shapely.is_valid_reason(shapely.Polygon(ring))
        where = reason[reason.find("[") :] if "[" in reason else ""
        # A vertex repeated non-consecutively (a "pinch") is also non-simple.
        _, first, counts = np.unique(ring, axis=0, return_index=True, return_counts=True)
        if (counts > 1).any():
            k = int(first[np.flatnonzero(counts > 1)[0]])
            raise InvalidPolygonError(
                f"{name}: vertex {k} {_fmt(ring[k])} appears more than once; "
                "a ring must not touch itself"
            )
        raise InvalidPolygonError(
            f"{name}: the ring intersects itself {where.strip()}; "
            "reorder the vertices so edges only meet at their shared endpoints"
        )
    return ring


class Polygon:
    """A validated polygon with holes, interior segments and fixed points.

    Parameters
    ----------
    outer : array_like, shape (k, 2)
        Vertices of the outer ring, in either orientation.  A closing vertex equal
        to the first one is dropped.
    holes : sequence of array_like, each shape (k_i, 2)
        Vertices of each hole ring, in either orientation.
    segments : sequence of array_like, each shape (k_i, 2), keyword-only
        Interior polylines that the mesh must contain as chains of edges (members,
        stiffeners, ridges, joints, region borders).  Open or closed (last vertex
        equal to the first).  One may end on a ring (that point becomes a vertex
        of the ring), inside P, or on another segment (which is split there).
    points : array_like, shape (K, 2), keyword-only
        Fixed points that must be mesh vertices (supports, load points).  One on
        a segment splits it; one on a ring becomes a vertex of the ring.
    regions : sequence of (x, y, label), keyword-only
        Region labels (like Triangle's regional attributes): each seed point
        labels the region (:mod:`uniform2d.regions`) strictly containing it with
        ``label``, a string or a number.

    Raises
    ------
    InvalidPolygonError
        If a ring has fewer than 3 distinct vertices, a non-finite coordinate, a
        repeated consecutive vertex, zero area or a self-intersection; if a hole is
        not strictly inside the outer ring; or if two holes overlap or touch.
    InvalidConstraintError
        If a segment or point is malformed, outside P or in a hole, or if a
        segment crosses or overlaps a ring or another segment (an
        :class:`InvalidPolygonError`); if a region seed is malformed, not strictly
        inside a region, or shares its region with another seed.

    Notes
    -----
    :attr:`vertices` are the ring vertices (``ring_offsets`` delimits the rings)
    followed by the constraint vertices not on a ring; :attr:`edges` are the ring
    edges only and :attr:`segment_edges` the segments' pieces, split at every
    vertex on them.  Junctions are decided exactly on the coordinates as given,
    "on" a piece including within 2 units in the last place of it (a junction
    computed onto a rotated edge rounds off its line; :mod:`uniform2d.constraints`).
    :attr:`area` and :attr:`perimeter` are those of the rings with the junctions.

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> sq = Polygon([(0, 0), (0, 1), (1, 1), (1, 0)])      # clockwise on input
    >>> sq.area, sq.perimeter, sq.n_holes
    (1.0, 4.0, 0)
    >>> sq.outer[:2].tolist()                                 # stored counter-clockwise
    [[0.0, 0.0], [1.0, 0.0]]
    >>> slab = Polygon([(0, 0), (4, 0), (4, 3), (0, 3)], segments=[[(2, 0), (2, 2)]],
    ...                points=[(1, 1), (3, 1)])
    >>> slab.outer.tolist()                                  # the T-junction joins the ring
    [[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]]
    >>> slab.segment_edges.tolist(), slab.fixed.tolist()
    ([[1, 5]], [6, 7])
    """

    __slots__ = ("_rings", "_vertices", "_offsets", "_area", "_perimeter", "_segments",
                 "_points", "_segment_edges", "_segment_ids", "_fixed", "_seeds", "_regions",
                 "_edges", "_constraint_edges")  # fmt: skip

    def __init__(self, outer, holes=(), *, segments=(), points=(), regions=()):
        outer_ring = _as_ring(outer, "outer ring")
        if isinstance(holes, np.ndarray) and holes.ndim == 2:
            raise InvalidPolygonError(
                "holes must be a sequence of rings; wrap a single hole as [hole]"
            )
        hole_rings = [_as_ring(h, f"hole {i}") for i, h in enumerate(holes)]

        # Reverse where needed, keeping each ring's first vertex first.
        if signed_area(outer_ring) < 0:
            outer_ring = np.roll(outer_ring[::-1], 1, axis=0)
        hole_rings = [np.roll(h[::-1], 1, axis=0) if signed_area(h) > 0 else h for h in hole_rings]

        shell = shapely.Polygon(outer_ring)
        hole_polys = [shapely.Polygon(h) for h in hole_rings]
        for i, hp in enumerate(hole_polys):
            if not shapely.contains_properly(shell, hp):
                if shapely.intersects(shell, hp) and not shapely.within(hp, shell):
                    what = "crosses the outer ring or lies outside it"
                elif shapely.within(hp, shell):
                    what = "touches the outer ring"
                else:
                    what = "lies outside the outer ring"
                raise InvalidPolygonError(
                    f"hole {i} {what}; every hole must lie strictly inside the outer ring"
                )
        for i in range(len(hole_polys)):
            for j in range(i + 1, len(hole_polys)):
                if shapely.intersects(hole_polys[i], hole_polys[j]):
                    raise InvalidPolygonError(
                        f"holes {i} and {j} overlap or touch; merge them into one hole "
                        "or move them apart"
                    )

        rings = [outer_ring, *hole_rings]
        extra = self._set_constraints(rings, segments, points)
        # of the rings as spliced: a junction may lie a rounding off its edge
        self._area = signed_area(rings[0]) + sum(signed_area(h) for h in rings[1:])
        self._perimeter = float(
            sum(np.linalg.norm(np.roll(r, -1, axis=0) - r, axis=1).sum() for r in rings)
        )
        for r in rings:
            r.setflags(write=False)
        self._rings = tuple(rings)
        self._vertices = np.concatenate([*rings, extra], axis=0)
        self._vertices.setflags(write=False)
        self._offsets = np.cumsum([0] + [len(r) for r in rings])
        self._offsets.setflags(write=False)
        # made once: the optimiser asks for them a hundred times a mesh
        self._edges = self._ring_edges()
        self._constraint_edges = np.concatenate([self._edges, self._segment_edges], axis=0)
        self._seeds = _regions.region_seeds(regions)
        self._regions = _regions.build(self, self._seeds) if self._seeds else None

    def _set_constraints(self, rings: list, segments, points) -> np.ndarray:
        """Check and store the segments and points; splice T-junctions into
        ``rings`` (in place); return the constraint vertices not on a ring."""
        if isinstance(segments, np.ndarray) and segments.ndim == 2:
            raise InvalidConstraintError(
                "segments must be a sequence of polylines; wrap a single one as [segment]"
            )
        lines = [_constraints.polyline(c, f"segment {i}") for i, c in enumerate(segments)]
        pts = _constraints.fixed_points(points if points is not None else ())
        self._segments = tuple(lines)
        self._points = pts
        extra = np.empty((0, 2), np.float64)
        edges, ids, fixed = (np.empty((0, 2), np.int64), np.empty(0, np.int64),
                             np.empty(0, np.int64))  # fmt: skip
        if lines or len(pts):
            for v in [*lines, pts]:
                big = float(np.abs(v).max()) if v.size else 0.0
                if big > COORD_MAX:
                    raise InvalidConstraintError(
                        f"a segment or point coordinate is {big:.3g}, beyond {COORD_MAX:g}; "
                        "rescale the polygon (other units)"
                    )
            c = _constraints.build(rings, lines, pts)
            rings[:] = c.rings
            extra, edges, ids, fixed = c.extra, c.segment_edges, c.segment_ids, c.fixed
        for a in (pts, extra, edges, ids, fixed, *lines):
            a.setflags(write=False)
        self._segment_edges, self._segment_ids, self._fixed = edges, ids, fixed
        return extra

    # -- basic views -------------------------------------------------------------
    @property
    def outer(self) -> np.ndarray:
        """Outer ring, (k, 2) float64, counter-clockwise, not closed."""
        return self._rings[0]

    @property
    def holes(self) -> tuple[np.ndarray, ...]:
        """Hole rings, each (k_i, 2) float64, clockwise, not closed."""
        return self._rings[1:]

    @property
    def rings(self) -> tuple[np.ndarray, ...]:
        """All rings, outer first; the interior is on the left of every edge."""
        return self._rings

    @property
    def vertices(self) -> np.ndarray:
        """All ring vertices V, (N, 2) float64: the outer ring, then each hole."""
        return self._vertices

    V = vertices

    @property
    def ring_offsets(self) -> np.ndarray:
        """Ring ``r`` is ``vertices[ring_offsets[r]:ring_offsets[r + 1]]``."""
        return self._offsets

    @property
    def n_ring_vertices(self) -> int:
        """How many of :attr:`vertices` are ring vertices (they come first)."""
        return int(self._offsets[-1])

    @property
    def segments(self) -> tuple[np.ndarray, ...]:
        """The interior segments as given, each (k_i, 2) float64 (a closed one ends
        where it starts)."""
        return self._segments

    @property
    def points(self) -> np.ndarray:
        """The fixed points as given, (K, 2) float64."""
        return self._points

    @property
    def segment_edges(self) -> np.ndarray:
        """The segments' pieces as (S, 2) int64 indices into :attr:`vertices`,
        in the direction given; no vertex lies inside a piece."""
        return self._segment_edges

    @property
    def segment_ids(self) -> np.ndarray:
        """(S,) int64: the segment (index into :attr:`segments`) of each piece."""
        return self._segment_ids

    @property
    def fixed(self) -> np.ndarray:
        """(K,) int64: the index into :attr:`vertices` of each fixed point."""
        return self._fixed

    @property
    def constraint_edges(self) -> np.ndarray:
        """Ring edges then segment pieces, (E + S, 2) int64: every edge the mesh
        must contain."""
        return self._constraint_edges.copy()

    @property
    def region_seeds(self) -> tuple:
        """The region labels as given: a tuple of ``(x, y, label)``."""
        return self._seeds

    @property
    def regions(self) -> "_regions.Regions":
        """The regions the rings and segments split P into, numbered as
        :mod:`uniform2d.regions` says, with their areas and labels."""
        if self._regions is None:
            self._regions = _regions.build(self, self._seeds)
        return self._regions

    @property
    def has_constraints(self) -> bool:
        """Whether there are interior segments or fixed points."""
        return bool(len(self._segments) or len(self._points))

    @property
    def n_holes(self) -> int:
        return len(self._rings) - 1

    @property
    def area(self) -> float:
        """Area A(P): outer area minus hole areas."""
        return self._area

    @property
    def perimeter(self) -> float:
        """Total boundary length B(P), holes included."""
        return self._perimeter

    @property
    def edges(self) -> np.ndarray:
        """Boundary edges as (E, 2) int64 indices into :attr:`vertices`, interior on the left."""
        return self._edges.copy()

    def _ring_edges(self) -> np.ndarray:
        out = []
        for r in range(len(self._rings)):
            a, b = self._offsets[r], self._offsets[r + 1]
            idx = np.arange(a, b)
            out.append(np.stack([idx, np.roll(idx, -1)], axis=1))
        return np.concatenate(out, axis=0)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax)."""
        lo = self._vertices.min(axis=0)
        hi = self._vertices.max(axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    def interior_angles(self) -> np.ndarray:
        """Interior angle at every ring vertex, (:attr:`n_ring_vertices`,) radians in
        (0, 2*pi), ordered like :attr:`vertices`."""
        out = []
        for r in self._rings:
            prev = np.roll(r, 1, axis=0) - r
            nxt = np.roll(r, -1, axis=0) - r
            cross = nxt[:, 0] * prev[:, 1] - nxt[:, 1] * prev[:, 0]
            dot = (nxt * prev).sum(axis=1)
            ang = libm.arctan2(cross, dot)
            out.append(np.where(ang <= 0, ang + 2 * np.pi, ang))
        return np.concatenate(out)

    def min_vertex_distance(self) -> float:
        """l(V, V): the smallest distance between two distinct polygon vertices."""
        d, _ = cKDTree(self._vertices).query(self._vertices, k=2)
        return float(d[:, 1].min())

    # -- conversions -------------------------------------------------------------
    def to_shapely(self) -> shapely.Polygon:
        """The polygon as a :class:`shapely.Polygon`."""
        return shapely.Polygon(self._rings[0], list(self._rings[1:]))

    @classmethod
    def from_shapely(cls, geom) -> "Polygon":
        """Build from a :class:`shapely.Polygon` (a MultiPolygon is refused)."""
        if geom.geom_type != "Polygon":
            raise InvalidPolygonError(
                f"expected a single Polygon, got a {geom.geom_type}; "
                "mesh each part separately"
            )
        return cls(
            np.asarray(geom.exterior.coords), [np.asarray(h.coords) for h in geom.interiors]
        )

    def split_segments(self) -> list[np.ndarray]:
        """The segments as polylines through every vertex on them (junctions
        included), one per input segment, each (k_i, 2) float64."""
        out = []
        for s in range(len(self._segments)):
            e = self._segment_edges[self._segment_ids == s]
            out.append(self._vertices[np.append(e[:, 0], e[-1, 1])])
        return out

    def with_rings(self, rings) -> "Polygon":
        """A polygon with ``rings`` (the outer ring, then the holes; each (k, 2))
        and this one's segments, fixed points and region seeds: a resampled
        outline's.

        Examples
        --------
        >>> p = Polygon([(0, 0), (2, 0), (2, 2), (0, 2)], points=[(1, 1)])
        >>> q = p.with_rings([[(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)]])
        >>> len(q.vertices), q.points.tolist()
        (6, [[1.0, 1.0]])
        """
        return Polygon(rings[0], rings[1:], segments=self.split_segments(), points=self._points,
                       regions=self.region_seeds)

    def transformed(self, scale: float = 1.0, offset=(0.0, 0.0)) -> "Polygon":
        """A copy with every vertex mapped to ``scale * v + offset``.

        Segments are mapped through their junction vertices, so a junction stays
        one even where rounding would move a mapped point off a mapped line.
        """
        off = np.asarray(offset, dtype=np.float64)
        return Polygon(
            self._rings[0] * scale + off,
            [h * scale + off for h in self._rings[1:]],
            segments=[s * scale + off for s in self.split_segments()],
            points=self._points * scale + off,
            regions=[(x * scale + off[0], y * scale + off[1], lab) for x, y, lab in self._seeds],
        )

    def __eq__(self, other) -> bool:
        if not isinstance(other, Polygon):
            return NotImplemented
        if len(self._rings) != len(other._rings) or self._vertices.shape != other._vertices.shape:
            return False
        return (
            all(np.array_equal(a, b) for a, b in zip(self._rings, other._rings))
            and np.array_equal(self._vertices, other._vertices)
            and np.array_equal(self._segment_edges, other._segment_edges)
            and np.array_equal(self._fixed, other._fixed)
            and self._seeds == other._seeds
        )

    __hash__ = None

    def __repr__(self) -> str:
        more = ""
        if self.has_constraints:
            more = f", {len(self._segments)} segments, {len(self._points)} points"
        if self._seeds:
            more += f", {len(self._seeds)} region labels"
        return (
            f"Polygon({len(self._vertices)} vertices, {self.n_holes} holes{more}, "
            f"area={self._area:.6g})"
        )


def as_polygon(polygon) -> Polygon:
    """``polygon`` as a :class:`Polygon`: itself, from a shapely Polygon, or from an outer ring."""
    if isinstance(polygon, Polygon):
        return polygon
    if hasattr(polygon, "geom_type"):
        return Polygon.from_shapely(polygon)
    return Polygon(polygon)
