"""Whole ring edges that set a resampled mesh's longest edge, halved for a second mesh.

A ring edge between two points the resampling keeps (corners, or a stretch of
outline one chord within the tolerance) is a polygon edge for the mesher, which
splits it into ``round(L / (c h))`` pieces for its boundary spacing c (1, 0.95
or 1.05): an edge of 1.4 to 1.5 spacings is left whole or halved as the spacing
the optimiser picks falls, and whole it can be the mesh's longest edge by
itself.  :func:`edges_to_halve` names the ring edges that are whole mesh edges
longer than every other mesh edge and whose halves are no shorter than the
mesh's shortest edge (halving them lowers the longest edge and leaves the
shortest); :func:`halve_edges` inserts their midpoints as boundary points.  A
midpoint lies on the ring edge, so the rings are the same point set: the
deviation from the outline, the kept vertices and the corners are unchanged,
and the new points count in n like every boundary point the resampling placed.
:func:`uniform2d.uniform_mesh` with ``resample`` meshes again with them halved
where its first mesh's ratio is above :data:`SPLIT_RATIO` and keeps the mesh
with the lower edge ratio (its CV at most :data:`CV_SLACK` higher, its worst
angle at most :data:`ANGLE_SLACK` lower).

A whole ring edge of 1.3 to 1.45 spacings is also a triangle's long side: with
two sides near the spacing on it, the triangle's worst angle is near 28
degrees (Triangle's square with a circular hole at n = 2000: 0.73, 0.96 and
1.42 spacings, where Gmsh reaches 37.6 on the same polygon).  Where a mesh's
worst angle is below :data:`ANGLE_BELOW` and its worst triangle has such a
side, :func:`edges_for_angle` names every whole ring edge at least
:data:`SPLIT_LONG` mean edges long, and the mesh made with them halved is kept
if :func:`better_angle` says so.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .geometry import unique_edges
from .optimize.angles import ANGLE_FINE, min_angles
from .polygon import Polygon

__all__ = ["ANGLE_BELOW", "ANGLE_SLACK", "CV_SLACK", "HALF_REACH", "SPLIT_LONG", "SPLIT_RATIO", "better_angle",
           "better_mesh", "edges_for_angle", "edges_to_halve", "halve_edges"]

#: A second mesh is tried where the first has an edge ratio above this, and the
#: mesh's mean edge over its shortest ring edge (a bound on the ratio) is at most it.
SPLIT_RATIO = 2.0
#: The second mesh is kept if its edge ratio is lower and its edge CV at most this
#: fraction higher than the first's.
CV_SLACK = 0.05
#: ... and its worst angle at most this fraction lower (for every second mesh
#: the resampled path makes: a lower ratio is no gain with a flat triangle).
ANGLE_SLACK = 0.1
#: Whole ring edges are halved for the worst angle where it is below this
#: (degrees; :data:`uniform2d.optimize.angles.ANGLE_FINE`: a mesh above it is
#: left as it is elsewhere too).
ANGLE_BELOW = ANGLE_FINE
#: ... those at least this many mean edges long (a side of 1.25 mean edges on
#: a triangle whose other two are near the mean has angles under 39 degrees;
#: halved, its halves are 0.62 mean edges or more).
SPLIT_LONG = 1.25
#: ... unless their shortest half times the edge ratio (or SPLIT_RATIO) is
#: under this fraction of the longest other edge: that one need not stay (the
#: mesh is made again), so a little short is still tried.
HALF_REACH = 0.95


def better_mesh(q_new, q_old, cv_slack: float = CV_SLACK, angle_slack: float | None = None) -> bool:
    """Whether a second mesh of a resampled outline (quality ``q_new``,
    :class:`uniform2d.quality_result.Quality`) replaces the first (``q_old``):
    its edge ratio lower, its edge CV at most ``cv_slack`` higher and its worst
    angle at most ``angle_slack`` lower (relative; :data:`ANGLE_SLACK` if None)."""
    angle_slack = ANGLE_SLACK if angle_slack is None else angle_slack
    return (q_new.edge_ratio < q_old.edge_ratio and q_new.cv_edge <= (1 + cv_slack) * q_old.cv_edge
            and q_new.min_angle >= (1 - angle_slack) * q_old.min_angle)


def better_angle(q_new, q_old, cv_slack: float = CV_SLACK) -> bool:
    """Whether a mesh with whole ring edges halved for the angle (quality
    ``q_new``) replaces the first (``q_old``): its worst angle larger, its edge
    CV at most ``cv_slack`` higher and its edge ratio no higher than the first's
    or than :data:`SPLIT_RATIO` (a ratio of 2 or less stays so: issue 35's goal).

    Examples
    --------
    >>> from types import SimpleNamespace as Q
    >>> better_angle(Q(min_angle=35.5, cv_edge=0.071, edge_ratio=1.74),
    ...              Q(min_angle=28.2, cv_edge=0.073, edge_ratio=1.99))
    True
    >>> better_angle(Q(min_angle=32.4, cv_edge=0.071, edge_ratio=2.04),
    ...              Q(min_angle=28.2, cv_edge=0.073, edge_ratio=1.99))
    False
    """
    return (q_new.min_angle > q_old.min_angle and q_new.cv_edge <= (1 + cv_slack) * q_old.cv_edge
            and q_new.edge_ratio <= max(q_old.edge_ratio, SPLIT_RATIO))


def edges_for_angle(polygon: Polygon, points, triangles) -> np.ndarray:
    """(q, 2) int64: the ring edges of ``polygon`` (vertex pairs, smaller first)
    that are whole mesh edges at least :data:`SPLIT_LONG` mean edges long, if
    the mesh's worst angle is below :data:`ANGLE_BELOW`, its worst triangle
    has one of them as a side and no other ring edge (a corner's one triangle
    is left), and their shortest half times the mesh's edge
    ratio (or :data:`SPLIT_RATIO` if that is higher) is at least
    :data:`HALF_REACH` of the longest other edge (else none).

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> from uniform2d.triangulation import triangulate
    >>> rect = Polygon([(0, 0), (1.4, 0), (1.4, 0.7), (0, 0.7)])
    >>> P, T = triangulate(rect, [(0.7, 0.3)])   # the worst angle, 23 degrees, on 0-1
    >>> edges_for_angle(rect, P, T).tolist()      # both long sides (mean edge 0.92)
    [[0, 1], [2, 3]]
    >>> P, T = triangulate(rect, [(0.7, 0.35), (0.35, 0.35), (1.05, 0.35)])
    >>> edges_for_angle(rect, P, T).tolist()      # worst angle 45: none
    []
    """
    P = np.asarray(points, dtype=np.float64)
    T = np.asarray(triangles)
    none = np.empty((0, 2), dtype=np.int64)
    angles = min_angles(P, T)
    worst = int(np.argmin(angles))
    if not angles[worst] < ANGLE_BELOW:
        return none
    E, L, whole, ring_keys = _mesh_edges(polygon, P, T)
    n = len(P)
    pick = whole & (L >= SPLIT_LONG * L.mean())
    t = T[worst]
    sides = np.sort(np.array([[t[1], t[2]], [t[2], t[0]], [t[0], t[1]]], dtype=np.int64), axis=1)
    keys = sides[:, 0] * n + sides[:, 1]
    if not np.isin(keys, E[pick, 0] * n + E[pick, 1]).any():
        return none
    # two ring edges: a corner's one triangle, its points all on the ring; its
    # smallest angle the outline's own or across a chord of the corner (the NYC
    # shorelines' tips, Australia's chord at 31 degrees: second meshes worse)
    if np.isin(keys, ring_keys).sum() >= 2:
        return none
    # halves that short would likely set an edge ratio above the mesh's (or 2),
    # which better_angle does not keep: not meshed (India at n = 2000, 0.87 of
    # the other edges' longest: 0.5 s for nothing; the square with a hole at
    # n = 1500, 0.99: kept, 28.4 -> 30.9 degrees, the ratio still under 2)
    if 0.5 * L[pick].min() * max(L.max() / L.min(), SPLIT_RATIO) < HALF_REACH * L[~pick].max():
        return none
    return E[pick].astype(np.int64)


def edges_to_halve(polygon: Polygon, points, triangles) -> np.ndarray:
    """(q, 2) int64: the ring edges of ``polygon`` (vertex pairs, smaller first)
    that are whole edges of the mesh, longer than every other mesh edge, with
    halves no shorter than the mesh's shortest edge.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.triangulation import triangulate
    >>> sq = Polygon([(0, 0), (1.5, 0), (1.5, 1.5), (0, 1.5)])
    >>> P, T = triangulate(sq, [(0.75, 0.75), (0.75, 0.0)])   # one on the side 0-1
    >>> edges_to_halve(sq, P, T).tolist()     # the three sides left whole
    [[0, 3], [1, 2], [2, 3]]
    """
    E, L, whole, _ = _mesh_edges(polygon, np.asarray(points, dtype=np.float64), triangles)
    if not whole.any() or whole.all():
        return np.empty((0, 2), dtype=np.int64)
    pick = whole & (L > L[~whole].max()) & (0.5 * L >= L.min())
    return E[pick]


def _mesh_edges(polygon: Polygon, P, T) -> tuple:
    """(E, L, whole, ring keys): the mesh's edges (smaller vertex first), their
    lengths, which of them are whole ring edges of ``polygon``, and the ring
    edges as keys ``a * len(P) + b`` (a < b)."""
    E = unique_edges(T, len(P))
    L = np.hypot(*(P[E[:, 1]] - P[E[:, 0]]).T)
    ring = np.sort(polygon.edges, axis=1)
    ring_keys = ring[:, 0] * len(P) + ring[:, 1]
    return E, L, np.isin(E[:, 0] * len(P) + E[:, 1], ring_keys), ring_keys


def halve_edges(res, pairs):
    """The resampled outline ``res`` (:class:`uniform2d.outline.Resampled`) with
    the midpoints of its ring edges ``pairs`` ((q, 2) vertex indices) inserted
    as boundary points (not kept input vertices): the same rings as point sets.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.outline import resample_polygon
    >>> t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    >>> r, _ = resample_polygon(Polygon(np.c_[np.cos(t), np.sin(t)]), 100, tolerance=0.25)
    >>> r2 = halve_edges(r, np.array([[0, 1]]))
    >>> r2.n_boundary - r.n_boundary, r2.deviation == r.deviation
    (1, True)
    """
    q = res.polygon
    off = q.ring_offsets
    pairs = {(int(a), int(b)) for a, b in np.sort(np.asarray(pairs).reshape(-1, 2), axis=1)}
    by_ring, kept = [], []
    for r, ring in enumerate(q.rings):
        k, pts = len(ring), []
        for i in range(k):
            a, b = off[r] + i, off[r] + (i + 1) % k
            pts.append(ring[i])
            kept.append(res.kept[a])
            if (min(a, b), max(a, b)) in pairs:
                pts.append(0.5 * (ring[i] + ring[(i + 1) % k]))
                kept.append(False)
        by_ring.append(np.array(pts))
    poly = q.with_rings(by_ring)
    kept = np.concatenate([np.array(kept, dtype=bool), res.kept[q.n_ring_vertices:]])
    return dataclasses.replace(res, polygon=poly, kept=kept)
