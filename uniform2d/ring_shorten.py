"""Ring points at the ends of a resampled mesh's too-long edges moved towards their other ends.

:mod:`uniform2d.ring_nudge` lengthens a resampled mesh's too-short edges by
moving a ring point off the other end.  Where the shortest edge is left at a
kept corner (a ring edge from a corner to a sample the tolerance pins, a chord
across a tip between a corner and a sample), the edge ratio can still come
down from the other side: the mesh's longest edges are often ring edges or
edges from a ring point (a ring edge of 1.3 to 1.4 spacings the mesher does
not split, an edge from a sample to a point across a bay).
:func:`shorten_rings` takes every mesh edge longer than twice the shortest
with an end that is a movable ring point (placed by the resampling: not a kept
corner, segment end or fixed point) and moves that end towards the other:
among :data:`uniform2d.ring_nudge.STEPS` spacings in the
:data:`~uniform2d.ring_nudge.TURNS` directions from straight towards it, the
position where that edge is shortest (down to twice the mesh's shortest edge,
the nearest such position first), where

- neither of the point's ring edges, nor its distance to the rest of the
  ring, becomes shorter than the mesh's shortest edge (or than it was), and a
  ring edge that grows stays at most twice the mesh's shortest edge;
- the rings stay within the tolerance of the outline, both ways
  (:func:`uniform2d.ring_nudge.band_bound`), and the polygon stays valid.

:func:`shortened` (what :func:`uniform2d.uniform_mesh` with ``resample`` runs
after :func:`uniform2d.ring_nudge.nudged` and the relocation moves, where the
edge ratio is above 2 and the shortest edge is at least :data:`FLOOR` of the
mean: below that the short side sets the ratio whatever the long side does)
keeps the moves as :func:`~uniform2d.ring_nudge.nudged` does (the mesh
relaxed around the moved points, kept if its edge ratio is lower, its CV at
most 1 % higher and its worst angle at most 1 % lower; every end at once, then
one at a time).  The polygon has as many vertices, the kept ones do not move,
n stays exact, and the deviation reported is the larger of the resampling's
and the moved edges' bound.
"""

from __future__ import annotations

import numpy as np

from .geometry import unique_edges
from .polygon import Polygon
from .ring_nudge import (
    CHECKED,
    GAIN,
    STEPS,
    candidate_positions,
    clearances,
    first_in_band,
    move_ends,
    moved_stage,
)
from .ring_split import SPLIT_RATIO

__all__ = ["FLOOR", "shorten_rings", "shortened"]

#: Tried only where the mesh's shortest edge is at least this fraction of its
#: mean edge (a longest edge of twice the shortest is then within reach).
FLOOR = 0.6


def shorten_rings(outline: Polygon, res, points, triangles, limit: float, skip=(),
                  most: int | None = None, sources: dict | None = None):
    """The rings of ``res.polygon`` (:class:`uniform2d.outline.Resampled`) with
    the movable ends of the mesh's too-long edges moved towards their other ends
    (see the module notes).  Parameters and returns as
    :func:`uniform2d.ring_nudge.nudge_rings`'s: (rings, pairs moved, bound,
    pairs that found no move).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.outline import Resampled
    >>> from uniform2d.triangulation import triangulate
    >>> sq = Polygon([(0, 0), (3, 0), (3, 3), (0, 3)])
    >>> res = Resampled(Polygon([(0, 0), (0.8, 0), (3, 0), (3, 3), (0, 3)]),
    ...                 np.array([1, 0, 1, 1, 1], bool), 1.0, 0.25, 0.0, 4)
    >>> P, T = triangulate(res.polygon, [(1.5, 1.5)])   # ring edges 0.8 and 2.2 whole
    >>> rings, moved, dev, stuck = shorten_rings(sq, res, P, T, 0.25)
    >>> moved, rings[0][1].tolist(), bool(dev <= 0.25)  # 0.25 along: 1.05 and 1.95
    ([(1, 2)], [1.05, 0.0], True)
    """
    P = np.asarray(points, dtype=np.float64)
    E = unique_edges(triangles, len(P))
    L = np.hypot(*(P[E[:, 1]] - P[E[:, 0]]).T)
    lo = float(L.min())
    target = 2.0 * lo  # the longest edge an edge ratio of 2 allows
    order = np.argsort(-L, kind="stable")
    pairs = ((int(x), int(y)) for a, b in E[order[L[order] > target]] for x, y in ((a, b), (b, a)))
    return move_ends(outline, res, P, pairs, lambda d: d > target, limit,
                     lambda *a: _toward(*a, target, lo, res.spacing, limit, res.polygon),
                     skip, most, sources)


def _toward(source, rings, ri, k, far, target, lo, h, limit, poly):
    """(ring, bound) with ring point k of ring ``ri`` moved towards ``far`` (see
    :func:`shorten_rings`), or None if no move shortens the edge to it."""
    ring = rings[ri]
    r = len(ring)
    prv, nxt = ring[k - 1], ring[(k + 1) % r]
    X0 = ring[k]
    X = candidate_positions(X0, far, h, toward=True)
    e1, e2 = np.hypot(*(X - prv).T), np.hypot(*(nxt - X).T)
    f1, f2 = float(np.hypot(*(X0 - prv))), float(np.hypot(*(nxt - X0)))
    c, c0 = clearances(ring, k, X)
    short = np.minimum(np.minimum(e1, e2), c)
    score = np.maximum(np.hypot(*(X - far).T), target)  # at twice the shortest, the nearest move
    ok = ((score < float(np.hypot(*(X0 - far))) - GAIN * h) & (short >= min(f1, f2, c0, lo))
          & ((e1 <= f1) | (e1 <= target)) & ((e2 <= f2) | (e2 <= target)))
    if not ok.any():
        return None
    idx = np.flatnonzero(ok)
    order = idx[np.lexsort((idx, score[ok]))][:CHECKED]
    cap = float(np.maximum(e1, e2)[order].max())
    return first_in_band(source, rings, ri, k, X, order, cap, float(STEPS.max()) * h, limit, poly)


def shortened(outline: Polygon, res, mesh, objective: str = "balanced"):
    """(res, mesh, points moved): a mesh of the resampled outline ``res``
    (:class:`uniform2d.outline.Resampled` of ``outline``) with ring points moved
    towards the far ends of its too-long edges where that is better (see the
    module notes); tried where the edge ratio is above ``SPLIT_RATIO`` and the
    shortest edge at least :data:`FLOOR` of the mean.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon, uniform_mesh
    >>> t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    >>> m = uniform_mesh(Polygon(np.c_[np.cos(t), np.sin(t)]), 300, resample=0.25)
    >>> m.info["resample"]["shortened"]           # ratio under 2: nothing to do
    0
    """
    return moved_stage(outline, res, mesh, objective, shorten_rings,
                       lambda q: q.edge_ratio <= SPLIT_RATIO or q.shortest_edge < FLOOR * q.mean_edge,
                       "towards the far ends of long")
