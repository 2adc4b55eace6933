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
correctly), each weighted by its area times ρ at its centroid; ``fixed``
points (the boundary and segment points) stay.  Each iteration moves every
free point ``omega`` times the way to its centroid at once (over-relaxation:
it converges in fewer iterations), in the kernel's mesh, built once
(:class:`~uniform2d.optimize.moves.KernelMesh`): a move that would invert a
triangle is not made (so no point leaves P), and flips keep the mesh the
exact constrained Delaunay triangulation of its points
(:func:`uniform2d._kernel.cells.lloyd`).
"""

from __future__ import annotations

import numpy as np

from ..polygon import Polygon
from ..sites import site_edges
from .._kernel.cells import lloyd
from .moves import KernelMesh

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
    # sites on the boundary stay on their edge (and by index: no site is
    # classified by distance again); the others move inside P
    stay = np.asarray(fixed, dtype=bool) | (edges >= 0)
    if len(S) == 0 or stay.all() or iterations <= 0:
        return S.copy()
    st = KernelMesh.built(polygon, S, edges=edges, frozen=stay)
    grid = size.transformed(1.0 / st.scale, -st.centre / st.scale)
    lloyd(st.m, st.role, grid.x, grid.y, grid.values, int(power), int(iterations), float(omega))
    out, _ = st.sites()
    out[stay] = S[stay]
    return out
