"""The last pass of the optimiser: raising the worst angle with the objective held.

The descent (:mod:`uniform2d._kernel.relax`) weighs edge lengths and
perimeters only; where the shortest edge is a polygon edge, nothing in the
energy stops a neighbour from drifting into a needle triangle as long as the
extremes do not grow.  :func:`raise_worst_angle` moves the interior points of
the worst triangles (those on the boundary along their edge), one at a
time, each to the place (found by a compass
search) that maximises the smallest angle of its star, under the mesh's own
extremes: no edge of the star longer than the longest edge or shorter than the
shortest one, no triangle perimeter above the largest.  The moved points are
triangulated afresh (the exact constrained Delaunay triangulation, which has
the largest smallest angle of all triangulations of the points, so the mesh
stays the CDT of its points); the round is kept only if the worst angle rose
(or, equal, fewer triangles fall short of it, :func:`_gains`) and the three
extremes did not get worse; the pass stops at the first round that does not
gain.
"""

from __future__ import annotations

import numpy as np

from .. import libm
from ..geometry import polygon_edges
from ..polygon import Polygon
from ..triangulation import triangulate
from .boundary import target_size

__all__ = ["ANGLES_MAX", "ANGLE_FINE", "ANGLE_POOR", "HELD", "RATE", "ROUNDS", "SLACK", "WORST",
           "angle_attempt_wins", "angle_corners", "angles_and_gradients", "forced_angle", "min_angles",
           "raise_worst_angle", "worth_its_edges"]

#: Meshes of up to ANGLES_MAX points get the pass (each round triangulates the
#: whole mesh again).
ANGLES_MAX = 20000

#: Rounds of moves (each a fresh triangulation), at most.
ROUNDS = 20
#: Triangles whose smallest angle is within WORST degrees of the worst are
#: worked on in a round (their points, if no two share a triangle).
WORST = 1.0
#: Compass search: first step (fraction of the star's shortest spoke), steps.
STEP0 = 0.25
STEPS = 16
#: Gains (degrees) below MIN_GAIN are not worth a move or a round.
MIN_GAIN = 0.05
#: Meshes whose worst angle is ANGLE_FINE degrees or more are left as they are:
#: on the benchmark polygons (worst angles 39 to 49 degrees) the pass gained
#: less than 0.1 degree for some 15 % more time at n = 1000.
ANGLE_FINE = 35.0
#: A worst angle below ANGLE_POOR degrees is poor: the optimiser then takes
#: the mesh of the larger worst angle whatever its edges (20 degrees: the
#: quality bound of Ruppert's refinement and Triangle's ``-q`` default, below
#: which finite-element codes warn).
ANGLE_POOR = 20.0
#: Between ANGLE_POOR and ANGLE_FINE the angle attempt's mesh is taken only if
#: none of its edge ratio, longest edge and edge CV is worse by more than
#: SLACK (relative), or by more than RATE per degree its worst angle gains if
#: that is more: the rate the angle fit's loose rounds pay too
#: (:mod:`uniform2d.optimize.anglefit`, about 1 % a degree).  ``plate_zones`` of
#: bench_constrained at n = 1000: the attempt lifts the worst angle from 25.1
#: to 35.5 degrees for a 15 % larger edge ratio (Gmsh: 36.8 degrees, ratio 3.19
#: against our 2.33 and 2.68), and the fit then takes it to 38.5 with the edges
#: held; the (priced) loose rounds on the first mesh would reach 37.7 only
#: after 16 rounds, ten times the mesh's time, for the same edge ratio.
SLACK = 0.01
RATE = 0.02
#: The measures SLACK holds: the edge ratio and CV the angle goal is stated
#: with, and the longest edge.  Not the largest perimeter: on the bolt plate at
#: 8000 vertices the angle attempt lifts the worst angle from 30.6 to 37.2
#: degrees (Gmsh 36.2) with the ratio and longest edge the same, the CV lower,
#: the largest perimeter 7 % larger.
HELD = ("edge_ratio", "longest_edge", "cv_edge")


def angle_attempt_wins(first, other) -> bool:
    """Whether the optimiser's angle attempt (``other``, a
    :class:`~uniform2d.quality_result.Quality`) beats its first mesh
    (``first``): a larger worst angle, and either the first one's is poor
    (below ``ANGLE_POOR``) or its edges are worth it (:func:`worth_its_edges`).

    Examples
    --------
    >>> from types import SimpleNamespace as Q
    >>> edges = dict(edge_ratio=2.0, longest_edge=1.0, max_perimeter=3.0, cv_edge=0.1)
    >>> worse = dict(edge_ratio=2.3, longest_edge=1.1, max_perimeter=3.1, cv_edge=0.2)
    >>> angle_attempt_wins(Q(min_angle=12.0, **edges), Q(min_angle=29.0, **worse))
    True
    >>> angle_attempt_wins(Q(min_angle=25.0, **edges), Q(min_angle=29.0, **worse))
    False
    >>> angle_attempt_wins(Q(min_angle=25.0, **edges), Q(min_angle=29.0, **edges))
    True
    """
    if not other.min_angle > first.min_angle:
        return False
    return first.min_angle < ANGLE_POOR or worth_its_edges(first, other)


def worth_its_edges(first, other) -> bool:
    """Whether ``other``'s worst angle is larger than ``first``'s and none of
    its measures ``HELD`` is worse by more than ``SLACK``, or ``RATE`` per
    degree gained if that is more.

    Examples
    --------
    >>> from types import SimpleNamespace as Q
    >>> edges = dict(edge_ratio=2.0, longest_edge=1.0, cv_edge=0.1)
    >>> worth_its_edges(Q(min_angle=30.0, **edges),
    ...                 Q(min_angle=35.0, edge_ratio=2.19, longest_edge=1.09, cv_edge=0.109))
    True
    >>> worth_its_edges(Q(min_angle=30.0, **edges),
    ...                 Q(min_angle=31.0, edge_ratio=2.19, longest_edge=1.09, cv_edge=0.109))
    False
    >>> worth_its_edges(Q(min_angle=30.0, **edges),
    ...                 Q(min_angle=30.1, edge_ratio=2.01, longest_edge=1.005, cv_edge=0.1))
    True
    """
    gain = other.min_angle - first.min_angle
    if not gain > 0:
        return False
    cap = 1.0 + max(SLACK, RATE * gain)
    return all(getattr(other, f) <= cap * getattr(first, f) for f in HELD)


def min_angles(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """The smallest angle of every triangle, in degrees, shape (M,).

    Examples
    --------
    >>> import numpy as np
    >>> min_angles(np.array([[0.0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2]])).round(6)
    array([45.])
    """
    q = points[triangles]
    a = np.linalg.norm(q[:, 1] - q[:, 2], axis=1)
    b = np.linalg.norm(q[:, 2] - q[:, 0], axis=1)
    c = np.linalg.norm(q[:, 0] - q[:, 1], axis=1)
    cross = np.abs((q[:, 1, 0] - q[:, 0, 0]) * (q[:, 2, 1] - q[:, 0, 1])
                   - (q[:, 1, 1] - q[:, 0, 1]) * (q[:, 2, 0] - q[:, 0, 0]))
    # the smallest angle is opposite the shortest side: sin = cross / (product of the others)
    s = np.minimum(np.minimum(a, b), c)
    prod = a * b * c / s
    return np.degrees(libm.arcsin(np.clip(cross / prod, 0.0, 1.0)))


def _extremes(points, triangles):
    q = points[triangles]
    L = np.linalg.norm(q - q[:, [1, 2, 0]], axis=2)
    return L.max(), L.min(), L.sum(axis=1).max()


def _star_scores(P, ring, lmax, lmin, pmax):
    """Smallest angle (degrees) of the star with its centre at each of the
    places ``P`` (c, 2), the star given by its opposite edges ``ring`` (k, 2, 2)
    in CCW order; -inf where a triangle turns or an extreme is passed."""
    a, b = ring[None, :, 0], ring[None, :, 1]
    x, y = P[:, None, 0], P[:, None, 1]
    cross = (a[..., 0] - x) * (b[..., 1] - y) - (a[..., 1] - y) * (b[..., 0] - x)
    la = np.hypot(a[..., 0] - x, a[..., 1] - y)
    lb = np.hypot(b[..., 0] - x, b[..., 1] - y)
    lab = np.hypot(*(ring[:, 1] - ring[:, 0]).T)[None, :]
    s = np.minimum(np.minimum(la, lb), lab)
    with np.errstate(divide="ignore", invalid="ignore"):
        ang = np.degrees(libm.arcsin(np.clip(cross * s / (la * lb * lab), 0.0, 1.0))).min(axis=1)
    bad = ((cross <= 0.0).any(axis=1) | (np.maximum(la, lb).max(axis=1) > lmax)
           | (np.minimum(la, lb).min(axis=1) < lmin) | ((la + lb + lab).max(axis=1) > pmax))
    return np.where(bad, -np.inf, ang)


_COMPASS = np.array([[1, 0], [0, 1], [-1, 0], [0, -1], [0.7071, 0.7071], [-0.7071, 0.7071],
                     [-0.7071, -0.7071], [0.7071, -0.7071]])


def _best_place(p0, ring, lmax, lmin, pmax, edge=None):
    """(place, its score, p0's score): compass search for the place of the
    star's centre with the largest smallest angle, from p0; with ``edge`` =
    (start, vector) of the polygon edge p0 lies on, along it only (placed as
    ``start + t * vector``, as the kernel places a sliding point, so it stays
    on the edge within rounding)."""
    best = p0.copy()
    score = first = float(_star_scores(p0[None], ring, lmax, lmin, pmax)[0])
    step = STEP0 * float(np.hypot(*(ring[:, 0] - p0).T).min())
    if edge is not None:
        a, d = edge
        dd = float(d @ d)
        t = float((p0 - a) @ d) / dd
        step /= np.sqrt(dd)
    for _ in range(STEPS):
        if edge is None:
            cand = best + step * _COMPASS
        else:
            cand = a + np.array([[t + step], [t - step]]) * d
        scores = _star_scores(cand, ring, lmax, lmin, pmax)
        i = int(np.argmax(scores))
        if scores[i] > score:
            best, score = cand[i], float(scores[i])
            if edge is not None:
                t += step if i == 0 else -step
        else:
            step *= 0.5
    return best, score, first


def _round(points, triangles, ang, movable, along, lmax, lmin, pmax):
    """The points after one round of moves (None if nothing moved); ``along``:
    the (start, vector) of the edge each sliding point lies on (None: free);
    ``ang`` the triangles' smallest angles."""
    worst = ang.min()
    picked = np.flatnonzero(ang <= worst + WORST)
    picked = picked[np.lexsort((picked, ang[picked]))]
    busy = np.zeros(len(points), bool)
    out = points.copy()
    moved = False
    corner = np.argsort(triangles.ravel(), kind="stable")  # the stars, once a round
    start = np.searchsorted(triangles.ravel()[corner], np.arange(len(points) + 1))
    for t in picked:
        best = None  # (gain, vertex, place, star) of the triangle's best move
        for v in triangles[t]:
            if not movable[v] or busy[v]:
                continue
            at = corner[start[v]:start[v + 1]]
            rows, cols = at // 3, at % 3
            star = triangles[rows]
            if busy[star].any():
                continue
            k = np.arange(len(rows))
            ring = np.stack([out[star[k, (cols + 1) % 3]], out[star[k, (cols + 2) % 3]]], axis=1)
            place, score, before = _best_place(out[v], ring, lmax, lmin, pmax, along[v])
            if score > before + MIN_GAIN and (best is None or score - before > best[0]):
                best = (score - before, v, place, star)
        if best is not None:
            out[best[1]] = best[2]
            busy[best[3].ravel()] = True
            moved = True
    return out if moved else None


def raise_worst_angle(polygon: Polygon, points: np.ndarray, triangles: np.ndarray,
                      edges: np.ndarray):
    """(points, triangles, rounds kept): the mesh after the pass of the module
    docstring.  ``points`` are P's vertices then the sites, ``edges`` the polygon
    edge of each site (-1 inside; a site on an edge slides along it).  Inputs are not modified.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> pts, tri = triangulate(sq, [(0.2, 0.3)])
    >>> p2, t2, kept = raise_worst_angle(sq, pts, tri, np.array([-1]))
    >>> bool(min_angles(p2, t2).min() >= min_angles(pts, tri).min())
    True
    """
    nV = len(polygon.vertices)
    edges = np.asarray(edges)
    movable = np.zeros(len(points), bool)
    movable[nV:] = True
    a, d, _ = polygon_edges(polygon, constraints=True)
    along = [None] * len(points)
    for i in np.flatnonzero(edges >= 0):
        along[nV + i] = (a[edges[i]], d[edges[i]])
    ang = min_angles(points, triangles)
    if ang.min() >= ANGLE_FINE:
        return points, triangles, 0
    lmax, lmin, pmax = _extremes(points, triangles)
    kept = 0
    for _ in range(ROUNDS):
        moved = _round(points, triangles, ang, movable, along, lmax, lmin, pmax)
        if moved is None:
            break
        got = _better(polygon, moved, edges, ang, lmax, lmin, pmax)
        if got is None:
            break
        points, triangles, ang = got
        kept += 1
    return points, triangles, kept


def _better(polygon, moved, edges, ang0, lmax, lmin, pmax):
    """(points, triangles, angles): the exact constrained Delaunay triangulation
    of a round's moved points, or None if it does not gain (:func:`_gains`)
    within the extremes (a flip can lengthen an edge).  ``ang0``: the
    smallest angles before the round."""
    nV = len(polygon.vertices)
    P2, T2 = triangulate(polygon, moved[nV:], edges)
    ang = min_angles(P2, T2)
    L2, l2, p2 = _extremes(P2, T2)
    if L2 <= lmax and l2 >= lmin and p2 <= pmax and _gains(ang0, ang):
        return P2, T2, ang
    return None


def _gains(ang0, ang) -> bool:
    """Whether smallest angles ``ang`` beat ``ang0``: a larger worst angle, or
    the same with less of a shortfall below ``WORST`` degrees above it (the
    worst triangles of a symmetric mesh are mended over several rounds)."""
    w0, w = ang0.min(), ang.min()
    if w < w0:
        return False
    if w >= w0 + MIN_GAIN:
        return True
    top = w0 + WORST
    return np.maximum(top - ang, 0.0).sum() < np.maximum(top - ang0, 0.0).sum() - MIN_GAIN


def angles_and_gradients(q):
    """The three angles (degrees) of triangles ``q`` (m, 3, 2), shape (3m,), and
    their gradients by the corners, (3m, 3, 2) with the corner order of
    :func:`angle_corners`."""
    vals, grads = [], []
    for k in range(3):
        u = q[:, (k + 1) % 3] - q[:, k]
        w = q[:, (k + 2) % 3] - q[:, k]
        vals.append(libm.arctan2(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0], (u * w).sum(axis=1)))
        # the angle is arg(w) - arg(u); d arg(v) / dv = perp(v) / |v|^2
        gw = np.stack([-w[:, 1], w[:, 0]], axis=1) / (w * w).sum(axis=1)[:, None]
        gu = -np.stack([-u[:, 1], u[:, 0]], axis=1) / (u * u).sum(axis=1)[:, None]
        grads.append(np.stack([-(gu + gw), gu, gw], axis=1))
    return np.degrees(np.concatenate(vals)), np.degrees(np.concatenate(grads))


def angle_corners(T):
    """The points of each angle of :func:`angles_and_gradients`, (3m, 3)."""
    return np.concatenate([T[:, [k, (k + 1) % 3, (k + 2) % 3]] for k in range(3)])


def forced_angle(polygon: Polygon, points: np.ndarray, triangles: np.ndarray) -> float:
    """The worst angle a mesh of the target size h is forced to at its worst
    triangle, in degrees (infinite if none): where that triangle has a corner
    at a vertex of P, the angle opposite the shortest piece of P's edges and
    segments at that vertex, of length l, in the isosceles triangle whose
    other sides grade from l to h in one row, (l + h) / 2.  Next to a piece
    much shorter than h (a small hole) a mesh of that size, ours or a
    frontal mesher's, must grade that fast; the loose rounds
    (:func:`~uniform2d.optimize.anglefit.loosen_worst_angle`) do not trade
    edges for an angle beyond it.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> from uniform2d.optimize.boundary import target_size
    >>> pts, tri = triangulate(sq, [(0.5, 0.5)])
    >>> h = target_size(sq, 1)  # 0.84
    >>> bool(np.isclose(forced_angle(sq, pts, tri), np.degrees(2 * np.arcsin(1 / (1 + h)))))
    True
    """
    nV = len(polygon.vertices)
    corners = triangles[int(np.argmin(min_angles(points, triangles)))]
    pieces = polygon.constraint_edges
    at = np.isin(pieces, corners[corners < nV]).any(axis=1)
    if not at.any():
        return float("inf")
    _, _, L = polygon_edges(polygon, constraints=True)
    piece = float(L[at].min())
    h = target_size(polygon, len(points) - nV)
    return float(np.degrees(libm.arcsin(np.array([piece / (piece + h)]))[0])) * 2.0
