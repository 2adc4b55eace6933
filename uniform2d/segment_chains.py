"""The interior segment pieces of a polygon in the kernel's triangulation.

A segment piece is kept as a chain of mesh edges through the points on it; the
kernel flags those edges as constraints (:mod:`uniform2d._kernel.cdt`).  Here:
the chain of every piece as vertex pairs (:func:`piece_pairs`,
:func:`piece_chains`) and loading a mesh with its pieces flagged
(:func:`rebuild`).
"""

from __future__ import annotations

import numpy as np

from ._kernel import cdt, polytri
from .errors import InternalError, PLEASE_REPORT
from .polygon import Polygon

__all__ = ["piece_pairs", "piece_chains", "rebuild"]


def piece_chains(polygon: Polygon, boundary, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The segment pieces of P split at the points on them, as vertex pairs
    ``(us, vs)`` (mesh indices), from ``boundary`` as :func:`load_mesh` returns
    it: ``(index among the points after P's vertices, edge, parameter)``; ``tol``
    as :func:`piece_pairs`'s."""
    nV, nR = len(polygon.vertices), polygon.n_ring_vertices
    on: dict[int, list] = {}
    for i, e, t in boundary:
        if e >= nR:
            on.setdefault(e - nR, []).append((t, nV + i))
    out = np.array(piece_pairs(polygon, on, tol), dtype=np.int64).reshape(-1, 2)
    return out[:, 0].copy(), out[:, 1].copy()


def piece_pairs(polygon: Polygon, on: dict, tol: float) -> list:
    """Consecutive vertex pairs along every segment piece s: its ends, the points
    ``on[s]`` ((parameter, vertex) pairs) and any polygon vertex within ``tol``
    (the boundary tolerance) of the piece between its ends, in order along it.  Such a
    vertex (a fixed point a few ulps off a segment, beyond the 2 that make it a
    junction splitting the piece, ``constraints.NEAR_ULPS``) may lie exactly on
    the line between two points placed on the piece, which then cannot be an
    edge: it joins the chain."""
    V = polygon.vertices
    pairs = []
    for s, (a, b) in enumerate(polygon.segment_edges):
        d = V[b] - V[a]
        L2 = float(d @ d)
        rel = V - V[a]
        tt = rel @ d / L2
        off = np.abs(d[0] * rel[:, 1] - d[1] * rel[:, 0]) / np.sqrt(L2)
        near = np.flatnonzero((off <= tol) & (tt > 0.0) & (tt < 1.0))
        inner = sorted(on.get(s, []) + [(float(tt[k]), int(k)) for k in near if k not in (a, b)])
        chain = [int(a), *(v for _, v in inner), int(b)]
        pairs.extend(zip(chain[:-1], chain[1:]))
    return pairs


def rebuild(m, triangles, pieces) -> None:
    """Load the triangles (a valid mesh of P whose edges include the segment
    pieces ``pieces`` = (us, vs)) into ``m``, flag the pieces and make it the
    constrained Delaunay triangulation of its points."""
    cdt.build_adjacency(m, np.ascontiguousarray(triangles, dtype=np.int32))
    if len(pieces[0]):
        if polytri.recover_pieces(m, pieces[0], pieces[1]) < 0:
            raise InternalError(f"a segment piece is not an edge of the mesh {PLEASE_REPORT}")
    else:
        cdt.legalize_all(m)
