"""Where segments split P into regions: each region's side of every edge, its
lattice's anchor and its share of the points."""

from __future__ import annotations

import math

import numpy as np
import shapely

from .. import libm
from ..geometry import polygon_edges
from ..polygon import Polygon

__all__ = ["sides_of", "anchor", "region_shares"]


def sides_of(polygon: Polygon, faces) -> np.ndarray:
    """(E + S, 2): the region on the left and on the right of every constraint
    edge (-1 for none: outside P).

    Matched exactly: the faces are closed from the constraint edges themselves,
    so an edge on a face's boundary is a pair of consecutive vertices of one of
    its rings, which has the face on its left where it runs counter-clockwise
    round the face (a probe a small step off the edge can land in the wrong
    region where the region is thinner than the step).  An edge on no face's
    boundary (a free piece, a bridge) lies inside one face, on both sides."""
    left = {}
    for r, f in enumerate(faces):
        for k, ring in enumerate((f.exterior, *f.interiors)):
            xy = [tuple(c) for c in np.asarray(ring.coords)]
            if ring.is_ccw != (k == 0):  # the face's side first
                xy.reverse()
            left.update({(p, q): r for p, q in zip(xy[:-1], xy[1:])})
    V = [tuple(v) for v in polygon.vertices.tolist()]
    E = polygon.constraint_edges
    out = np.array([[left.get((V[u], V[v]), -1), left.get((V[v], V[u]), -1)] for u, v in E],
                   dtype=np.int64).reshape(-1, 2)
    a, d, _ = polygon_edges(polygon, constraints=True)
    for e in np.flatnonzero((out == -1).all(axis=1) & (np.arange(len(E)) >= len(polygon.edges))):
        mid = a[e] + 0.5 * d[e]
        inside = [r for r, f in enumerate(faces) if shapely.contains_xy(f, *mid)]
        out[e] = inside[0] if inside else -1
    return out


def anchor(polygon: Polygon, sides: np.ndarray, r: int, angle: float, h: float) -> np.ndarray:
    """Where a lattice at ``angle`` starts in region r: at the apex, inside the
    region, of the piece on its boundary nearest to that angle (modulo 60
    degrees; the longest of those within a degree), so that the lattice meets
    that piece's row of :func:`boundary_rows` in step."""
    a, d, L = polygon_edges(polygon, constraints=True)
    on = np.flatnonzero((sides == r).any(axis=1))
    ang = libm.arctan2(d[on, 1], d[on, 0])
    off = np.abs((ang - angle + math.pi / 6) % (math.pi / 3) - math.pi / 6)
    near = off <= max(off.min(), math.radians(1.0))
    e = on[np.lexsort((on, -L[on], ~near))[0]]
    side = 1.0 if sides[e, 0] == r else -1.0
    return a[e] + 0.5 * d[e] + side * np.array([-d[e, 1], d[e, 0]]) / L[e] * h * math.sqrt(3) / 2


def region_shares(polygon: Polygon, faces, sides, h: float, count: int) -> np.ndarray:
    """How many of ``count`` interior points each region gets: in proportion to
    the interior vertices of an equilateral mesh of side h of it (Euler's
    formula: 2A/(sqrt(3) h^2) - B/(2h) + 1 - holes, a free segment inside it
    counting as boundary on both sides, a fixed point off the segments as one
    vertex), by largest remainders."""
    _, _, L = polygon_edges(polygon, constraints=True)
    on_seg = np.zeros(len(polygon.vertices), bool)
    on_seg[polygon.segment_edges.ravel()] = True
    lone = polygon.vertices[polygon.fixed[~on_seg[polygon.fixed]]]
    want = np.empty(len(faces))
    for r, f in enumerate(faces):
        free = L[(sides[:, 0] == r) & (sides[:, 1] == r)].sum()
        n_lone = np.count_nonzero(shapely.contains_xy(f, lone[:, 0], lone[:, 1]))
        want[r] = (2.0 * f.area / (math.sqrt(3.0) * h * h) - (f.length + 2.0 * free) / (2.0 * h)
                   + 1.0 - len(f.interiors) - n_lone)
    want = np.maximum(want, 0.0) + 1e-12
    exact = count * want / want.sum()
    share = np.floor(exact).astype(np.int64)
    extra = np.lexsort((np.arange(len(faces)), share - exact))[: count - int(share.sum())]
    share[extra] += 1
    return share
