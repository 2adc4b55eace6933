"""Interior constraints of a polygon: segments (polylines) and fixed points.

:func:`build` turns the caller's polylines and points into a planar straight-line
graph on top of the polygon's rings, decided exactly (rational arithmetic on the
floats as given, so no floating-point error judges a junction):

* every vertex that lies on a piece of a segment or a ring edge, other than its
  ends, splits it there: a segment ending on a ring edge (a T-junction) or a
  fixed point on it becomes a vertex of that ring, a fixed point or another
  segment's end on a segment splits that segment;
* "on" includes within :data:`NEAR_ULPS` units in the last place of the
  coordinates (still decided exactly): a junction placed by computing
  ``a + t (b - a)`` rounds a hair off its piece, and a vertex left that close
  beside a piece would make a sliver no coordinate can hold a point in;
* pieces that cross properly, or overlap along a line (or that close to one),
  are refused with the two pieces and the place named; so is a piece outside
  P or in a hole;
* so are two pieces that run along each other closer than INSERT can keep
  apart (:func:`apart_tol`: its tie tolerance, or the rounding of the
  coordinates, whichever is larger) at two distinct places -- e.g. two
  segments leaving one vertex at an angle so small that their far ends are
  that close: points INSERT puts on one would land within its tolerance of the
  other, and the mesh could not keep both.

Nothing is repaired silently: the only change to the input is the splitting
above, which keeps every given point where it was given.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import shapely

from ._kernel.rank import REL_TIE
from .errors import InvalidConstraintError
from .geometry import check_finite, xy_array

__all__ = ["Constraints", "build"]


@dataclass(frozen=True)
class Constraints:
    """The planar straight-line graph of a polygon's rings, segments and points.

    Attributes
    ----------
    rings : list of ndarray
        The rings with the T-junction vertices spliced into their edges.
    extra : ndarray, shape (K, 2)
        Constraint vertices not on a ring, each once, in order of appearance
        (segment vertices first, then fixed points).
    segment_edges : ndarray, shape (S, 2), int64
        The segments' pieces as indices into ``rings`` then ``extra`` concatenated;
        no vertex lies inside a piece.
    segment_ids : ndarray, shape (S,), int64
        The input segment each piece belongs to.
    fixed : ndarray, shape (F,), int64
        The vertex index of each fixed point.
    """

    rings: list
    extra: np.ndarray
    segment_edges: np.ndarray
    segment_ids: np.ndarray
    fixed: np.ndarray


def _fmt(p) -> str:
    return f"({float(p[0]):.17g}, {float(p[1]):.17g})"


def _q(p) -> tuple[Fraction, Fraction]:
    return Fraction(float(p[0])), Fraction(float(p[1]))


def _orient(a, b, c) -> int:
    v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (v > 0) - (v < 0)


def _strictly_inside(p, a, b) -> bool:
    """Is p on the open segment a-b?  (Exact, rational points.)"""
    if _orient(a, b, p) != 0 or p == a or p == b:
        return False
    return min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


#: A vertex this many units in the last place (of the largest coordinate of it
#: and the piece) or nearer to a piece, beside its inside, is a junction on it.
NEAR_ULPS = 2


def apart_tol(rings, lines, points=()) -> float:
    """How far apart two constraint pieces must stay (beyond the place where they
    meet): INSERT's tie tolerance on coordinates, ``REL_TIE`` of the polygon's
    size (the larger side of its bounding box) plus 4 units in the last place of
    its largest coordinate (the most its rounding of a point to the caller's
    coordinates allows for, :func:`uniform2d.tolerance.grain`)."""
    allv = np.concatenate([np.asarray(r, dtype=np.float64).reshape(-1, 2) for r in
                           [*rings, *lines, np.asarray(points, dtype=np.float64).reshape(-1, 2)]])
    outer = np.asarray(rings[0], dtype=np.float64)
    extent = float(np.max(outer.max(axis=0) - outer.min(axis=0)))
    return REL_TIE * extent + 4.0 * float(np.spacing(np.abs(allv).max()))


def _dist2_to_piece(p, a, b) -> Fraction:
    """Squared distance from p to the closed segment a-b (exact, rational points)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    px, py = p[0] - a[0], p[1] - a[1]
    L2 = dx * dx + dy * dy
    t = min(max((px * dx + py * dy) / L2, Fraction(0)), Fraction(1))
    ex, ey = px - t * dx, py - t * dy
    return ex * ex + ey * ey


def _check_apart(p: "_Piece", q: "_Piece", tol: Fraction) -> None:
    """Refuse two segment pieces that run along each other within ``tol``: two
    ends (of either; a shared end counts once) within ``tol`` of the other piece
    and more than ``tol`` apart -- between them the pieces are that close, as
    INSERT cannot keep apart (:func:`apart_tol`).  Ends that close to each other
    are a meeting place, the junction rule's concern (:func:`_on_piece`).

    A piece along a ring edge is not refused: such strips (a few ulps wide)
    mesh correctly (the near-degenerate constraint tests); two interior pieces
    that close made meshes that had lost one of them."""
    if p.ring >= 0 or q.ring >= 0:
        return
    near = {x for x in (q.a, q.b) if _dist2_to_piece(x, p.a, p.b) <= tol * tol}
    near |= {x for x in (p.a, p.b) if _dist2_to_piece(x, q.a, q.b) <= tol * tol}
    near = sorted(near)
    for i, u in enumerate(near):
        for v in near[i + 1:]:
            if (u[0] - v[0]) ** 2 + (u[1] - v[1]) ** 2 > tol * tol:
                _refuse_along(p, q, u, v, tol)


def _refuse_along(p: "_Piece", q: "_Piece", u, v, tol: Fraction) -> None:
    other = f"piece {p.local} of itself" if p.what == q.what else p.what
    raise InvalidConstraintError(
        f"{q.what} (piece {q.local}) runs along {other} within {float(tol):.3g} of it "
        f"between {_fmt(u)} and {_fmt(v)}, closer than the mesh can keep apart "
        f"({REL_TIE:g} of the polygon's size plus the rounding of its coordinates); merge "
        f"them into one, or move them more than {float(tol):.3g} apart there (e.g. widen "
        "the angle where they meet)"
    )


def _near_tol(*pts) -> Fraction:
    big = max(abs(float(c)) for p in pts for c in p)
    return Fraction(NEAR_ULPS * float(np.spacing(big)))


def _on_piece(p, a, b) -> bool:
    """Is p a junction on piece a-b: its foot strictly between a and b, and p on
    the line or within :data:`NEAR_ULPS` units in the last place of it?  (Exact,
    rational points.)"""
    dx, dy = b[0] - a[0], b[1] - a[1]
    px, py = p[0] - a[0], p[1] - a[1]
    L2 = dx * dx + dy * dy
    if not 0 < px * dx + py * dy < L2:
        return False
    cross = dx * py - dy * px
    return cross == 0 or cross * cross <= _near_tol(p, a, b) ** 2 * L2


def polyline(coords, name: str) -> np.ndarray:
    """One segment as a float64 (k, 2) array, checked locally (closed if first == last)."""
    line = xy_array(coords, name, InvalidConstraintError)
    if line.ndim != 2 or line.shape[1] != 2 or len(line) < 2:
        hint = "; segments is a list of polylines: wrap a single one as [segment]" if line.ndim == 1 else ""
        raise InvalidConstraintError(
            f"{name}: expected a (k, 2) array of at least 2 (x, y) points, got shape "
            f"{line.shape}{hint}"
        )
    check_finite(line, name, InvalidConstraintError)
    same = np.all(line[1:] == line[:-1], axis=1)
    if same.any():
        i = int(np.flatnonzero(same)[0])
        raise InvalidConstraintError(
            f"{name}: vertices {i} and {i + 1} are the same point {_fmt(line[i])}, a zero-length "
            "piece; remove the repeated vertex"
        )
    if np.array_equal(line[0], line[-1]) and len(line) < 4:
        raise InvalidConstraintError(
            f"{name}: a closed segment needs at least 3 distinct vertices, got {len(line) - 1}"
        )
    return line


def fixed_points(coords) -> np.ndarray:
    """The fixed points as a float64 (K, 2) array, finite and distinct."""
    try:
        pts = np.array(coords, dtype=np.float64).reshape(-1, 2)
    except (TypeError, ValueError) as exc:
        raise InvalidConstraintError(f"points must be a (K, 2) array of coordinates ({exc})") from None
    bad = ~np.isfinite(pts).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InvalidConstraintError(f"point {i} has a non-finite coordinate {_fmt(pts[i])}")
    _, first, inv, counts = np.unique(pts, axis=0, return_index=True, return_inverse=True,
                                      return_counts=True)  # fmt: skip
    if (counts > 1).any():
        k = int(np.flatnonzero(counts > 1)[0])
        i, j = np.flatnonzero(inv.ravel() == k)[:2]
        raise InvalidConstraintError(
            f"points {int(i)} and {int(j)} are the same point {_fmt(pts[i])}; remove the duplicate"
        )
    return pts


@dataclass
class _Piece:
    a: tuple
    b: tuple
    what: str  # for messages: "segment 2" or "the outer ring" / "hole 1"
    ring: int  # ring index, -1 for a segment piece
    owner: int  # edge index within its ring, or segment index
    local: int  # piece index within its segment
    count: int = 0  # pieces in its segment
    closed: bool = False  # whether its segment is a closed polyline


def _pieces(rings, lines) -> list[_Piece]:
    out = []
    for r, ring in enumerate(rings):
        what = "the outer ring" if r == 0 else f"hole {r - 1}"
        q = [_q(p) for p in ring]
        for e in range(len(q)):
            out.append(_Piece(q[e], q[(e + 1) % len(q)], what, r, e, e))
    for s, line in enumerate(lines):
        q = [_q(p) for p in line]
        closed = q[0] == q[-1]
        for j in range(len(q) - 1):
            out.append(_Piece(q[j], q[j + 1], f"segment {s}", -1, s, j, len(q) - 1, closed))
    return out


def _boxes(pieces, tol: float = 0.0) -> np.ndarray:
    """(len(pieces), 4) bounding boxes, grown by twice the junction tolerance
    (:func:`_on_piece`), or ``tol`` if larger, so that a vertex near a piece is
    in its box."""
    a = np.array([[float(p.a[0]), float(p.a[1])] for p in pieces])
    b = np.array([[float(p.b[0]), float(p.b[1])] for p in pieces])
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    grow = 2 * NEAR_ULPS * np.spacing(np.maximum(np.abs(lo), np.abs(hi)).max(axis=1))
    grow = np.maximum(grow, 2 * tol)
    return np.hstack([lo - grow[:, None], hi + grow[:, None]])


def _candidate_pairs(pieces, tol: float) -> np.ndarray:
    """Index pairs (i < j, j a segment piece) whose bounding boxes (grown by the
    junction tolerance, or ``tol`` if larger) meet."""
    box = _boxes(pieces, tol)
    tree = shapely.STRtree(shapely.box(*box.T))
    seg = np.array([i for i, p in enumerate(pieces) if p.ring < 0], dtype=np.int64)
    if len(seg) == 0:
        return np.empty((0, 2), np.int64)
    q, hit = tree.query(shapely.box(*box[seg].T))
    pairs = np.stack([hit, seg[q]], axis=1)
    pairs = np.sort(pairs, axis=1)
    return np.unique(pairs[pairs[:, 0] != pairs[:, 1]], axis=0)


def _adjacent(p: _Piece, q: _Piece) -> bool:
    """Consecutive pieces of one polyline (closed ones wrap around)."""
    if p.ring >= 0 or q.ring >= 0 or p.owner != q.owner:
        return False
    d = abs(p.local - q.local)
    return d == 1 or (p.closed and d == p.count - 1 and p.count > 2)


def _check_fold(p: _Piece, q: _Piece) -> None:
    """Consecutive pieces may not fold back onto each other."""
    first, second = (p, q) if p.b == q.a else (q, p)
    if first.b != second.a or _orient(first.a, first.b, second.b) != 0:
        return
    dot = (first.b[0] - first.a[0]) * (second.b[0] - second.a[0]) + (
        first.b[1] - first.a[1]) * (second.b[1] - second.a[1])
    if dot < 0:
        raise InvalidConstraintError(
            f"{p.what} folds back on itself at {_fmt(first.b)} (pieces {first.local} and "
            f"{second.local} overlap); remove the doubled-back part"
        )


def _check_pair(p: _Piece, q: _Piece) -> None:
    """Refuse two pieces that overlap (two distinct points on both: shared ends or
    junctions, :func:`_on_piece`) or cross properly away from a junction."""
    inner = [x for x in (q.a, q.b) if _on_piece(x, p.a, p.b)]
    inner += [x for x in (p.a, p.b) if _on_piece(x, q.a, q.b)]
    if len(set(inner) | ({p.a, p.b} & {q.a, q.b})) >= 2:
        where = _fmt(inner[0] if inner else p.a)
        raise InvalidConstraintError(
            f"{q.what} runs along {p.what} (they overlap near {where}); a segment may not "
            "overlap a ring or another segment: remove the repeated part"
        )
    if inner:  # a junction (one end on the other piece, maybe a hair across it)
        return
    o1, o2 = _orient(p.a, p.b, q.a), _orient(p.a, p.b, q.b)
    o3, o4 = _orient(q.a, q.b, p.a), _orient(q.a, q.b, p.b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        x = _crossing(p, q)
        other = "itself" if p.what == q.what else p.what
        raise InvalidConstraintError(
            f"{q.what} crosses {other} at {_fmt(x)}; constraints may only meet at their "
            "vertices: split both there (or move one)"
        )


def _crossing(p: _Piece, q: _Piece):
    dx1, dy1 = p.b[0] - p.a[0], p.b[1] - p.a[1]
    dx2, dy2 = q.b[0] - q.a[0], q.b[1] - q.a[1]
    t = ((q.a[0] - p.a[0]) * dy2 - (q.a[1] - p.a[1]) * dx2) / (dx1 * dy2 - dy1 * dx2)
    return p.a[0] + t * dx1, p.a[1] + t * dy1


class _Rings:
    """The rings, for exact point location (float prefilter, rational decision)."""

    def __init__(self, rings):
        self.rings = [np.asarray(r) for r in rings]
        a = np.concatenate(self.rings)
        b = np.concatenate([np.roll(r, -1, axis=0) for r in self.rings])
        self.a, self.b = a, b
        self.lo, self.hi = np.minimum(a, b), np.maximum(a, b)

    def where(self, point) -> int:
        """1 inside P, 0 on its boundary, -1 outside or in a hole (exact)."""
        x, y = point
        xf, yf = float(x), float(y)
        # float(x) is within half an ulp of x: widen the filters by one ulp
        xl, xh = np.nextafter(xf, -np.inf), np.nextafter(xf, np.inf)
        yl, yh = np.nextafter(yf, -np.inf), np.nextafter(yf, np.inf)
        box = (self.lo[:, 0] <= xh) & (self.hi[:, 0] >= xl) & (self.lo[:, 1] <= yh) & (self.hi[:, 1] >= yl)
        for e in np.flatnonzero(box):
            a, b = _q(self.a[e]), _q(self.b[e])
            if point == a or _strictly_inside(point, a, b):
                return 0
        crossings = 0
        ray = (self.hi[:, 0] >= xl) & (self.lo[:, 1] <= yh) & (self.hi[:, 1] >= yl)
        for e in np.flatnonzero(ray):
            a, b = _q(self.a[e]), _q(self.b[e])
            if (a[1] > y) != (b[1] > y) and (_orient(a, b, point) > 0) == (b[1] > a[1]):
                crossings += 1
        return 1 if crossings % 2 else -1

    def outside_message(self, what: str, point) -> str:
        xy = (float(point[0]), float(point[1]))
        for h, hole in enumerate(self.rings[1:]):
            if shapely.contains_xy(shapely.Polygon(hole), *xy):
                return f"{what} at {_fmt(xy)} lies inside hole {h}; move it into the polygon's interior"
        return f"{what} at {_fmt(xy)} lies outside the polygon; move it inside the outer ring"


def _check_inside(pieces, inner, points, rings, on_rings) -> None:
    """Every segment piece (split at the vertices on it) and point lies in closed P
    (a point in ``on_rings``, a junction on a ring edge, is on the boundary even
    where it lies a rounding outside the edge)."""
    loc = _Rings(rings)
    for p, split in zip(pieces, inner):
        if p.ring >= 0:
            continue
        chain = [p.a, *split, p.b]
        for u, v in zip(chain[:-1], chain[1:]):
            mid = ((u[0] + v[0]) / 2, (u[1] + v[1]) / 2)
            if loc.where(mid) < 0:
                raise InvalidConstraintError(loc.outside_message(f"{p.what} (piece {p.local})", mid))
    for i, pt in enumerate(points):
        if _q(pt) not in on_rings and loc.where(_q(pt)) < 0:
            raise InvalidConstraintError(loc.outside_message(f"point {i}", _q(pt)))


def _splits(pieces, verts, n_ring: int) -> list[list]:
    """For every piece, the vertices that are junctions on it (:func:`_on_piece`),
    ordered from a to b.

    ``verts[:n_ring]`` are ring vertices: they cannot lie inside a ring edge (the
    rings are simple), so ring pieces are only matched with the others.
    """
    box = _boxes(pieces)
    vf = np.array([[float(v[0]), float(v[1])] for v in verts]).reshape(-1, 2)
    out = []
    for k, p in enumerate(pieces):
        lo = n_ring if p.ring >= 0 else 0
        near = lo + np.flatnonzero((vf[lo:, 0] >= box[k, 0]) & (vf[lo:, 0] <= box[k, 2])
                                   & (vf[lo:, 1] >= box[k, 1]) & (vf[lo:, 1] <= box[k, 3]))  # fmt: skip
        inner = [verts[i] for i in near if _on_piece(verts[i], p.a, p.b)]
        dx, dy = p.b[0] - p.a[0], p.b[1] - p.a[1]
        inner.sort(key=lambda v: (v[0] - p.a[0]) * dx + (v[1] - p.a[1]) * dy)
        out.append(inner)
    return out


def _check_ring_junctions(ring_pieces, inner) -> None:
    """A vertex may join one ring edge only: one within rounding of two (beside
    the vertex they share) would enter the ring twice."""
    seen = {}
    for p, split in zip(ring_pieces, inner):
        for v in split:
            if v in seen:
                raise InvalidConstraintError(
                    f"a segment or fixed point vertex at {_fmt(v)} lies on both {seen[v].what} "
                    f"edge {seen[v].owner} and {p.what} edge {p.owner} (within rounding of the "
                    "vertex they share); move it onto that vertex or clearly off it"
                )
            seen[v] = p


def build(rings, lines, points) -> Constraints:
    """The constraint graph of normalised ``rings`` with ``lines`` (checked by
    :func:`polyline`) and fixed ``points`` (checked by :func:`fixed_points`)."""
    pieces = _pieces(rings, lines)
    tol = apart_tol(rings, lines, points)
    for i, j in _candidate_pairs(pieces, tol):
        if _adjacent(pieces[i], pieces[j]):
            _check_fold(pieces[i], pieces[j])
        else:
            _check_pair(pieces[i], pieces[j])
        _check_apart(pieces[i], pieces[j], Fraction(tol))
    n_ring = sum(len(r) for r in rings)
    ring_verts = [p.a for p in pieces[:n_ring]]
    more = [p.a for p in pieces[n_ring:]] + [p.b for p in pieces[n_ring:]] + [_q(x) for x in points]
    on_rings = set(ring_verts)
    verts = ring_verts + [v for v in dict.fromkeys(more) if v not in on_rings]
    inner = _splits(pieces, verts, n_ring)
    _check_ring_junctions(pieces[:n_ring], inner[:n_ring])
    _check_inside(pieces, inner, points, rings, {v for split in inner[:n_ring] for v in split})
    new_rings = []
    k = 0
    for ring in rings:
        pts = []
        for _ in range(len(ring)):
            pts.append(pieces[k].a)
            pts.extend(inner[k])
            k += 1
        new_rings.append(pts)
    index = {}
    for pts in new_rings:
        for v in pts:
            index.setdefault(v, len(index))
    n_ring = len(index)
    edges, ids = [], []
    for p, split in zip(pieces[k:], inner[k:]):
        chain = [p.a, *split, p.b]
        for v in chain:
            index.setdefault(v, len(index))
        edges.extend((index[u], index[v]) for u, v in zip(chain[:-1], chain[1:]))
        ids.extend([p.owner] * (len(chain) - 1))
    fixed = [index.setdefault(_q(x), len(index)) for x in points]
    extra = sorted(((i, v) for v, i in index.items() if i >= n_ring))
    return Constraints(
        rings=[np.array([[float(x), float(y)] for x, y in pts]) for pts in new_rings],
        extra=np.array([[float(v[0]), float(v[1])] for _, v in extra]).reshape(-1, 2),
        segment_edges=np.array(edges, dtype=np.int64).reshape(-1, 2),
        segment_ids=np.array(ids, dtype=np.int64),
        fixed=np.array(fixed, dtype=np.int64),
    )
