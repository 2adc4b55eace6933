"""Point location in a planar triangle mesh by walking from a nearby face.

For queries that each come with a face they are known to be near (the chord
ends of :func:`surface.chord.interior_chord_error` lie about half an output
edge from an input vertex), a walk across a few faces beats a tree search over
the whole mesh.  The walk (a *visibility walk*): at face ``f`` with
counter-clockwise corners ``(v0, v1, v2)``, if the query ``q`` lies strictly to
the right of edge ``(v_i, v_{i+1})`` it cannot be in ``f``: step to the face
across that edge; when it lies to the right of none, ``f`` holds it::

            v2
           /  \\        q right of (v1, v2): step to the
          / f  \\   q   neighbour across that edge
        v0 ---- v1

It gives up (returns -1) where it would step off the mesh (the query is
outside, or the straight way to it leaves a non-convex mesh) or after
:data:`MAX_STEPS` steps (a visibility walk can cycle on a non-Delaunay mesh):
callers then use a tree search (:func:`surface._igl.closest_faces`).  The
face neighbours come from :func:`surface._igl.face_neighbours`.
Plain floating point, like the tree search: a query within rounding of an edge
may be given either face.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["walk", "MAX_STEPS"]

#: Steps after which a walk gives up.
MAX_STEPS = 256


@njit(cache=True)
def walk(q, start, uv, F, nbr):
    """Face (K,) holding each query point (K, 2), walking from face ``start`` (K,);
    -1 where the walk gave up (see the module docstring)."""
    out = np.empty(q.shape[0], np.int64)
    for k in range(q.shape[0]):
        qx = q[k, 0]
        qy = q[k, 1]
        f = start[k]
        prev = -1
        found = -1
        for _ in range(MAX_STEPS):
            step = -1
            for i in range(3):
                a = F[f, i]
                b = F[f, (i + 1) % 3]
                if nbr[f, i] == prev and prev >= 0:
                    continue  # came in through this edge: q is on its inner side
                ax = uv[a, 0]
                ay = uv[a, 1]
                if (uv[b, 0] - ax) * (qy - ay) - (uv[b, 1] - ay) * (qx - ax) < 0.0:
                    step = i
                    break
            if step < 0:
                found = f
                break
            nxt = nbr[f, step]
            if nxt < 0:
                break
            prev = f
            f = nxt
        out[k] = found
    return out
