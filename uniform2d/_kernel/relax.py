"""Moving the vertices of a constrained Delaunay triangulation, in place.

The optimiser (:mod:`uniform2d.optimize`) improves a mesh by moving its points;
the kernel does the moving on a :class:`~uniform2d._kernel.cdt.Tri` (flat
half-edge arrays, see ``cdt``) without ever rebuilding it.  This module states
what the three ways to move share and gathers them: :mod:`.spring`,
:mod:`.descent`, :mod:`.spread`, on the star and measures of :mod:`.star`.

Vertex roles (``role[v]``)
--------------------------
``FIXED``  never moves (the polygon's vertices).
``FREE``   an interior point; moves in the plane.
``SLIDE``  a boundary point on polygon edge ``eid[v]``: its place is
           ``ea[e] + t[v] * ed[e]`` and it moves by changing ``t[v]``, never past
           its neighbours along the ring (so the boundary chain keeps its order).

Every move keeps the mesh valid, exactly
----------------------------------------
Every trial place is first rounded to what the caller's coordinates hold
(:func:`cdt.snap`; the identity near the origin), so the points the optimiser
hands back are exactly the ones decided on here; a SLIDE vertex may then sit a
rounding off its edge's line, and stays on its constraint by index.
A move is only made if every triangle around the moved vertex stays strictly
counter-clockwise (exact ``orient2d``).  With the boundary chain in order that
means the triangles still tile P, so nothing has to be located again.  After a
round of moves, :func:`.lawson.legalize_stack` (started from the edges around the
moved vertices) makes every unconstrained edge locally
Delaunay with the exact ``incircle`` (Lawson flips never touch a constrained,
i.e. boundary, edge), so after every round the mesh is again the constrained
Delaunay triangulation of its points.

Targets
-------
``hv[v]`` is the target size at vertex v relative to ``href`` (1 everywhere for
a uniform mesh; the size field for a graded one), refreshed from the Tri's size
grid after each round.  An edge's target is ``href * (hv[a] + hv[b]) / 2``, its
normalised length ``l = L / target``; a triangle's normalised perimeter is its
perimeter over the sum of its three edge targets.

Three ways to move
------------------
:func:`spring`   Jacobi rounds of linear springs whose rest lengths are the
                 targets scaled so that their root mean square equals the
                 edges' (times ``pressure``): a least-squares pull towards equal
                 normalised lengths (small spread, the edge CV).
:func:`descend`  Gauss-Seidel sweeps over the vertices, each moved by a
                 backtracking line search on its share of the energy
                 ``w_len sum l**p + w_short sum l**-p`` over edges (and
                 ``w_per sum pi**p`` over perimeters): with large p that is the
                 max/min of the objective, decreased one vertex at a time (a
                 decrease of a vertex's share is a decrease of the total).  The
                 weights (:func:`.descent._weights`, once per sweep) make the energy the
                 linearised log of the objective, so no term drowns the others.
                 The best state by the true objective is kept.
:func:`spread`   Gauss-Seidel sweeps on ``sum (l - mean l)**2`` (the spread, the
                 edge CV), a move accepted only if the star's longest and
                 shortest edge and largest perimeter stay within the mesh's
                 extremes, so the objective is held while the spread drops.

Restricted passes
-----------------
Every round or sweep also passes over the mesh: the measures and weights, the
edges to legalise, each vertex's star.  Where most vertices are FIXED (the
optimiser freezes the deep interior of a large lattice, which is uniform
already) those passes would cost more than the moves.  With ``restrict`` they
cover only the live triangle slots (:func:`.star.live_slots`: those with a
movable vertex, two rings around them, and any slot a flip rewrites); what the
other triangles add to the measures is computed once (:func:`.star.dead_part`),
for their shapes cannot change.  Only sums are added in another order (the
dead part last), so values, and the moves they steer, can differ in the last
bits.  Without ``restrict`` every pass covers every triangle, in the same order
as always (the surface layer's meshes are made so).

Besides validity, moves obey a quality guard (a float test, not a predicate): no
triangle around the moved vertex may become flatter than ``flat * target**2``
(twice its area) unless it was flatter before, so slivers cannot form but can heal.
"""

from .descent import descend
from .spread import spread
from .spring import spring
from .star import FIXED, FREE, SLIDE, edge_cv, measure, objective_of, refresh_sizes

__all__ = [
    "FIXED", "FREE", "SLIDE", "spring", "descend", "spread", "measure", "edge_cv", "objective_of",
    "refresh_sizes",
]
