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
(:func:`uniform2d.triangulation.triangulate`, exact) with the sites' edges found
once (a free site only moves to places strictly inside P).
"""

from __future__ import annotations

import numpy as np
import shapely

from ..polygon import Polygon
from ..sites import site_edges
from ..triangulation import triangulate

__all__ = ["weighted_lloyd"]


def _signed_area(a, b, c):
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def _circumcentres(a, b, c):
    d = 2 * (a[:, 0] * (b[:, 1] - c[:, 1]) + b[:, 0] * (c[:, 1] - a[:, 1])
             + c[:, 0] * (a[:, 1] - b[:, 1]))
    sa, sb, sc = (a**2).sum(1), (b**2).sum(1), (c**2).sum(1)
    ux = (sa * (b[:, 1] - c[:, 1]) + sb * (c[:, 1] - a[:, 1]) + sc * (a[:, 1] - b[:, 1])) / d
    uy = (sa * (c[:, 0] - b[:, 0]) + sb * (a[:, 0] - c[:, 0]) + sc * (b[:, 0] - a[:, 0])) / d
    return np.column_stack([ux, uy])


def _centroids(P: np.ndarray, T: np.ndarray, size, power: int = 2) -> np.ndarray:
    """(N, 2) ρ = 1 / size**power weighted centroid of every vertex's Voronoi cell within the mesh."""
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    cc = _circumcentres(a, b, c)
    num = np.zeros((len(P), 2))
    den = np.zeros(len(P))
    for k in range(3):
        v, w1, w2 = T[:, k], T[:, (k + 1) % 3], T[:, (k + 2) % 3]
        pv = P[v]
        m1, m2 = 0.5 * (pv + P[w1]), 0.5 * (pv + P[w2])
        for x, y in ((m1, cc), (cc, m2)):
            g = (pv + x + y) / 3.0
            w = _signed_area(pv, x, y) / size(g) ** power
            # bincount sums in input order, as np.add.at does, and much faster
            num[:, 0] += np.bincount(v, w * g[:, 0], minlength=len(P))
            num[:, 1] += np.bincount(v, w * g[:, 1], minlength=len(P))
            den += np.bincount(v, w, minlength=len(P))
    with np.errstate(invalid="ignore", divide="ignore"):
        return num / den[:, None]


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
    size : callable
        ``size(points (m, 2)) -> (m,)`` (a :class:`~uniform2d.SizeField`).
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
    for _ in range(iterations):
        P, T = triangulate(polygon, S, edges)
        target = _centroids(P, T, size, power)[nV:]
        cand = S + omega * (target - S)
        ok = free & np.isfinite(cand).all(axis=1)
        ok[ok] = shapely.contains_xy(shape, cand[ok, 0], cand[ok, 1])
        S[ok] = cand[ok]
    return S
