"""The first layer of a start: a row of points along every edge, after fans at the corners.

:func:`boundary_rows` puts one point above the middle of every boundary piece
(at the apex of the equilateral triangle on it), after the corners' fans
(:func:`corner_fans`), keeping those clear of the constraints
(:func:`keep_clear`) and of the points before them.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .. import libm
from .._kernel.distance import to_segments
from ..geometry import polygon_edges
from ..polygon import Polygon

__all__ = ["boundary_rows", "corner_fans", "keep_clear", "FAN_CAP"]

#: Corner fan points sit at most FAN_CAP target sizes from their corner.
FAN_CAP = 1.5


def boundary_rows(polygon: Polygon, m: np.ndarray, h: float, depth: int = 1) -> np.ndarray:
    """One row of points along every polygon edge and segment piece (m[e] pieces
    of each of :attr:`~uniform2d.Polygon.constraint_edges`): above the middle of
    each piece, at the apex of the equilateral triangle on it, inside P for a
    ring edge and on both sides for a segment piece (P is on both), after the
    corners' fans (:func:`corner_fans`), keeping only those clear of the
    constraint edges and fixed points and of the points before them (the fans
    win at corners).  ``depth`` > 1: as many rows, each staggered by half a
    piece from the one below and the equilateral height above it (a strip of
    near-equilateral triangles along every edge), kept after the first."""
    a, d, L = polygon_edges(polygon, constraints=True)
    rows, gaps = corner_fans(polygon, L / m, h)
    for layer in range(1, depth + 1):
        rows_, gaps_ = _layer(polygon, a, d, L, m, layer)
        rows.append(rows_)
        gaps.append(gaps_)
    R, G = np.concatenate(rows), np.concatenate(gaps)
    shp = polygon.to_shapely()
    ok = shapely.contains_xy(shp, R[:, 0], R[:, 1])
    a, b = keep_clear(polygon)
    ok &= to_segments(R, a, b, 0.6 * G.max()) >= 0.6 * G
    R, G = R[ok], G[ok]
    keep = []
    # every point's neighbours in one query (the same sets as one query a
    # point: the greedy pass below reads them in Python alone)
    near = cKDTree(R).query_ball_point(R, 0.75 * G)
    taken = np.zeros(len(R), bool)
    for i in range(len(R)):  # greedy, in ring order: the first of two crowded points stays
        if taken[i]:
            continue
        keep.append(i)
        taken[near[i]] = True
    return R[keep]


def _layer(polygon: Polygon, a, d, L, m, layer: int):
    """(points, their pieces' lengths) of row ``layer`` of :func:`boundary_rows`:
    edge by edge (a segment piece's side 1 then side -1), each edge's points in
    order along it.  All edges at once (a few arrays, not a dozen small ones
    per edge, which held the GIL while the starts' rows are made on several
    threads), each point's coordinates by the operations of one edge's."""
    g = L / m
    nrm = np.stack([-d[:, 1], d[:, 0]], axis=1) / L[:, None]  # left normal: into P on every ring
    count = m if layer % 2 else m - 1
    sides = np.where(np.arange(len(L)) < len(polygon.edges), 1, 2)
    edge = np.repeat(np.arange(len(L)), sides)  # the blocks of points: an edge's side
    side = np.ones(len(edge))
    side[1:][edge[1:] == edge[:-1]] = -1.0
    size = count[edge]
    first = np.cumsum(size) - size
    block = np.repeat(np.arange(len(edge)), size)
    k = np.arange(len(block)) - first[block]  # the point's place along its edge
    e = edge[block]
    s = ((k + 0.5) if layer % 2 else (k + 1)) / m[e]
    mid = a[e] + d[e] * s[:, None]
    off = side[:, None] * nrm[edge] * g[edge][:, None] * math.sqrt(3) / 2 * layer
    return mid + off[block], g[e]


def keep_clear(polygon: Polygon):
    """(starts, ends) of what seed points keep clear of: the rings' edges, the
    segment pieces and, as segments of length zero, the fixed points."""
    a, d, _ = polygon_edges(polygon, constraints=True)
    if not len(polygon.fixed):
        return a, a + d
    f = polygon.vertices[polygon.fixed]
    return np.concatenate([a, f]), np.concatenate([a + d, f])


def corner_fans(polygon: Polygon, piece: np.ndarray, h: float):
    """Points that split every polygon corner of angle theta into
    k = round(theta / 60 degrees) equal angles, one boundary piece away from the
    corner (at most :data:`FAN_CAP` h: a polygon edge left whole is no guide):
    the corner's fan of near-equilateral triangles.  Only for k = 2 and k >= 4:
    below 90 degrees there is nothing to split, and a vertex within 30 degrees
    of straight (k = 3) is split into three by the apexes of
    :func:`boundary_rows` already (on the surface layer's domains, those are
    the vertices that are not corners).  At a vertex that segment pieces
    touch, the corners are the angles between its consecutive constraint edges
    (:func:`_sectors`): a free end of a segment is a corner of 360 degrees.
    ``piece`` holds the piece length of every constraint edge.

    Returns lists of (1, 2) points and of their (1,) spacings."""
    E = polygon.edges
    V = polygon.vertices
    theta = polygon.interior_angles()
    _, d, L = polygon_edges(polygon)
    e_in = np.empty(len(V), np.int64)
    e_in[E[:, 1]] = np.arange(len(E))
    joined = np.zeros(len(V), bool)
    joined[polygon.segment_edges.ravel()] = True
    out, gaps = [], []
    for e in range(len(E)):  # e leaves vertex v: the interior is on its left
        v = E[e, 0]
        if joined[v]:
            continue
        _fan(out, gaps, V[v], d[e] / L[e], theta[v], 0.5 * (piece[e] + piece[e_in[v]]), h)
    for v, u, phi, c1, c2 in _sectors(polygon, np.flatnonzero(joined)):
        _fan(out, gaps, V[v], u, phi, 0.5 * (piece[c1] + piece[c2]), h)
    return out, gaps


def _fan(out: list, gaps: list, v, u, theta: float, piece: float, h: float) -> None:
    """Append the fan of the corner at ``v`` that opens counter-clockwise from
    unit direction ``u`` by ``theta``: see :func:`corner_fans`."""
    k = int(math.floor(theta / (math.pi / 3) + 0.5))
    if k < 2 or k == 3:  # k = 3: a near-straight vertex, the rows' apexes split it
        return
    g = min(piece, FAN_CAP * h)
    for j in range(1, k):
        phi = j * theta / k
        c, s = math.cos(phi), math.sin(phi)
        out.append(v + g * np.array([[c * u[0] - s * u[1], s * u[0] + c * u[1]]]))
        gaps.append(np.full(1, g))


def _sectors(polygon: Polygon, vertices):
    """The corners inside P at each of ``vertices`` between consecutive
    constraint edges (counter-clockwise): (vertex, unit direction of the first
    edge, angle, constraint edge of the first and of the second side)."""
    C = polygon.constraint_edges
    V = polygon.vertices
    ring_in = np.full(len(V), -1, np.int64)
    ring_in[polygon.edges[:, 1]] = np.arange(len(polygon.edges))
    out = []
    for v in vertices:
        cs = np.flatnonzero((C[:, 0] == v) | (C[:, 1] == v))
        w = np.where(C[cs, 0] == v, C[cs, 1], C[cs, 0])
        u = V[w] - V[v]
        u /= np.hypot(u[:, 0], u[:, 1])[:, None]
        ang = libm.arctan2(u[:, 1], u[:, 0])
        order = np.lexsort((cs, ang))
        cs, u, ang = cs[order], u[order], ang[order]
        gap = np.diff(np.append(ang, ang[0] + 2 * math.pi))
        for i in range(len(cs)):
            if cs[i] == ring_in[v]:  # from the incoming ring edge on: outside P
                continue
            j = (i + 1) % len(cs)
            out.append((v, u[i], float(gap[i]), int(cs[i]), int(cs[j])))
    return out
