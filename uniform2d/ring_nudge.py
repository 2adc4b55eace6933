"""Ring points at the ends of a resampled mesh's too-short edges moved apart, the mesh relaxed there.

Before meshing, :mod:`uniform2d.ring_slide` and :mod:`uniform2d.ring_pull`
lengthen short ring edges looking at the ring alone.  The mesh's shortest
edges are often not ring edges, though: a chord across the tip of a narrow
spike (the mesher puts one triangle there), an edge across a narrow feature
to a point the mesher put on a long ring edge, an edge from a resampled point
to a kept corner two places away.  What they are is only known once meshed.
:func:`nudge_rings` takes the mesh: for a mesh edge between two boundary
points shorter than half the longest (an edge that keeps the edge ratio above
2), it moves the end that is a movable ring point (placed by the resampling:
not a kept corner, segment end or fixed point) off the other end: the
position, among :data:`STEPS` spacings in the :data:`TURNS` directions from
straight away, where the least of its distance to the other end, its two
ring edges and its distance to the rest of the ring is largest (capped at
half the longest edge, the nearest such position first), where

- the rings stay within the tolerance of the outline, both ways
  (:func:`band_bound`: the point's two edges against the input ring, the
  input ring near the point against the rings, sampled, with the bound
  between samples), so the Hausdorff distance stays within the tolerance;
- neither of the point's ring edges becomes longer than :data:`LONGEST`
  spacings (or than it was), and the polygon stays valid.

:func:`nudged` (what :func:`uniform2d.uniform_mesh` with ``resample`` runs
where the edge ratio is above 2, also where the shortest ring edge forces a
ratio above 2: it may be one it moves) carries the mesh to
the moved polygon (boundary points along their edges) and relaxes the
points within :data:`RADIUS` target sizes of the moved ones
(:func:`relaxed`), keeping the result if its edge ratio is lower, its CV at
most :data:`CV_SLACK` higher and its worst angle at most :data:`ANGLE_SLACK`
lower: first every such end at once, then one at a time (a move that did not
help is not tried again), at most :data:`TRIES` times.  The polygon has as
many vertices, the kept ones do not move, and n stays exact; the deviation
reported is the larger of the resampling's and the moved edges' bound.
Where a move was kept, :func:`uniform2d.uniform_mesh` runs the relocation
moves (:mod:`uniform2d.ring_relocate`) once more.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import libm
from .errors import InvalidPolygonError
from .geometry import boundary_edges, unique_edges
from .mesh import Mesh
from .optimize.moves import improve_kept
from .optimize.pipeline import quality_summary
from .optimize.schedule import RELOCATE
from .polygon import Polygon
from .quality import quality
from .ring_split import SPLIT_RATIO, better_mesh
from .segment_distance import from_point, nearest
from .sites import classify_sites
from .threads import thread_map
from .tolerance import boundary_tol
from .validity import ensure_valid

__all__ = ["ANGLE_SLACK", "CHECKED", "CV_SLACK", "GAIN", "InputRing", "LONGEST", "RADIUS", "STEPS",
           "TRIES", "TURNS", "band_bound", "candidate_positions", "clearances", "first_in_band",
           "move_ends", "moved_stage", "nudge_rings", "nudged", "relaxed", "valid_rings"]

log = logging.getLogger(__name__)

#: Moves tried, in spacings, smallest first (at most the 0.25 spacing of the
#: usual tolerance: the point stays near the outline).
STEPS = np.arange(1, 13) / 48
#: Directions tried (radians from straight away from the edge's other end).
TURNS = (0.0, -np.pi / 6, np.pi / 6, -np.pi / 3, np.pi / 3)
#: A move lengthens the least of the point's distances by at least this many spacings.
GAIN = 0.01
#: Best candidates per point checked against the tolerance and for validity.
CHECKED = 60
#: A move makes neither of the point's ring edges longer than this many spacings
#: (or than it was): the mesher would split it.
LONGEST = 1.4
#: Moves tried (each a local relaxation of the mesh): every end at once, then one at a time.
TRIES = 12
#: Sites within this many target sizes of a moved ring point are relaxed again.
RADIUS = 4.0
#: The moved mesh is kept if its edge ratio is lower, its edge CV at most this
#: fraction higher ...
CV_SLACK = 0.01
#: ... and its worst angle at most this fraction lower.
ANGLE_SLACK = 0.01
#: Points per moved ring edge at which its distance to the outline is measured, less one.
_SAMPLES = 32
#: The input is sampled at this fraction of the tolerance for its distance to the rings.
_DENSE = 1 / 16


def band_bound(outline, ring, k: int, window: float, limit: float, dense=None) -> float:
    """A bound on the Hausdorff distance between ``ring`` ((r, 2), closed) and the
    input ring ``outline`` ((m, 2)) where it may have changed: around ring point
    ``k``, whose two edges are sampled (each point's exact distance to the
    outline, plus half the sample step), and the outline within ``window`` of
    point ``k`` sampled at ``limit / 16`` (each sample's exact distance to the
    ring, plus half the step; ``dense``: those samples of the whole outline, if
    the caller has them).

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([(0, 0), (4, 0), (4, 4), (0, 4)], float)
    >>> ring = np.array([(0, 0), (2, 0.1), (4, 0), (4, 4), (0, 4)], float)
    >>> b = band_bound(square, ring, 1, 3.0, 0.2)    # 0.1 off; half a sample step above
    >>> bool(0.1 <= b <= 0.1 + 0.5 * np.hypot(2, 0.1) / 32 + 0.2 / 32)
    True
    """
    source = InputRing(outline, limit, dense)
    return _Band(source, ring, k, window, ring[k], 0.0).bound(ring, k, window, limit)


class InputRing:
    """An input ring as :func:`band_bound` looks at it: its edges with their
    bounding boxes, and its dense samples in a k-d tree (built once per ring)."""

    def __init__(self, outline, limit: float, dense=None):
        ring = np.asarray(outline, dtype=np.float64)
        self.A, self.B = ring, np.roll(ring, -1, axis=0)
        self.lo, self.hi = np.minimum(self.A, self.B), np.maximum(self.A, self.B)
        self.dense = _dense(shapely.LinearRing(ring), limit) if dense is None else dense
        self.tree = cKDTree(self.dense)

    def segments_near(self, X, reach: float):
        """The edges (A, B) within ``reach`` of X (boxes first, then exact, in order)."""
        r = 1.01 * reach  # a box test rounded the wrong way drops no edge
        box = np.flatnonzero(np.all((self.lo <= X + r) & (self.hi >= X - r), axis=1))
        return _near_segments_of(self.A[box], self.B[box], X, reach)

    def dense_near(self, X, reach: float):
        """The dense samples within ``reach`` of X, in order."""
        got = self.dense[np.sort(self.tree.query_ball_point(X, 1.01 * reach))]
        return got[np.hypot(*(got - X).T) <= reach]


class _Band:
    """What :func:`band_bound` looks at around ring point ``k`` for every position
    within ``step`` of ``X0`` and every window up to ``window``: the input edges,
    the dense samples of the input and the ring edges that can be near (a
    superset: :meth:`bound` applies :func:`band_bound`'s own filters to them, so
    its value is the same)."""

    def __init__(self, source: InputRing, ring, k: int, window: float, X0, step: float):
        r = len(ring)
        # the margin keeps the prefilter a superset whatever the rounding
        far = 1.01 * (window + step) + 1e-9 * float(np.abs(X0).max(initial=1.0))
        self.A, self.B = source.segments_near(X0, far + window)  # reach <= 2 window
        self.dense = source.dense_near(X0, far)
        A, B = ring, np.roll(ring, -1, axis=0)
        near = from_point(X0, A, B) <= far + window
        near[[(k - 1) % r, k]] = True  # the moved point's edges: where they go
        self.ring_edges = np.flatnonzero(near)

    def bound(self, ring, k: int, window: float, limit: float) -> float:
        """:func:`band_bound` of ``ring`` (ring point ``k`` moved within the step)."""
        r = len(ring)
        X = ring[k]
        reach = window + limit
        t = np.arange(_SAMPLES + 1) / _SAMPLES
        out = 0.0
        A, B = _near_segments_of(self.A, self.B, X, reach)
        for a, b in ((ring[k - 1], X), (X, ring[(k + 1) % r])):
            Z = a[None, :] + t[:, None] * (b - a)[None, :]
            out = max(out, _farthest(Z, A, B) + 0.5 * float(np.hypot(*(b - a))) / _SAMPLES)
        near = self.dense[np.hypot(*(self.dense - X).T) <= window]
        if len(near):
            e = self.ring_edges
            RA, RB = _near_segments_of(ring[e], ring[(e + 1) % r], X, reach)
            out = max(out, _farthest(near, RA, RB) + 0.5 * _DENSE * limit)
        return out


def _near_segments(ring, X, reach: float):
    """The edges (A, B) of a closed ring within ``reach`` of point X."""
    return _near_segments_of(ring, np.roll(ring, -1, axis=0), X, reach)


def _near_segments_of(A, B, X, reach: float):
    """The segments (A, B) within ``reach`` of point X."""
    near = from_point(X, A, B) <= reach
    return A[near], B[near]


def _farthest(Z, A, B) -> float:
    """The largest, over points Z, of the distance to the nearest segment A B (inf if none)."""
    if not len(A):
        return np.inf
    return float(nearest(Z, A, B).max())


def _dense(line, limit: float) -> np.ndarray:
    """The outline's vertices and points between, at most ``limit / 16`` apart."""
    return shapely.get_coordinates(shapely.segmentize(line, _DENSE * limit))


def nudge_rings(outline: Polygon, res, points, triangles, limit: float, skip=(),
                most: int | None = None, sources: dict | None = None):
    """The rings of ``res.polygon`` (:class:`uniform2d.outline.Resampled`) with
    the movable ends of the mesh's too-short boundary edges moved off their
    other ends (see the module notes).

    Parameters
    ----------
    outline : Polygon
        The input polygon ``res`` resampled (its rings in the same order).
    res : uniform2d.outline.Resampled
    points : (N, 2) float64
    triangles : (M, 3) int64
        A mesh of ``res.polygon`` (its vertices first).
    limit : float
        The tolerance, a length.
    skip : collection of (int, int)
        (point, other end) pairs not to try.
    most : int, optional
        Move at most this many points (the shortest edges' first).
    sources : dict, optional
        Filled with what the tolerance check keeps of each input ring (by ring
        index; pass the same dict to later calls with the same ``outline`` and
        ``limit`` not to build it again).

    Returns
    -------
    list of (r, 2) float64
        The rings.
    list of (int, int)
        The (point, other end) pairs moved, in order.
    float
        A bound on the moved edges' distance to the outline, both ways (0 if
        none moved).
    list of (int, int)
        The pairs tried that found no move.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.outline import Resampled
    >>> from uniform2d.triangulation import triangulate
    >>> sq = Polygon([(0, 0), (3, 0), (3, 3), (0, 3)])
    >>> res = Resampled(Polygon([(0, 0), (1, 0), (1.45, 0), (3, 0), (3, 3), (0, 3)]),
    ...                 np.array([1, 0, 0, 1, 1, 1], bool), 1.0, 0.25, 0.0, 4)
    >>> P, T = triangulate(res.polygon, [(1.5, 1.5)])
    >>> rings, moved, dev, stuck = nudge_rings(sq, res, P, T, 0.25)
    >>> def shortest(R):
    ...     return round(float(np.hypot(*(np.roll(R, -1, axis=0) - R).T).min()), 3)
    >>> shortest(res.polygon.outer), shortest(rings[0]), bool(dev <= 0.25)
    (0.45, 0.865, True)
    """
    P = np.asarray(points, dtype=np.float64)
    E = unique_edges(triangles, len(P))
    L = np.hypot(*(P[E[:, 1]] - P[E[:, 0]]).T)
    target = 0.5 * float(L.max())
    on = np.zeros(len(P), dtype=bool)
    on[boundary_edges(triangles, len(P)).ravel()] = True
    order = np.argsort(L, kind="stable")
    pairs = ((int(x), int(y)) for a, b in E[order[L[order] < target]] if on[a] and on[b]
             for x, y in ((a, b), (b, a)))
    return move_ends(outline, res, P, pairs, lambda d: d < target, limit,
                     lambda *a: _move(*a, target, res.spacing, limit, res.polygon),
                     skip, most, sources)


def move_ends(outline: Polygon, res, points, pairs, wanted, limit: float, move, skip=(),
              most: int | None = None, sources: dict | None = None):
    """:func:`nudge_rings`'s loop: each (point, other end) of ``pairs`` with a movable
    point (not kept), not in ``skip``, fewer than ``most`` moved and ``wanted(their
    distance as moved so far)`` moved where ``move(InputRing, rings, ring index, index
    in it, other end)`` says ((ring, bound) or None).  Returns as :func:`nudge_rings`."""
    poly = res.polygon
    off, nR = poly.ring_offsets, poly.n_ring_vertices
    movable = np.zeros(len(points), dtype=bool)
    movable[:nR] = ~np.asarray(res.kept[:nR], dtype=bool)
    rings = [np.array(r, dtype=np.float64) for r in poly.rings]
    Q = np.array(points, dtype=np.float64)  # the points as moved so far
    moved, stuck, dev = [], [], 0.0
    sources = {} if sources is None else sources  # per ring, the input ring as band_bound sees it
    for x, y in pairs:
        if (not movable[x] or (x, y) in skip or not wanted(np.hypot(*(Q[x] - Q[y])))
                or len(moved) == most):
            continue
        ri = int(np.searchsorted(off, x, side="right") - 1)
        if ri not in sources:
            sources[ri] = InputRing(outline.rings[ri], limit)
        got = move(sources[ri], rings, ri, x - off[ri], Q[y])
        if got is not None:
            rings[ri], d = got
            Q[x] = rings[ri][x - off[ri]]
            moved.append((x, y))
            dev = max(dev, d)
        else:
            stuck.append((x, y))
    return rings, moved, dev, stuck


def _move(source, rings, ri, k, far, target, h, limit, poly):
    """(ring, bound) with ring point k of ring ``ri`` moved off ``far`` (see
    :func:`nudge_rings`), or None if no move lengthens what is short there."""
    ring = rings[ri]
    r = len(ring)
    prv, nxt = ring[k - 1], ring[(k + 1) % r]
    X0 = ring[k]
    X = candidate_positions(X0, far, h)
    e1, e2 = np.hypot(*(X - prv).T), np.hypot(*(nxt - X).T)
    cap = max(np.hypot(*(X0 - prv)), np.hypot(*(nxt - X0)), min(LONGEST * h, 2 * target))
    c, c0 = clearances(ring, k, X)  # the rest of the ring: no narrower feature made there
    score = np.minimum(np.minimum(np.minimum(e1, e2), np.hypot(*(X - far).T)), c)
    had = min(np.hypot(*(X0 - prv)), np.hypot(*(nxt - X0)), np.hypot(*(X0 - far)), c0, target)
    score = np.minimum(score, target)  # at half the longest edge, the nearest move
    ok = (score > had + GAIN * h) & (np.maximum(e1, e2) <= cap)
    if not ok.any():
        return None
    order = np.flatnonzero(ok)[np.lexsort((np.flatnonzero(ok), -score[ok]))][:CHECKED]
    return first_in_band(source, rings, ri, k, X, order, cap, float(STEPS.max()) * h, limit, poly)


def candidate_positions(X0, far, h: float, toward: bool = False) -> np.ndarray:
    """(len(TURNS) * len(STEPS), 2): the positions tried for a ring point at
    ``X0``, :data:`STEPS` spacings ``h`` in the :data:`TURNS` directions from
    straight away from ``far`` (``toward``: from straight towards it)."""
    d = far - X0 if toward else X0 - far
    turn = libm.arctan2(*d[::-1]) + np.asarray(TURNS)
    return (X0[None, None, :] + (STEPS * h)[None, :, None]
            * np.stack([np.cos(turn), np.sin(turn)], axis=1)[:, None, :]).reshape(-1, 2)


def clearances(ring, k: int, X):
    """((len(X),), float): the distance from each position X, and from ring point
    ``k``, to the ring edges that touch neither k nor its neighbours (inf if none)."""
    r = len(ring)
    others = np.setdiff1d(np.arange(r), [(k - 2) % r, (k - 1) % r, k, (k + 1) % r])
    if not len(others):
        return np.full(len(X), np.inf), np.inf
    A, B = ring[others], ring[(others + 1) % r]
    c0 = float(from_point(ring[k], A, B).min())
    return nearest(X, A, B), c0


def first_in_band(source, rings, ri: int, k: int, X, order, cap: float, step: float,
                  limit: float, poly: Polygon):
    """(ring, bound) with point k of ring ``ri`` at the first position ``X[order]``
    whose two ring edges and the input near it stay within ``limit`` both ways
    (:func:`band_bound`) and whose polygon is valid (:func:`valid_rings`); None if
    none.  ``source``: the input ring (:class:`InputRing`); ``cap``: the
    longest ring edge a position may make; ``step``: the farthest position."""
    ring = rings[ri]
    r = len(ring)
    prv, nxt = ring[k - 1], ring[(k + 1) % r]
    X0 = ring[k]
    both = max(np.hypot(*(X0 - prv)), np.hypot(*(nxt - X0)))
    band = _Band(source, ring, k, max(both, cap) + limit, X0, step)
    if not len(band.A):
        return None
    # the band check's first sample is the position itself (computed alike), its
    # distance to these edges at most that to the nearer ones it measures: farther
    # than the tolerance, it fails
    order = order[nearest(prv + (X[order] - prv), band.A, band.B) <= limit]
    e1, e2 = np.hypot(*(X - prv).T), np.hypot(*(nxt - X).T)
    for i in order:
        R = ring.copy()
        R[k] = X[i]
        d = band.bound(R, k, max(both, e1[i], e2[i]) + limit, limit)
        if d <= limit and valid_rings(poly, rings, ri, R):
            return R, d
    return None


def valid_rings(poly: Polygon, rings, ri: int, R) -> bool:
    """Whether the rings with ring ``ri`` replaced by ``R`` make a valid polygon with
    ``poly``'s constraints and as many vertices (no segment end spliced into a ring)."""
    try:
        new = poly.with_rings([R if i == ri else g for i, g in enumerate(rings)])
    except InvalidPolygonError:  # InvalidConstraintError too
        return False
    return len(new.vertices) == len(poly.vertices)


def relaxed(old: Polygon, new: Polygon, mesh, objective: str = "balanced", wide: bool = False):
    """``mesh`` (of ``old``) carried to ``new`` (the same vertices, some ring
    points moved): its boundary points at the same place along their edges,
    the points within :data:`RADIUS` target sizes of a moved vertex (with
    ``wide``, of any end of an edge shorter than half the longest too) relaxed
    again (:func:`uniform2d.optimize.moves.improve_kept`, the relocation's
    schedule); None if an interior point would be outside ``new``.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon, uniform_mesh
    >>> old = Polygon([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)])
    >>> m = uniform_mesh(old, 30)
    >>> new = Polygon([(0, 0), (1.1, 0), (2, 0), (2, 2), (0, 2)])
    >>> m2 = relaxed(old, new, m)
    >>> len(m2.points) == len(m.points), m2.polygon == new
    (True, True)
    """
    nV = len(old.vertices)
    sites = np.array(mesh.points[nV:], dtype=np.float64)
    _, boundary = classify_sites(old, sites, boundary_tol(old))
    edges = np.full(len(sites), -1, dtype=np.int64)
    V, C = new.vertices, new.constraint_edges
    for i, e, t in boundary:
        edges[i] = e
        sites[i] = V[C[e, 0]] + t * (V[C[e, 1]] - V[C[e, 0]])
    inner = edges < 0
    if not shapely.contains_xy(new.to_shapely(), sites[inner, 0], sites[inner, 1]).all():
        return None
    now = np.concatenate([V, sites])
    centres = [V[np.any(old.vertices != V, axis=1)]]
    if wide:
        E = unique_edges(mesh.triangles, len(mesh.points))
        L = np.hypot(*(mesh.points[E[:, 1]] - mesh.points[E[:, 0]]).T)
        centres.append(now[np.unique(E[L < 0.5 * L.max()])])
    C0 = np.concatenate(centres)
    near = cKDTree(C0).query(sites)[0] if len(C0) else np.full(len(sites), np.inf)
    h = mesh.info["h"]
    pts, tri, _ = improve_kept(new, sites, objective=objective, href=h, frozen=near > RADIUS * h,
                               edges=edges, **RELOCATE)
    ensure_valid(pts, tri, new, mesh.n_steiner, "uniform_mesh (ring nudge)")
    # INSERT's packing distance was of the old polygon: no certificate of the new one
    return Mesh(pts, tri, new, mesh.n_steiner, {k: v for k, v in mesh.info.items() if k != "d_n"})


def nudged(outline: Polygon, res, mesh, objective: str = "balanced"):
    """(res, mesh, points moved): a mesh of the resampled outline ``res``
    (:class:`uniform2d.outline.Resampled` of ``outline``) with ring points
    moved off its too-short edges where that is better (see the module
    notes); tried where the edge ratio is above ``SPLIT_RATIO``, also where
    the shortest ring edge forces a ratio above it (a shoreline's piers: the
    short ring edges have a movable end).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon, uniform_mesh
    >>> t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    >>> disk = Polygon(np.c_[np.cos(t), np.sin(t)])
    >>> m = uniform_mesh(disk, 300, resample=0.25)
    >>> m.info["resample"]["nudged"]              # ratio under 2: nothing to do
    0
    """
    return moved_stage(outline, res, mesh, objective, nudge_rings,
                       lambda q: q.edge_ratio <= SPLIT_RATIO, "off short")


def moved_stage(outline: Polygon, res, mesh, objective: str, mover, done, what: str):
    """(res, mesh, points moved): :func:`nudged`'s loop with ``mover`` (called as
    :func:`nudge_rings`) choosing the moves, until ``done(quality)``: every move
    at once, then one at a time, each kept where the relaxed mesh
    (:func:`relaxed`) is better (:func:`uniform2d.ring_split.better_mesh` with
    :data:`CV_SLACK` and :data:`ANGLE_SLACK`); ``what`` is for the log."""
    total, failed, sources = 0, set(), {}
    limit = res.tolerance * res.spacing
    for attempt in range(TRIES):
        q = quality(mesh.points, mesh.triangles)
        if done(q):
            break
        rings, moved, dev, stuck = mover(outline, res, mesh.points, mesh.triangles, limit,
                                         skip=failed, most=None if attempt == 0 else 1,
                                         sources=sources)
        failed.update(stuck)  # no move from there: not tried again
        if not moved:
            break
        res2 = dataclasses.replace(res, polygon=res.polygon.with_rings(rings),
                                   deviation=max(res.deviation, dev))
        # the two relaxations are independent: on two threads (the same meshes)
        made = thread_map(lambda w: relaxed(res.polygon, res2.polygon, mesh, objective, w),
                          (False, True))
        got = [(quality(m.points, m.triangles), m) for m in made if m is not None]
        got = [(q2, m) for q2, m in got if better_mesh(q2, q, CV_SLACK, ANGLE_SLACK)]
        if not got:
            if len(moved) == 1:  # not tried again
                failed.update(moved)
            continue
        q2, mesh2 = min(got, key=lambda g: g[0].edge_ratio)  # the first of a tie
        log.info("resampled outline: %d ring point(s) moved %s mesh edges, edge ratio "
                 "%.4g -> %.4g", len(moved), what, q.edge_ratio, q2.edge_ratio)
        res, total = res2, total + len(moved)
        mesh = Mesh(mesh2.points, mesh2.triangles, mesh2.polygon, mesh2.n_steiner,
                    {**mesh2.info, "after": quality_summary(q2)})
    return res, mesh, total
