"""Shift moves: the change of structure that lifts a worst angle point moves cannot.

Where the worst triangle sits at a vertex of too many or too few neighbours
(near a star's reflex corners, beside a short polygon edge), moving points
one at a time under the mesh's extremes gains little
(:func:`~uniform2d.optimize.angles.raise_worst_angle`): the valences are what
hold the angle down.  :func:`shift_worst` moves one interior point of the worst
triangle to the midpoint of one of its edges to an interior neighbour, which
changes the valences around it, re-relaxes the points near the move (as
:func:`~uniform2d.optimize.relocate.relocate` does) and runs the angle pass
again.  The best try is kept if it raises the worst angle and none of the
edge ratio, longest edge, largest perimeter and edge CV of the mesh it started
from grows by more than ``SLACK``.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ..polygon import Polygon
from ..quality import quality
from ..threads import thread_map
from . import schedule as S
from .angles import MIN_GAIN, min_angles, raise_worst_angle
from .moves import improve_kept

__all__ = ["SHIFT_BELOW", "SHIFT_MAX", "SHIFT_MIN", "SHIFT_ROUNDS", "SLACK", "shift_worst"]

#: Meshes whose worst angle is SHIFT_BELOW degrees or more are left as they
#: are: Gmsh's worst angles on the benchmark polygons at n = 300 are 40.6 to
#: 43.7 degrees; above 44 no shift is needed to match them.
SHIFT_BELOW = 44.0
#: Meshes of up to SHIFT_MAX points get the moves (each try builds the whole
#: mesh again, as a relocation does).
SHIFT_MAX = S.RELOCATE_MAX
#: Meshes of fewer than SHIFT_MIN sites are left as they are: the points a
#: shift re-relaxes (within ``schedule.RELOCATE_RADIUS`` sizes) are then the
#: whole mesh, no local change of structure (the guide's 3-point square gained
#: 0.15 degree).
SHIFT_MIN = 50
#: Rounds (each the tries around the worst triangle of the round), at most: at
#: n = 300 a second round found no try within SLACK that gains on star10 and
#: heptagon_short, and lifted square2holes (already above Gmsh) further, for
#: 0.1-0.4 s more per mesh.
SHIFT_ROUNDS = 1
#: The relative growth of the edge ratio, longest edge, largest perimeter and
#: edge CV a kept shift may cost, all rounds together (the benchmarks hold
#: every measure within 1 %).
SLACK = 0.009

_HELD = ("edge_ratio", "longest_edge", "max_perimeter", "cv_edge")


def _tries(pts, tri, edges, fixed, nV):
    """(donor, place) pairs: each free interior vertex of the worst triangle, to
    the midpoint of each of its edges to an interior neighbour (an edge of
    the triangulation between two interior points lies inside P, off its
    boundary, and holds no other point)."""
    worst = tri[int(np.argmin(min_angles(pts, tri)))]
    out = []
    for v in sorted(int(v) for v in worst):
        if v < nV or edges[v - nV] >= 0 or fixed[v - nV]:
            continue
        ring = np.unique(tri[(tri == v).any(axis=1)])
        for u in ring:
            if u >= nV and u != v and edges[u - nV] < 0:
                out.append((v, 0.5 * (pts[v] + pts[u])))
    return out


def _try(polygon, pts, edges, fixed, h, objective, options, move):
    """The mesh after one shift: (points, triangles, edges, quality)."""
    nV = len(polygon.vertices)
    v, new = move
    sites = pts[nV:].copy()
    old = sites[v - nV].copy()
    sites[v - nV] = new
    near = np.minimum(np.hypot(*(sites - new).T), np.hypot(*(sites - old).T))
    local = fixed | (near > S.RELOCATE_RADIUS * h)
    p2, t2, info = improve_kept(polygon, sites, objective=objective, href=h, frozen=local,
                                edges=edges.copy(), **{**options, **S.RELOCATE})
    p3, t3, _ = raise_worst_angle(polygon, p2, t2, info["edges"])
    return p3, t3, info["edges"], quality(p3, t3)


def shift_worst(polygon: Polygon, pts, tri, frozen, objective: str, h: float, options, edges):
    """The mesh after up to ``SHIFT_ROUNDS`` kept shifts (module docstring).

    Arguments as :func:`~uniform2d.optimize.relocate.relocate`'s: ``frozen`` the
    sites that stay put, ``edges`` the polygon edge of each site (-1 inside).
    Meshes whose worst angle is ``SHIFT_BELOW`` or more, of more than
    ``SHIFT_MAX`` points or of fewer than ``SHIFT_MIN`` sites are returned as
    they are.  The tries of a round run
    on :func:`uniform2d.threads.thread_map` threads and the best is taken in
    their order: the same mesh on any number of threads.  Inputs are not
    modified.

    Returns (points, triangles, shifts kept, the sites' ``edges`` after them).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.triangulation import triangulate
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> pts, tri = triangulate(sq, [(0.5, 0.5)])
    >>> shift_worst(sq, pts, tri, np.zeros(1, bool), "balanced", 0.7, {}, np.array([-1]))[2]
    0
    """
    nV = len(polygon.vertices)
    edges = np.asarray(edges)
    fixed = np.asarray(frozen, dtype=bool)
    if len(pts) > SHIFT_MAX or len(pts) - nV < SHIFT_MIN:
        return pts, tri, 0, edges
    q0 = quality(pts, tri)
    if q0.min_angle >= SHIFT_BELOW:
        return pts, tri, 0, edges
    limit = {k: getattr(q0, k) * (1.0 + SLACK) for k in _HELD}
    angle, kept = q0.min_angle, 0
    for _ in range(SHIFT_ROUNDS):
        made = thread_map(partial(_try, polygon, pts, edges, fixed, h, objective, options),
                          _tries(pts, tri, edges, fixed, nV))
        ok = [m for m in made if m[3].min_angle >= angle + MIN_GAIN
              and all(getattr(m[3], k) <= limit[k] for k in _HELD)]
        if not ok:
            break
        best = max(ok, key=lambda m: m[3].min_angle)  # the first of equals: max is stable
        pts, tri, edges, angle = best[0], best[1], best[2], best[3].min_angle
        kept += 1
    return pts, tri, kept, edges
