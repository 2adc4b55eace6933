"""Weighted Lloyd iterations: a graded start with the structure of a centroidal
Voronoi tessellation.

Algorithm INSERT with a size field places points at the field's density, but
with the irregular neighbourhoods of a farthest-point sequence; the optimiser's
moves keep the connectivity they start from (up to Delaunay flips), and that
limits how even the edges can become (the spread of q = length / h).  A few
Lloyd iterations for the density ρ = 1 / h² move every free point to the
ρ-weighted centroid of its Voronoi cell, which tends to the hexagonal
neighbourhoods of a centroidal Voronoi tessellation, whose cells have sizes
following h.

The Voronoi cell of a vertex v is taken within the mesh: in every triangle
(v, a, b) around it, the two triangles (v, mid(v, a), c) and (v, c, mid(v, b))
with c the circumcentre (signed areas, so that obtuse triangles add up
correctly), each weighted by its area times ρ at its centroid.  A point whose
centroid falls outside P stays; ``fixed`` points (the boundary and segment
points) stay.  Each iteration moves ``omega`` times the way to the centroid
(over-relaxation: it converges in fewer iterations) and triangulates again
(:func:`uniform2d.triangulation.load`, exact) with the sites' edges found
once (a free site only moves to places strictly inside P).
"""

from __future__ import annotations

import numpy as np
import shapely

from ..polygon import Polygon
from ..sites import site_edges
from .._kernel.cells import weighted_centroids
from ..triangulation import load, unload

__all__ = ["weighted_lloyd"]


def weighted_lloyd(polygon: Polygon, sites, fixed, size, *, iterations: int = 30,
                   omega: float = 1.5, power: int = 2) -> np.ndarray:
    """Move the free ``sites`` towards the ρ = 1 / size**power centroids of their cells.

    Parameters
    ----------
    polygon : Polygon
    sites : array_like, shape (k, 2)
        Steiner points in P.  Not modified.
    fixed : array_like of bool, shape (k,)
        Sites that stay (those on the boundary or on segments).
    size : SizeField
        The size field (its grid is read in compiled code).
    iterations : int
    omega : float
        Over-relaxation factor (1: plain Lloyd).
    power : int
        The density's power of 1 / size.  A centroidal Voronoi tessellation of
        density ρ has cells of diameter about ρ^(-1/4) in the plane (Gersho's
        conjecture, Du, Faber and Gunzburger 1999), so cells of diameter
        following the size need ρ = 1 / size⁴ (4); with 1 / size² (2) the
        iterations flatten the grading towards sqrt(size).

    Returns
    -------
    ndarray, shape (k, 2)
        The moved sites (the fixed ones exactly as given).

    Examples
    --------
    >>> from uniform2d import Polygon, SizeField
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = SizeField.constant(sq.bounds, 1.0)
    >>> weighted_lloyd(sq, [(0.3, 0.4)], [False], f).round(6).tolist()
    [[0.5, 0.5]]
    """
    S, edges = site_edges(polygon, sites)
    S = S.copy()
    # sites on the boundary stay on their edge; the others are placed as interior
    # points (only places strictly inside P are taken), so no site is classified
    # by distance again
    free = ~np.asarray(fixed, dtype=bool) & (edges < 0)
    off = polygon.ring_offsets
    rings = [polygon.vertices[off[r]:off[r + 1]] for r in range(len(polygon.rings))]
    shape = shapely.Polygon(rings[0], rings[1:])
    nV = len(polygon.vertices)
    V = polygon.vertices
    for _ in range(iterations):
        # the exact CDT, not checked: only the moves' result is a mesh
        T = unload(load(polygon, S, edges=edges)).astype(np.int64)
        P = np.concatenate([V, S])
        target = weighted_centroids(P, T, size.x, size.y, size.values, power)[nV:]
        cand = S + omega * (target - S)
        ok = free & np.isfinite(cand).all(axis=1)
        ok[ok] = shapely.contains_xy(shape, cand[ok, 0], cand[ok, 1])
        S[ok] = cand[ok]
    return S
