"""The interior of a start: a hexagonal lattice with exactly the count wanted.

:func:`lattice_seed` (public) and the optimiser's starts place their interior
points with :func:`seed_interior`: a lattice aligned with an edge of P, its
spacing searched (:func:`closest_count`) so that the count comes out, within a
tolerance the :class:`Fit` names, then made exact; where segments split P into
regions, a lattice per region, with its share of the points.
"""

from __future__ import annotations

import enum
import math

import numpy as np
import shapely

from .._kernel.clearance import bucket_grid, none_within
from .._kernel.distance import to_segments
from .._kernel import spacing
from .._kernel.hexrows import lattice_inside
from ..geometry import polygon_edges
from ..polygon import Polygon
from .boundary import target_size
from .fill import fill_band_gaps, fill_largest_gaps
from .rows import boundary_rows, keep_clear
from .shares import anchor, region_shares, sides_of

__all__ = ["lattice_seed", "seed_interior", "Fit", "Candidates", "closest_count", "drop_nearest",
           "hex_lattice", "LATTICE_ROWS"]

#: Rows of :func:`hex_lattice` made at a time: a dozen full-size temporaries of
#: the lattice over the polygon's box cost hundreds of MB at 1e6 points; row
#: blocks keep those to a few MB, the result unchanged.
LATTICE_ROWS = 64


def _frame(bounds, spacing: float, angle: float, origin) -> tuple:
    """(dy, cos, sin, i0, i1, j0, j1): the row step, the rows' direction and
    the columns and rows of the lattice of :func:`hex_lattice` that can reach
    ``bounds`` (a margin of two steps for the half-step shift of odd rows and
    for rounding)."""
    xmin, ymin, xmax, ymax = (float(b) for b in bounds)
    dy = spacing * math.sqrt(3.0) / 2
    c, s = math.cos(angle), math.sin(angle)
    ox, oy = float(origin[0]), float(origin[1])
    # the box's four corners in the lattice's frame, in plain floats: the
    # same operations as numpy's, element by element (the starts' spacing
    # search calls this some 100 times a mesh, where numpy's overhead told)
    corners = [(xmin - ox, ymin - oy), (xmax - ox, ymin - oy), (xmax - ox, ymax - oy),
               (xmin - ox, ymax - oy)]
    U = [c * X + s * Y for X, Y in corners]
    V = [-s * X + c * Y for X, Y in corners]
    j0, j1 = math.floor(min(V) / dy) - 2, math.ceil(max(V) / dy) + 2
    i0, i1 = math.floor(min(U) / spacing) - 2, math.ceil(max(U) / spacing) + 2
    return dy, c, s, i0, i1, j0, j1


def hex_lattice(bounds, spacing: float, angle: float, origin) -> np.ndarray:
    """The points of a hexagonal lattice (anchored at ``origin``, rows at ``angle``)
    within ``bounds`` = (xmin, ymin, xmax, ymax): the only ones that can lie inside
    a shape with those bounds.  Row by row, in a fixed order."""
    xmin, ymin, xmax, ymax = bounds
    dy, c, s, i0, i1, j0, j1 = _frame(bounds, spacing, angle, origin)
    out = []
    i = np.arange(i0, i1 + 1)[None, :]
    for jb in range(j0, j1 + 1, LATTICE_ROWS):
        # a column of rows against a row of columns: the grid by broadcasting
        j = np.arange(jb, min(jb + LATTICE_ROWS, j1 + 1))[:, None]
        u = (i + 0.5 * (j & 1)) * spacing
        v = j * dy
        x = origin[0] + c * u - s * v
        y = origin[1] + s * u + c * v
        keep = (x >= xmin) & (x <= xmax) & (y >= ymin) & (y <= ymax)
        out.append(np.stack([x[keep], y[keep]], axis=1))
    return np.concatenate(out, axis=0)


def lattice_seed(polygon: Polygon, count: int, *, rows: bool = True) -> np.ndarray:
    """Exactly ``count`` points of a hexagonal lattice inside P, away from its boundary.

    With ``rows`` (default), the first layer is a fan at every corner of
    90 degrees or more that is not within 30 degrees of straight (points one
    edge length from the corner that split its angle into near-60-degree
    parts), then one point above the middle of every polygon edge, at the apex
    of the equilateral triangle on it (those crowding a point before them
    dropped): the boundary's own spacing, wherever it is.  Interior segments
    count as boundary on both sides (a free end is a corner of 360 degrees).
    The lattice, aligned with P's longest edge, fills the rest; its spacing is
    chosen so that the count comes out (the last few are dropped near the
    boundary or added in the largest gaps).  Where segments split P into
    regions, each region gets its share of the count and a lattice of its own.
    A structured start for :func:`uniform2d.optimize.improve`: relaxing a
    lattice ends far more uniform than relaxing scattered points.

    Parameters
    ----------
    polygon : Polygon
    count : int
    rows : bool

    Returns
    -------
    ndarray, shape (count, 2)

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> from uniform2d.optimize import lattice_seed
    >>> lattice_seed(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), 9).shape
    (9, 2)
    """
    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    count = int(count)
    h = target_size(polygon, count)
    pieces = np.ones(len(polygon.constraint_edges), np.int64)
    first = boundary_rows(polygon, pieces, h) if rows else None
    return seed_interior(polygon, count, h, np.empty((0, 2)), None, first)


class Fit(enum.Enum):
    """How :func:`closest_count`'s search on the lattice spacing may miss the count
    by up to ``count // 500`` candidates (the tolerance), and how the start is
    then made exact.

    NEAREST  either side, the nearer found; :func:`lattice_seed`'s points.
    ABOVE    only too many (the fix-up drops the extra ones nearest to the
             boundary, :func:`drop_nearest`): the optimiser's starts, whose
             filling a shortfall (:func:`~uniform2d.optimize.fill.fill_largest_gaps`)
             would triangulate the whole seed.
    BELOW    only too few, filled where the lattice meets the boundary
             (:func:`~uniform2d.optimize.fill.fill_band_gaps`): the optimiser's
             large starts, whose short schedule does not close the holes that
             points dropped from that layer leave (regions use ABOVE).
    """

    NEAREST = "nearest"
    ABOVE = "above"
    BELOW = "below"


#: Each :class:`Fit`'s code in :func:`~uniform2d._kernel.spacing.closest_count`.
_FITS = {Fit.NEAREST: spacing.NEAREST, Fit.ABOVE: spacing.ABOVE, Fit.BELOW: spacing.BELOW}


#: Bucket side (in target sizes) of the points a lattice keeps clear of
#: (:func:`~uniform2d._kernel.clearance.bucket_grid`): above the largest
#: distance tested (three quarters of the widest spacing searched, 1.5 h), so
#: that a test reads the 3 x 3 buckets around a point.
CELL = 1.2


def _bucketed(R, cell: float) -> tuple:
    """(R as a contiguous float array, its bucket grid of side ``cell``)."""
    R = np.ascontiguousarray(R, dtype=float)
    return (R, *bucket_grid(R, cell))


class Candidates:
    """Lattice points of a given spacing inside P (or inside ``face``, one of its
    regions, anchored at ``origin``), clear of its boundary and of the first rows
    (when given): the candidates :func:`seed_interior` counts."""

    def __init__(self, polygon: Polygon, h: float, edge: int | None, rows, face=None, origin=None,
                 held=None):
        a, d, L = polygon_edges(polygon)
        e = int(np.argmax(L)) if edge is None else int(edge)
        self.angle = math.atan2(d[e, 1], d[e, 0])
        # anchor a lattice row at distance h·√3/2 inside the chosen edge
        nrm = np.array([-d[e, 1], d[e, 0]]) / L[e]  # left normal: inside for the CCW outer ring
        self.origin = a[e] + nrm * h * math.sqrt(3) / 2 + d[e] / L[e] * (h / 2)
        if origin is not None:
            self.origin = origin
        # inside P: row by row (lattice_inside), without a point-in-polygon
        # query per point of the box; inside a region (a shapely face): by shapely
        self.face = face
        self.bounds = polygon.bounds if face is None else face.bounds
        if face is not None:
            shapely.prepare(self.face)
        self.rings = polygon.vertices, polygon.edges
        self._uv = None  # the rings in the lattice's coordinates, for its origin and angle
        self.sa, self.sb = keep_clear(polygon)  # clear of the segments and fixed points too
        self.rows = rows
        # what the lattice keeps clear of, bucketed once for the ten or so
        # lattices a search tries (none_within: a k-d tree's decision, for
        # less than its query's call costs)
        self._cell = CELL * h
        if rows is not None:
            self.rgrid = _bucketed(rows, self._cell)
            self.band = h * math.sqrt(3) / 2
        # points placed before the lattice anywhere (rows around small holes)
        self.held = None
        if held is not None and len(held):
            self.held = _bucketed(held, self._cell)

    def _inside(self, sp, cap):
        """The lattice points of spacing ``sp`` inside and their distance to
        what they keep clear of, capped at ``cap`` (see :meth:`__call__`)."""
        if self.face is not None:
            P = hex_lattice(self.bounds, sp, self.angle, self.origin)
            P = P[shapely.contains_xy(self.face, P[:, 0], P[:, 1])]
            return P, to_segments(P, self.sa, self.sb, cap)
        origin, rings, seg = self._lattice_coords()
        dy, c, s, i0, i1, j0, j1 = _frame(self.bounds, sp, self.angle, origin)
        frame = np.array([sp, dy, c, s, i0, i1, j0, j1], dtype=float)
        return lattice_inside(frame, origin, np.asarray(self.bounds, dtype=float), *rings, seg,
                              float(cap))

    def _lattice_coords(self):
        """(origin, P's ring edges, what the points keep clear of): the
        arguments of :func:`~uniform2d._kernel.hexrows.lattice_inside`, the
        rings in the lattice's coordinates for its origin and angle."""
        origin = np.asarray(self.origin, dtype=float)
        key = (origin[0], origin[1], self.angle)
        if self._uv is None or self._uv[0] != key:
            c, s = math.cos(self.angle), math.sin(self.angle)

            def uv(P):  # the lattice's coordinates of points (k, 2)
                X, Y = P[:, 0] - origin[0], P[:, 1] - origin[1]
                return c * X + s * Y, -s * X + c * Y

            V, E = self.rings  # each vertex once: the edges meeting there meet exactly
            U, W = uv(V)
            self._uv = (key, (U[E[:, 0]], W[E[:, 0]], U[E[:, 1]], W[E[:, 1]]),
                        (self.sa, self.sb, *uv(self.sa), *uv(self.sb)))
        return origin, self._uv[1], self._uv[2]

    def __call__(self, sp):
        # a point within rounding of the boundary may be counted inside or
        # not (lattice_inside); none within half a spacing of it is kept
        rows = self.rows is not None
        # only distances below the cap matter, here and in the drop below
        cap = (2.0 * self.band + 2.0 * sp) if rows else 2.0 * sp
        P, dist = self._inside(sp, cap)
        ok = dist >= 0.5 * sp
        # a lattice point stays if nothing placed before it is nearer than
        # 0.75 sp (the buckets around it read alone, _clear_of)
        clear = 0.75 * sp
        if rows:  # rows lie within ~band of the boundary: test only near ones
            ok &= dist >= self.band + 0.5 * sp
            near = np.flatnonzero(ok & (dist < 2.0 * self.band + sp))
            ok[near] = self._clear_of(self.rgrid, P[near], clear)
        if self.held is not None:
            ok &= self._clear_of(self.held, P, clear)
        return P[ok], dist[ok]

    def _clear_of(self, grid, P, r):
        """Whether each point of P has no point of ``grid`` (a point set and
        its :func:`~uniform2d._kernel.clearance.bucket_grid`) nearer than r."""
        R, x0, y0, nx, ny, start, order = grid
        return none_within(P, R, x0, y0, self._cell, nx, ny, start, order, float(r))

    def search(self, count: int, h: float, fit: Fit):
        """:func:`closest_count` (the same lattice found), in one kernel call
        where the candidates are P's (:mod:`~uniform2d._kernel.spacing`: no
        Python between the lattices tried, which held the GIL while the
        starts run on several threads); in a region, :func:`closest_count`."""
        if self.face is not None:
            return closest_count(self, count, h, fit)
        origin, rings, seg = self._lattice_coords()
        rows, held = self.rows is not None, self.held is not None
        empty = _bucketed(np.empty((0, 2)), 1.0)
        return spacing.closest_count(
            int(count), float(h), _FITS[fit], np.asarray(self.bounds, dtype=float), origin,
            math.cos(self.angle), math.sin(self.angle), rings, seg,
            float(self.band) if rows else 0.0, rows, self.rgrid if rows else empty,
            held, self.held if held else empty, float(self._cell))


def closest_count(cand: Candidates, count: int, h: float, fit: Fit = Fit.NEAREST):
    """Search on the lattice spacing for ``count`` candidates (the count
    decreases with the spacing); the best (points, distances) found.  ``fit``
    as :class:`Fit` says.

    Bisection, stopping within ``count // 500`` of the count.  With ABOVE
    (the optimiser's starts) it stops only at up to that many candidates too
    many (the fix-up, :func:`drop_nearest`, drops the extra ones nearest to
    the boundary), not too few: filling those (:func:`fill_largest_gaps`)
    triangulates the whole seed.  With ABOVE and a tolerance (count >= 500)
    each step also aims where the count, about proportional to 1/spacing**2,
    says the target is (:func:`uniform2d._kernel.spacing._aim`), bisecting only where that would not
    halve the bracket, and gives up where the bracket is 1e-4 h wide (the
    count jumps there: a row of an aligned lattice enters at once): 9 lattices
    a start instead of 14 on the benchmark polygons at n = 1000.  Below 500
    the count must come out exactly, and the plain bisection's lattice (which
    can sit a hair from such a jump) gave better minimum angles at n = 200.
    BELOW (the optimiser's large starts) is ABOVE's search stopping at
    up to ``count // 500`` candidates too few instead, which
    :func:`fill_band_gaps` adds where the lattice meets the boundary: points
    dropped from that layer leave holes there that the short schedule of a
    large mesh does not close (its longest edges and largest triangles)."""
    # the steps are the kernel's (:func:`uniform2d._kernel.spacing.step`): the
    # same search as its whole-kernel one, on candidates only Python can count
    lo, hi, mid, aimed = spacing.start(float(h))
    best = None
    for _ in range(30):
        P, dist = cand(mid)
        better, outcome, lo, hi, mid, aimed = spacing.step(
            len(P), 0 if best is None else len(best[0]), best is not None, int(count), float(h),
            _FITS[fit], lo, hi, mid, aimed)
        if better:
            best = (P, dist)
        if outcome == spacing.TAKE:
            return P, dist
        if outcome == spacing.BEST:
            break
    return best


def drop_nearest(cand: Candidates, P, dist, count: int) -> np.ndarray:
    """The ``count`` of the lattice points P farthest from the boundary (in
    their order)."""
    if len(P) <= count:
        return P
    if np.count_nonzero(dist < dist.max()) < len(P) - count:  # capped ones would go
        dist = to_segments(P, cand.sa, cand.sb, np.inf)
    order = np.lexsort((np.arange(len(P)), dist))
    return P[np.sort(order[len(P) - count :])]


def seed_interior(
    polygon: Polygon, count: int, h: float, bpts: np.ndarray, edge: int | None = None,
    rows: np.ndarray | None = None, bedges: np.ndarray | None = None, fit: Fit = Fit.NEAREST,
    held: np.ndarray | None = None, lattice=None,
) -> np.ndarray:
    """``count`` interior points on a hexagonal lattice aligned with polygon edge
    ``edge`` (default: the longest), deterministic.  With ``rows`` (from
    :func:`boundary_rows`) those come first and the lattice fills the rest,
    clear of them.  Where the segments split P into regions, each region gets
    its own share of the points (:func:`region_shares`): points cannot cross
    a segment afterwards, so a region seeded too densely stays so.  ``bedges``
    (optional): the polygon edge of each boundary point ``bpts``, as the caller
    placed them, so that gaps are found without judging them by distance.
    ``over``: as :func:`closest_count`'s (the optimiser's starts; the default
    keeps :func:`lattice_seed`'s points as they were); ``under``: also as
    its, where the lattice is not split into regions.  ``held`` (optional):
    points placed before the rows (:mod:`~uniform2d.optimize.transition`'s),
    which come first in the result and which the lattice keeps clear of
    wherever they are (the rows only near the boundary).  ``lattice``
    (optional): ``(origin, angle, spacing, natural)`` of a lattice shared
    with other meshes (the parts of a partitioned mesh) instead of one of P's
    own whose spacing is searched for the count; with ``natural`` all its
    points inside are taken, however many (``count`` is then only a guide);
    ignored where segments split P."""
    if count <= 0:
        return np.empty((0, 2))
    if held is not None and (not len(held) or len(held) >= count):
        held = None
    if rows is not None and len(rows) >= count - (0 if held is None else len(held)):
        rows = None
    if held is not None and len(polygon.segment_edges) and len(polygon.regions) > 1:
        rows = held if rows is None else np.concatenate([held, rows])
        held = None
    if rows is not None and len(polygon.segment_edges) and len(polygon.regions) > 1:
        return _seed_regions(polygon, count, h, bpts, edge, rows, bedges, fit is not Fit.NEAREST)
    cand = Candidates(polygon, h, edge, rows, held=held)
    if lattice is not None:
        cand.origin, cand.angle = lattice[0], lattice[1]
    total = count
    first = [q for q in (held, rows) if q is not None]
    count = total - sum(len(q) for q in first)
    P, dist = cand.search(count, h, fit) if lattice is None else cand(lattice[2])
    if lattice is not None and lattice[3]:
        count = len(P)
        total = count + sum(len(q) for q in first)
    P = drop_nearest(cand, P, dist, count)
    if first:
        P = np.concatenate([*first, P])
        count = total
    if fit is Fit.BELOW:
        return fill_band_gaps(polygon, bpts, P, count, h, cand.sa, cand.sb, bedges)
    return fill_largest_gaps(polygon, bpts, P, count, bedges=bedges)


def _seed_regions(
    polygon: Polygon, count: int, h: float, bpts, edge, rows, bedges=None, over=False
) -> np.ndarray:
    """:func:`seed_interior` region by region: the rows, then in each region a
    lattice (of its own spacing, see :func:`anchor`) topped up to the region's
    share."""
    faces = polygon.regions.faces
    sides = sides_of(polygon, faces)
    share = region_shares(polygon, faces, sides, h, count)
    P = np.empty((0, 2)) if rows is None else rows
    angle = Candidates(polygon, h, edge, None).angle
    for r, face in enumerate(faces):
        have = int(np.count_nonzero(shapely.contains_xy(face, P[:, 0], P[:, 1])))
        need = share[r] - have
        if need <= 0:
            continue
        cand = Candidates(polygon, h, edge, rows, face, anchor(polygon, sides, r, angle, h))
        Q, dist = closest_count(cand, need, h, Fit.ABOVE if over else Fit.NEAREST)
        P = np.concatenate([P, drop_nearest(cand, Q, dist, need)])
        P = fill_largest_gaps(polygon, bpts, P, len(P) + need - min(need, len(Q)), face, bedges)
    if len(P) > count:  # rows beyond some region's share: drop lattice points instead
        first = 0 if rows is None else len(rows)
        dist = to_segments(P[first:], *keep_clear(polygon), np.inf)
        order = np.lexsort((np.arange(len(dist)), dist))
        P = np.concatenate([P[:first], P[first:][np.sort(order[len(P) - count:])]])
    return fill_largest_gaps(polygon, bpts, P, count, bedges=bedges)[:count]
