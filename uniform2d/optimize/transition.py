"""Rows around small holes: the mesh grades from a hole's short edges out to the target size.

A hole whose edges are much shorter than the target size h (a bolt hole of a
plate meshed coarsely) cannot be met by the lattice: the points at distance h
fan onto its short edges in needle triangles, and no point move mends that,
for the structure is wrong (too few points near the hole).
:func:`transition_rows` puts rows of points around such a hole, each a
constant offset of the one before (``shapely``'s buffer of the hole) split
evenly: the fewest points (down to 1 / ``GROW`` of the row before) whose
spacing stays within ``LAST_ROW`` h, at the apex height of an equilateral
triangle over the row before's pieces; the first row fans onto the hole's
edges, the lattice meets the last one at about its own size.  Fewest points:
a row costs points the rest of the mesh lacks (the count is exact), which at
low counts raises the longest edge and the edge CV more than the angles need.
The optimiser keeps these points where they are (the descent would push them
out towards h, back into the fans).  Holes whose edges are near h are left
alone: a start without small holes is unchanged.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .._kernel.distance import to_segments
from ..polygon import Polygon
from .rows import keep_clear

__all__ = ["GROW", "LAST_ROW", "SMALL_PIECE", "transition_rows", "with_transition"]

#: A hole gets rows when its longest boundary piece is below SMALL_PIECE * h.
SMALL_PIECE = 0.5
#: A row has at least 1 / GROW of the points of the row before (2 on the
#: bolt plate left its edge CV above Gmsh's at 400 and 500 vertices).
GROW = 3.0
#: Rows are placed while their spacing stays below LAST_ROW * h.
LAST_ROW = 0.8


def _next_row(hole, count: int, length: float, offset: float, h: float):
    """The sparsest row after one of ``count`` points on a line of ``length``
    at ``offset`` from the hole: the fewest points, down to count / GROW, at the
    apex height over its own pieces, whose spacing stays within LAST_ROW * h.
    (count, line, offset) of it, or None."""
    for c in range(max(3, math.ceil(count / GROW)), count):
        off = offset + length / c * math.sqrt(3) / 2
        line = hole.buffer(off, quad_segs=16).exterior
        if line.length / c <= LAST_ROW * h:
            return c, line, off
    return None


def _hole_rows(ring: np.ndarray, h: float):
    """(points, spacings) of the rows around one hole ring (:func:`_next_row`
    after :func:`_next_row`, from the ring's own vertices)."""
    hole = shapely.Polygon(ring)
    out, gaps = [], []
    count, length, offset = len(ring), hole.exterior.length, 0.0
    while (row := _next_row(hole, count, length, offset, h)) is not None:
        count, line, offset = row
        length = line.length
        at = shapely.line_interpolate_point(line, np.arange(count) * (length / count))
        out.append(shapely.get_coordinates(at))
        gaps.append(np.full(count, length / count))
    return out, gaps


def transition_rows(polygon: Polygon, m: np.ndarray, h: float) -> np.ndarray:
    """The rows around every small hole of P, (k, 2): holes whose boundary pieces
    (``m[e]`` pieces of ring edge e) are all shorter than ``SMALL_PIECE * h``.
    Points outside P or within 0.6 of their row's spacing of a constraint are
    left out, and of two rows' points closer than 0.75 spacing the first kept
    (rows of near holes meet).  Empty if no hole is small."""
    offsets = polygon.ring_offsets
    V = polygon.vertices
    E = polygon.edges
    L = np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T)
    rows, gaps = [], []
    for r in range(1, len(polygon.rings)):
        e = np.arange(offsets[r], offsets[r + 1])
        pieces = L[e] / m[e]
        if pieces.max() >= SMALL_PIECE * h:
            continue
        got, g = _hole_rows(polygon.rings[r], h)
        rows += got
        gaps += g
    if not rows:
        return np.empty((0, 2))
    R, G = np.concatenate(rows), np.concatenate(gaps)
    ok = shapely.contains_xy(polygon.to_shapely(), R[:, 0], R[:, 1])
    a, b = keep_clear(polygon)
    ok &= to_segments(R, a, b, 0.45 * G.max()) >= 0.45 * G
    R, G = R[ok], G[ok]
    tree = cKDTree(R)
    taken = np.zeros(len(R), bool)
    keep = []
    for i in range(len(R)):  # in row order: the inner rows win
        if taken[i]:
            continue
        keep.append(i)
        taken[tree.query_ball_point(R[i], 0.75 * G[i])] = True
    return R[keep]


def with_transition(polygon: Polygon, m: np.ndarray, h: float, rows):
    """(held, rows): :func:`transition_rows` (None without small holes) and the
    points of ``rows`` (a start's first rows, or None) farther than
    ``LAST_ROW * h`` from them."""
    trans = transition_rows(polygon, m, h)
    if not len(trans):
        return None, rows
    if rows is not None and len(rows):
        rows = rows[cKDTree(trans).query(rows)[0] >= LAST_ROW * h]
    return trans, rows
