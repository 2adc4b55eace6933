"""DXF curves as polylines: CIRCLE, ARC and polyline bulges, and chains of pieces.

CAD draws bolt holes as ``CIRCLE`` entities, fillets and slots as ``ARC``
entities or as arc segments (*bulges*) of polylines.  uniform2d meshes
polygons, so every curve becomes a polyline through points on it.

The rule: a circular arc of radius r turning through an angle theta is cut into
``k = ceil(theta / step)`` equal pieces, with ``step = 2 acos(1 - tol)``: the
sagitta of every piece (the largest distance between the arc and its chord) is
at most ``tol * r``.  With the default :data:`CHORD_TOL` = 0.01 a full circle
has 23 pieces of 15.7 degrees (its area is 1.2 % below the circle's) and a
quarter-circle fillet 6.  Angles that are multiples of 90 degrees give exact
points (so an arc meets a line drawn to its quadrant point exactly).

Pieces that CAD stores separately (``LINE`` and ``ARC`` entities, open
polylines) join into a chain where exactly two of them meet: an ARC's ends are
computed from its centre, radius and angles, so ends within
:data:`JOIN_TOL` of the drawing's size count as one point, the exactly stored
one kept.  :func:`chains` returns the closed chains (rings) and the pieces that
close nothing.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "CHORD_TOL",
    "JOIN_TOL",
    "arc_points",
    "arc_polyline",
    "bulge_polyline",
    "chains",
    "circle_ring",
    "pieces_for",
    "to_wcs",
]

#: Largest sagitta of a piece of a curve, as a fraction of its radius.
CHORD_TOL = 0.01
#: Piece ends closer than this fraction of the drawing's size are joined.
JOIN_TOL = 1e-9


def pieces_for(angle: float, tol: float = CHORD_TOL) -> int:
    """Pieces of an arc turning ``angle`` radians so every sagitta is <= ``tol`` x radius.

    >>> pieces_for(2 * math.pi), pieces_for(math.pi / 2), pieces_for(1e-6)
    (23, 6, 1)
    """
    if not 0.0 < tol < 1.0:
        raise ValueError(f"the chord tolerance must be between 0 and 1 (of the radius), got {tol}")
    step = 2.0 * math.acos(1.0 - tol)
    return max(1, math.ceil(abs(angle) / step - 1e-12))


def _unit(deg: float) -> tuple[float, float]:
    """(cos, sin) of ``deg`` degrees, exact at multiples of 90."""
    q, r = divmod(deg, 90.0)
    if r == 0.0:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(q) % 4]
    a = math.radians(deg)
    return math.cos(a), math.sin(a)


def arc_points(center, radius: float, start_deg: float, sweep_deg: float,
               tol: float = CHORD_TOL) -> np.ndarray:
    """Points of the arc from ``start_deg`` turning ``sweep_deg`` (counter-clockwise
    if positive), both ends included: (k + 1, 2) float64.

    >>> arc_points((0, 0), 2.0, 0.0, 90.0)[[0, -1]].tolist()
    [[2.0, 0.0], [0.0, 2.0]]
    """
    k = pieces_for(math.radians(sweep_deg), tol)
    cx, cy = float(center[0]), float(center[1])
    out = np.empty((k + 1, 2), dtype=np.float64)
    for j in range(k + 1):
        c, s = _unit(start_deg + sweep_deg * j / k)
        out[j] = (cx + radius * c, cy + radius * s)
    return out


def to_wcs(entity, xy: np.ndarray, elevation: float = 0.0) -> np.ndarray:
    """Points in the entity's object coordinate system (OCS) to world (x, y)."""
    ocs = entity.ocs()
    if not ocs.transform:
        return xy
    pts = ocs.points_to_wcs([(float(x), float(y), elevation) for x, y in xy])
    return np.array([(p.x, p.y) for p in pts], dtype=np.float64).reshape(-1, 2)


def circle_ring(entity, tol: float = CHORD_TOL) -> np.ndarray:
    """A CIRCLE entity as a ring (k, 2) (not closed), in world coordinates."""
    c, r = entity.dxf.center, float(entity.dxf.radius)
    return to_wcs(entity, arc_points((c.x, c.y), r, 0.0, 360.0, tol)[:-1], float(c.z))


def arc_polyline(entity, tol: float = CHORD_TOL) -> np.ndarray:
    """An ARC entity as an open polyline (k + 1, 2), in world coordinates."""
    c, r = entity.dxf.center, float(entity.dxf.radius)
    a0, a1 = float(entity.dxf.start_angle), float(entity.dxf.end_angle)
    sweep = (a1 - a0) % 360.0 or 360.0
    return to_wcs(entity, arc_points((c.x, c.y), r, a0, sweep, tol), float(c.z))


def _bulge_arc(p1, p2, bulge: float, tol: float) -> np.ndarray:
    """Inner points of the arc from p1 to p2 with ``bulge`` = tan(angle / 4)
    (positive: counter-clockwise)."""
    d = p2 - p1
    c = float(np.hypot(*d))
    if c == 0.0:
        return np.empty((0, 2))
    theta = 4.0 * math.atan(bulge)
    normal = np.array([-d[1], d[0]]) / c
    center = (p1 + p2) / 2.0 + normal * (c / 2.0) * (1.0 - bulge * bulge) / (2.0 * bulge)
    radius = c / (2.0 * abs(math.sin(theta / 2.0)))
    start = math.degrees(math.atan2(p1[1] - center[1], p1[0] - center[0]))
    return arc_points(center, radius, start, math.degrees(theta), tol)[1:-1]


def bulge_polyline(xyb, closed: bool, tol: float = CHORD_TOL) -> np.ndarray:
    """Polyline vertices (x, y, bulge) in its plane with every bulged segment
    replaced by arc points; (k, 2), not closed for a closed polyline.

    >>> p = bulge_polyline([(0, 0, 1.0), (2, 0, 0.0)], closed=True)
    >>> len(p), p[[0, -1]].tolist(), float(p[:, 1].min())
    (13, [[0.0, 0.0], [2.0, 0.0]], -1.0)
    """
    v = np.asarray(xyb, dtype=np.float64).reshape(-1, 3)
    out = []
    n = len(v)
    for i in range(n):
        out.append(v[i, :2][None])
        last = i == n - 1
        if v[i, 2] != 0.0 and (closed or not last):
            out.append(_bulge_arc(v[i, :2], v[(i + 1) % n, :2], float(v[i, 2]), tol))
    return np.vstack(out)


def _nodes(pieces, exact) -> tuple[np.ndarray, np.ndarray]:
    """(node of each piece end (m, 2), node coordinates): ends within the join
    tolerance share a node, placed at an exactly stored end where there is one."""
    ends = np.array([[p[0], p[-1]] for p in pieces], dtype=np.float64).reshape(-1, 2)
    size = float(np.ptp(np.vstack(pieces), axis=0).max())
    tol = JOIN_TOL * size
    node = np.full(len(ends), -1)
    coords = []
    for i in np.argsort(~np.repeat(np.asarray(exact, bool), 2), kind="stable"):  # exact first
        if coords:
            dist = np.abs(np.asarray(coords) - ends[i]).max(axis=1)
            j = int(np.argmin(dist))
            if dist[j] <= tol:
                node[i] = j
                continue
        node[i] = len(coords)
        coords.append(ends[i])
    return node.reshape(-1, 2), np.asarray(coords, dtype=np.float64).reshape(-1, 2)


def chains(pieces, exact):
    """Join open pieces into rings where they close.

    Parameters
    ----------
    pieces : list of ndarray, each (k_i, 2), k_i >= 2
        Open polylines (lines, arcs, open polylines), in file order.
    exact : list of bool
        Whether each piece's ends are stored exactly (False for an ARC).

    Returns
    -------
    rings : list of (list of int, ndarray (k, 2))
        The pieces of each closed chain (two or more pieces meeting two by two
        at their ends) and its ring (not closed).
    rest : list of (int, ndarray (k_i, 2))
        Every other piece, its ends snapped to the nodes they share.

    >>> sq = [np.array([[0., 0], [1, 0]]), np.array([[1., 0], [1, 1]]),
    ...       np.array([[0., 1], [1, 1]]), np.array([[0., 0], [0, 1]])]
    >>> rings, rest = chains(sq, [True] * 4)
    >>> rings[0][0], rings[0][1].tolist(), rest
    ([0, 1, 2, 3], [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], [])
    """
    if not pieces:
        return [], []
    node, coords = _nodes(pieces, exact)
    snapped = []
    for p, (a, b) in zip(pieces, node):
        q = np.array(p, dtype=np.float64)
        q[0], q[-1] = coords[a], coords[b]
        snapped.append(q)
    at: dict[int, list[int]] = {}
    for i, (a, b) in enumerate(node.tolist()):
        for v in {a, b}:
            at.setdefault(v, []).append(i)
    used, rings = set(), []
    for i in range(len(pieces)):
        if i in used or node[i, 0] == node[i, 1]:
            continue
        order, walk, v = [i], [snapped[i]], int(node[i, 1])
        while v != node[i, 0] and len(at[v]) == 2:
            j = at[v][0] if at[v][1] == order[-1] else at[v][1]
            if j in order:
                break
            forward = node[j, 0] == v
            walk.append(snapped[j] if forward else snapped[j][::-1])
            order.append(j)
            v = int(node[j, 1] if forward else node[j, 0])
        if v == node[i, 0] and len(order) > 1 and len(at[v]) == 2:
            used.update(order)
            rings.append((order, np.vstack([w[:-1] for w in walk])))
    rest = [(i, snapped[i]) for i in range(len(pieces)) if i not in used]
    return rings, rest
