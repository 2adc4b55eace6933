"""A resampled mesh's longest edges, chords across a boundary vertex, broken by relocation.

On a resampled outline the longest edges of a mesh of a few thousand points are
often *chords*: edges between two boundary points across a boundary vertex
(a corner, or the tip of a small peninsula of ring points) that got a single
triangle.  Both ends are polygon vertices, so no point move shortens them
while the triangulation holds, and the constrained Delaunay triangulation
keeps them until an interior point enters the circle through the corner and
the chord's ends.  The optimiser's relocation moves
(:func:`uniform2d.optimize.relocate.relocate`: the interior point whose edges
are shortest moved to the midpoint of the longest edge, its neighbourhood
relaxed again, kept if the objective improves) do exactly that, but the
optimiser runs them on meshes of up to ``schedule.RELOCATE_MAX`` points
only.  :func:`relocated` runs them on a resampled mesh whose edge ratio is
above :data:`~uniform2d.ring_split.SPLIT_RATIO`, and keeps the result only
if its edge ratio is lower, its edge CV at most :data:`CV_SLACK` higher and
its worst angle at most :data:`~uniform2d.ring_split.ANGLE_SLACK` lower (a
move into one corner can leave a flat triangle in another).
The points are as many (n stays exact) and the polygon is the same.
"""

from __future__ import annotations

import logging

import numpy as np

from .mesh import Mesh
from .optimize.pipeline import quality_summary
from .optimize.relocate import relocate
from .quality import quality
from .ring_split import SPLIT_RATIO, better_mesh
from .sites import site_edges
from .validity import ensure_valid

__all__ = ["CV_SLACK", "TRIES", "relocated"]

log = logging.getLogger(__name__)

#: Relocation tries on a resampled mesh (each a CDT of the whole mesh and a
#: local relaxation; the optimiser's own, for small meshes, is 15).
TRIES = 30
#: The relocated mesh is kept if its edge ratio is lower and its edge CV at
#: most this fraction higher than the mesh's.
CV_SLACK = 0.01


def relocated(mesh: Mesh, objective: str = "balanced") -> tuple[Mesh, int]:
    """(mesh, relocation moves kept): ``mesh`` (a uniform mesh of a resampled
    outline, ``mesh.info["h"]`` its target size) with relocation moves where
    its edge ratio is above ``SPLIT_RATIO``; the input and 0 unless the moved
    mesh's edge ratio is lower, its CV at most ``CV_SLACK`` higher and its worst
    angle at most ``ANGLE_SLACK`` lower.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon, uniform_mesh
    >>> m = uniform_mesh(Polygon([(0, 0), (3, 0), (3, 1), (0, 1)]), 40)
    >>> m2, moves = relocated(m)
    >>> len(m2.points) == len(m.points), m2.quality().edge_ratio <= m.quality().edge_ratio
    (True, True)
    """
    q = mesh.quality()
    if q.edge_ratio <= SPLIT_RATIO:
        return mesh, 0
    polygon = mesh.polygon
    nV = len(polygon.vertices)
    _, edges = site_edges(polygon, mesh.points[nV:])
    pts, tri, kept, _ = relocate(polygon, mesh.points, mesh.triangles,
                                 np.zeros(len(edges), dtype=bool), objective, mesh.info["h"],
                                 {}, edges, tries=TRIES)
    if not kept:
        return mesh, 0
    q2 = quality(pts, tri)
    if not better_mesh(q2, q, CV_SLACK):
        return mesh, 0
    ensure_valid(pts, tri, polygon, mesh.n_steiner, "uniform_mesh (relocation)")
    log.info("resampled mesh: %d relocation move(s), edge ratio %.4g -> %.4g, CV %.4g -> %.4g",
             kept, q.edge_ratio, q2.edge_ratio, q.cv_edge, q2.cv_edge)
    return Mesh(pts, tri, polygon, mesh.n_steiner,
                {**mesh.info, "after": quality_summary(q2)}), kept
