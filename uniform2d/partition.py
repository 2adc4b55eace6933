"""Splitting a polygon into K parts of near-equal area along short, sampled cuts.

The first step of a partitioned mesh (:mod:`uniform2d.partitioned`).  Every
line the parts meet on is sampled **once**, at the target spacing h of the
whole mesh, and its points are numbered once; a part is a polygon whose ring
vertices are such points, so the parts' meshes share exactly the points of the
cuts between them and the stitched mesh is conforming by construction.

1. The rings and the interior segments are sampled first: every edge of length
   L gets ``max(1, round(L / h))`` equal pieces, as the optimiser's own start
   does (:func:`uniform2d.optimize.boundary.boundary_counts`).
2. Recursive bisection: a part of K' parts-to-be is cut across its longer side
   (a line ``x = c`` or ``y = c``) where the area on one side is
   ``floor(K'/2) / K'`` of it (a bisection search on c with shapely).  Each
   chord of that line through the part is snapped at both ends to the nearest
   ring sample (so the rings' spacing is never disturbed) and where it crosses
   a segment to the nearest sample of that segment, which becomes a shared
   point of the parts on both sides.  Offsets within a few h of the best one
   are tried in turn until the chords keep :data:`CLEARANCE` spacings clear of
   the part's other boundary points, of holes and of fixed points.
3. The chords are sampled at h like the rings.  A part may be several faces
   (a cut through a non-convex part); each face is a :class:`~uniform2d.Polygon`.

Different K cut differently, so they give different (equally valid) meshes.

Examples
--------
>>> from uniform2d import Polygon
>>> from uniform2d.partition import partition
>>> p = partition(Polygon([(0, 0), (4, 0), (4, 1), (0, 1)]), 400, 4)
>>> len(p.parts), [round(sum(f.area for f in part), 1) for part in p.parts]
(4, [1.0, 1.0, 1.0, 1.0])
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .errors import InsufficientPointsError, InternalError, InvalidArgumentError
from .optimize.boundary import target_size
from .polygon import Polygon

__all__ = ["CLEARANCE", "NUDGE_STEPS", "Partition", "partition"]

#: Offsets tried on either side of the area-balanced cut, in half spacings.
NUDGE_STEPS = 24

#: A cut keeps this many spacings from the boundary points, segment samples and
#: fixed points it does not pass through (0.7: it crosses a ring edge at 44
#: degrees or more, so no sliver forms where it ends).
CLEARANCE = 0.7

#: The search on the cut offset (halvings of the part's extent).
_BISECTIONS = 60


@dataclass(frozen=True, eq=False)
class Partition:
    """K parts and the points they share.

    Attributes
    ----------
    points : (S, 2) float64
        The shared points: the polygon's vertices first (as
        :attr:`uniform2d.Polygon.vertices`), then the segment samples, then
        the cut samples (those where a cut ends on a ring among them).
    n_cut : int
        How many of ``points`` (the last ones) are cut samples.
    parts : list of list of Polygon
        Per part, its faces (usually one): rings through the polygon's vertices
        and the cut samples only (the rings' own samples are the part's, placed
        again by its mesher where the partition put them), segments through
        their samples.
    index : list of list of (k,) int64
        Per part and face: the shared number of each of the face's vertices.
    cuts : list of (k,) int64
        Every cut chord as the shared numbers of its points, in order.
    h : float
        The spacing every line was sampled at.
    n_vertices : int
        How many of ``points`` (the first ones) are the polygon's vertices.
    """

    points: np.ndarray
    n_cut: int
    parts: list
    index: list
    cuts: list
    h: float
    n_vertices: int


class _Points:
    """Points numbered once, looked up by their exact coordinates."""

    def __init__(self, xy):
        self.xy = [tuple(map(float, p)) for p in np.asarray(xy, dtype=np.float64)]
        self.id = {}
        for i, p in enumerate(self.xy):
            self.id.setdefault(p, i)

    def add(self, p) -> int:
        p = (float(p[0]), float(p[1]))
        if p not in self.id:
            self.id[p] = len(self.xy)
            self.xy.append(p)
        return self.id[p]

    def sample(self, a: int, b: int, h: float) -> list[int]:
        """The ids of a..b split into ``max(1, round(L / h))`` equal pieces."""
        pa, pb = np.array(self.xy[a]), np.array(self.xy[b])
        m = max(1, int(np.rint(math.hypot(*(pb - pa)) / h)))
        return [a] + [self.add(pa + (pb - pa) * (k / m)) for k in range(1, m)] + [b]


def _sample_lines(polygon: Polygon, pts: _Points, h: float):
    """Rings as closed id sequences and the segments' sample edges (E, 2)."""
    rings = []
    for r in range(len(polygon.rings)):
        lo, hi = polygon.ring_offsets[r], polygon.ring_offsets[r + 1]
        ids = []
        for i in range(lo, hi):
            j = i + 1 if i + 1 < hi else lo
            ids.extend(pts.sample(i, j, h)[:-1])
        rings.append(ids)
    seg = []
    for a, b in polygon.segment_edges:
        s = pts.sample(int(a), int(b), h)
        seg.extend(itertools.pairwise(s))
    return rings, np.array(seg, dtype=np.int64).reshape(-1, 2)


def _halfplane(faces, normal, c: float):
    """A polygon covering the part of the faces' box where ``normal . p <= c``."""
    x0 = min(f.bounds[0] for f in faces)
    y0 = min(f.bounds[1] for f in faces)
    x1 = max(f.bounds[2] for f in faces)
    y1 = max(f.bounds[3] for f in faces)
    R = 2.0 * (math.hypot(x1 - x0, y1 - y0) + abs(c) + abs(x0) + abs(y0) + 1.0)
    n = np.asarray(normal)
    t = np.array([-n[1], n[0]])
    p0 = n * c
    return shapely.Polygon([p0 + t * R, p0 - t * R, p0 - t * R - n * R, p0 + t * R - n * R])


def _area_below(faces, normal, c: float) -> float:
    half = _halfplane(faces, normal, c)
    return float(sum(shapely.intersection(f, half).area for f in faces))


def _extent(faces, normal) -> tuple[float, float]:
    # written out, not ``@``: BLAS's kernel for the CPU rounds its own way
    s = np.concatenate([c[:, 0] * normal[0] + c[:, 1] * normal[1]
                        for c in (np.asarray(f.exterior.coords) for f in faces)])
    return float(s.min()), float(s.max())


def _balanced_offset(faces, normal, fraction: float) -> float:
    """The c with ``fraction`` of the faces' area where ``normal . p < c`` (bisection)."""
    lo, hi = _extent(faces, normal)
    want = fraction * sum(f.area for f in faces)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if _area_below(faces, normal, mid) < want:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


class _Context:
    """What every cut needs: the points, the segments' sample edges, the spacing."""

    def __init__(self, pts: _Points, seg: np.ndarray, avoid: np.ndarray, h: float):
        self.pts, self.seg, self.avoid, self.h = pts, seg, avoid, h
        self.cuts: list = []

    def xy(self, ids) -> np.ndarray:
        return np.array([self.pts.xy[i] for i in ids], dtype=np.float64)


def _face_ids(ctx: _Context, face) -> list[int]:
    out = []
    for ring in [face.exterior, *face.interiors]:
        out.extend(ctx.pts.id[tuple(p)] for p in list(ring.coords)[:-1])
    return out


def _segments_in(ctx: _Context, face) -> np.ndarray:
    """The segment sample edges (E, 2) inside ``face`` (their midpoints are)."""
    if not len(ctx.seg):
        return ctx.seg
    mids = ctx.xy(ctx.seg.ravel()).reshape(-1, 2, 2).mean(axis=1)
    return ctx.seg[shapely.contains_xy(face, mids[:, 0], mids[:, 1])]


def _chords(ctx: _Context, face, normal, c: float):
    """The chords of the line ``normal . p = c`` through ``face`` as id sequences
    (ends snapped to ring samples, segment crossings to segment samples), or
    None if a snapped chord would leave the face or cross a segment."""
    half = _halfplane([face], normal, c)
    cut = face.intersection(shapely.LineString(np.asarray(half.exterior.coords)[:2]))
    pieces = [g for g in shapely.get_parts(cut) if g.geom_type == "LineString" and g.length > 0]
    if not pieces:
        return []
    ring_ids = _face_ids(ctx, face)
    tree = cKDTree(ctx.xy(ring_ids))
    inside = _segments_in(ctx, face)
    seglines = shapely.MultiLineString([ctx.xy(e) for e in inside]) if len(inside) else None
    out = []
    for g in pieces:
        (px, py), (qx, qy) = g.coords[0], g.coords[-1]
        ends = [ring_ids[int(tree.query((px, py))[1])], ring_ids[int(tree.query((qx, qy))[1])]]
        mids = []
        if seglines is not None:
            for k in np.flatnonzero(shapely.intersects(shapely.get_parts(seglines), g)):
                a, b = inside[k]
                x = shapely.intersection(g, shapely.LineString(ctx.xy((a, b))))
                if x.geom_type != "Point":
                    return None
                pa, pb = np.array(ctx.pts.xy[a]), np.array(ctx.pts.xy[b])
                near = a if np.hypot(*(pa - x.coords[0])) <= np.hypot(*(pb - x.coords[0])) else b
                mids.append(near)
        first = np.array(ctx.pts.xy[ends[0]])
        mids.sort(key=lambda i: float(np.hypot(*(np.array(ctx.pts.xy[i]) - first))))
        chain = [ends[0]]
        for i in [*mids, ends[1]]:
            if i != chain[-1]:
                chain.append(i)
        if len(chain) < 2 or len(set(chain)) != len(chain):
            return None
        for a, b in itertools.pairwise(chain):
            ls = shapely.LineString(ctx.xy((a, b)))
            if not (face.contains(ls) and shapely.relate_pattern(ls, face.boundary, "F********")):
                return None
            if seglines is not None and shapely.relate_pattern(ls, seglines, "T********"):
                return None
        out.append(chain)
    used = [i for ch in out for i in ch]
    return out if len(used) == len(set(used)) else None


def _clear(ctx: _Context, face, chords) -> bool:
    """Whether the chords keep :data:`CLEARANCE` spacings clear of the face's other
    boundary points, of fixed points and of segment samples they do not pass through."""
    if not chords:
        return True
    on = {i for ch in chords for i in ch}
    others = [i for i in _face_ids(ctx, face) if i not in on]
    others += [int(i) for i in ctx.avoid if i not in on]
    others += [int(i) for i in np.unique(ctx.seg) if i not in on] if len(ctx.seg) else []
    if not others:
        return True
    lines = shapely.MultiLineString([ctx.xy(ch) for ch in chords])
    d = shapely.distance(shapely.points(ctx.xy(others)), lines)
    return bool(d.min() >= CLEARANCE * ctx.h)


def _split(ctx: _Context, faces, normal, c: float, strict: bool):
    """The faces below and above the cut, or None if this offset cannot cut them."""
    all_chords = []
    for f in faces:
        ch = _chords(ctx, f, normal, c)
        if ch is None or (strict and not _clear(ctx, f, ch)):
            return None
        all_chords.append(ch)
    below, above, sampled = [], [], []
    for f, chords in zip(faces, all_chords):
        if not chords:
            (below if _area_below([f], normal, c) >= 0.5 * f.area else above).append(f)
            continue
        lines = [ctx.xy(e) for e in _ring_edges(ctx, f)]
        for ch in chords:
            s = [ch[0]]
            for a, b in itertools.pairwise(ch):
                s.extend(ctx.pts.sample(a, b, ctx.h)[1:])
            sampled.append(s)
            lines.extend(ctx.xy(e) for e in itertools.pairwise(s))
        for g in shapely.get_parts(shapely.polygonize(shapely.linestrings(lines))):
            if not f.contains(g.representative_point()):
                continue  # a hole of f
            g = shapely.Polygon(g.exterior.coords, [r.coords for r in g.interiors])
            (below if _area_below([g], normal, c) >= 0.5 * g.area else above).append(g)
    if not below or not above:
        return None
    ctx.cuts.extend(sampled)
    return below, above


def _ring_edges(ctx: _Context, face):
    out = []
    for ring in [face.exterior, *face.interiors]:
        ids = [ctx.pts.id[tuple(p)] for p in ring.coords]
        out.extend(itertools.pairwise(ids))
    return out


def _bisect(ctx: _Context, faces, K: int) -> list:
    """The K parts of ``faces`` (lists of faces), by recursive bisection."""
    if K == 1:
        return [faces]
    k1 = K // 2
    spans = [np.subtract(*_extent(faces, n)[::-1]) for n in ctx.normals]
    order = np.lexsort((np.arange(len(spans)), -np.array(spans)))
    for strict in (True, False):
        for k in order:
            normal = ctx.normals[k]
            c0 = _balanced_offset(faces, normal, k1 / K)
            for j in range(2 * NUDGE_STEPS + 1):
                step = (j + 1) // 2 * (1 if j % 2 else -1)
                got = _split(ctx, faces, normal, c0 + 0.5 * ctx.h * step, strict)
                if got is not None:
                    return _bisect(ctx, got[0], k1) + _bisect(ctx, got[1], K - k1)
    raise InsufficientPointsError(
        f"a part of {sum(f.area for f in faces):.6g} area cannot be cut in {K} near the "
        f"balanced line at spacing {ctx.h:.6g}; ask for fewer parts or more points"
    )


def partition(polygon: Polygon, n: int, K: int) -> Partition:
    """Split ``polygon`` into ``K`` parts for a mesh with ``n`` Steiner points.

    Parameters
    ----------
    polygon : Polygon
    n : int
        The Steiner points of the whole mesh (sets the spacing h).
    K : int
        Parts, at least 1.

    Returns
    -------
    Partition

    Raises
    ------
    InvalidArgumentError
        If K is not a positive integer.
    InsufficientPointsError
        If a part cannot be cut at this spacing (too few points for K parts).
    """
    if isinstance(K, bool) or not isinstance(K, (int, np.integer)) or K < 1:
        raise InvalidArgumentError(f"parts must be a positive integer, got {K!r}")
    h = target_size(polygon, n)
    pts = _Points(polygon.vertices)
    rings, seg = _sample_lines(polygon, pts, h)
    lone = np.setdiff1d(polygon.fixed, np.concatenate([seg.ravel(), np.arange(polygon.n_ring_vertices)]))
    ctx = _Context(pts, seg, lone, h)
    ctx.normals = _lattice_normals(polygon)
    face = shapely.Polygon(ctx.xy(rings[0]), [ctx.xy(r) for r in rings[1:]])
    parts = _bisect(ctx, [face], int(K))
    # shared: the vertices, the segment samples, the cut samples, in that order
    nV = len(polygon.vertices)
    on_cut = np.unique(np.concatenate(ctx.cuts)) if ctx.cuts else np.zeros(0, np.int64)
    on_seg = np.setdiff1d(np.unique(seg), np.concatenate([np.arange(nV), on_cut]))
    keep = np.concatenate([np.arange(nV), on_seg, np.setdiff1d(on_cut, np.arange(nV))])
    new = np.full(len(pts.xy), -1, dtype=np.int64)
    new[keep] = np.arange(len(keep))
    polys, index = [], []
    for faces in parts:
        got = [_face_polygon(ctx, f, new) for f in faces]
        polys.append([g[0] for g in got])
        index.append([g[1] for g in got])
    cuts = [new[np.array(c, dtype=np.int64)] for c in ctx.cuts]
    return Partition(ctx.xy(keep), len(keep) - nV - len(on_seg), polys, index, cuts, h, nV)


def _lattice_normals(polygon: Polygon) -> list:
    """The normals of the three directions of a hexagonal lattice aligned with the
    polygon's longest edge (the parts' lattices run that way): cuts along them
    meet the lattices on both sides in rows, as a ring edge does."""
    a = polygon.vertices[polygon.edges]
    d = a[:, 1] - a[:, 0]
    e = int(np.argmax(np.hypot(d[:, 0], d[:, 1])))
    base = math.atan2(d[e, 1], d[e, 0])
    return [np.array([-math.sin(base + k * math.pi / 3), math.cos(base + k * math.pi / 3)])
            for k in range(3)]


def _face_polygon(ctx: _Context, face, new: np.ndarray):
    """A face as a Polygon of the shared points on its rings (``new`` >= 0), with
    its segment sample edges and fixed points, and the shared number of each of
    its vertices."""
    seg = _segments_in(ctx, face)
    lone = ctx.xy(ctx.avoid) if len(ctx.avoid) else np.zeros((0, 2))
    lone = lone[shapely.contains_xy(face, lone[:, 0], lone[:, 1])] if len(lone) else lone
    rings = []
    for ring in [face.exterior, *face.interiors]:
        ids = [ctx.pts.id[tuple(p)] for p in list(ring.coords)[:-1]]
        rings.append(ctx.xy([i for i in ids if new[i] >= 0]))
    poly = Polygon(rings[0], rings[1:], segments=[ctx.xy(e) for e in seg], points=lone)
    try:
        idx = np.array([new[ctx.pts.id[(float(x), float(y))]] for x, y in poly.vertices], dtype=np.int64)
    except KeyError:
        idx = np.array([-1])
    if (idx < 0).any():
        raise InternalError("a part's vertex is not a shared point (a bug: please report it)")
    return poly, idx
