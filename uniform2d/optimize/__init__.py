"""Beyond the paper: the most uniform mesh uniform2d can make with exactly n Steiner points.

Pipeline (:func:`optimize_mesh`, in :mod:`~uniform2d.optimize.pipeline`):

1. **Target size** (:mod:`~uniform2d.optimize.boundary`).  h solves "an
   equilateral mesh of side h has |V| + n vertices"
   (:func:`uniform2d.geometry.size_for_count`).
2. **Starts** (:mod:`~uniform2d.optimize.seed`; the lattice
   :mod:`~uniform2d.optimize.lattice`, the first row :mod:`~uniform2d.optimize.rows`).  Boundary: every polygon edge
   of length L gets m = max(1, round(L / (c h))) equal pieces (fewer if they
   would exceed n).  Interior: the remaining points of a hexagonal lattice
   aligned with one polygon edge, at least half a spacing inside P, optionally
   after a first row at the apex of the equilateral triangle over every
   boundary piece, which begins with a fan at every corner of 90 degrees or
   more.  Boundary counts, lattice orientation and the first row fix the mesh's
   structure, which moving points cannot change, and the best choice depends
   on the polygon: small meshes try several by successive halving (every start
   a short run, the better two thirds or half a short descent, and so on) and
   the best goes on into the full schedule
   (:func:`~uniform2d.optimize.moves.improve_best`).  Lattice points deep inside P are uniform
   already and stay put (the kernel's passes then leave out the triangles
   that cannot change).
3. **Moving points** (:func:`improve`, in :mod:`~uniform2d.optimize.moves`;
   kernel :mod:`uniform2d._kernel.relax`).  The constrained Delaunay
   triangulation of the points is built once and kept valid and Delaunay by
   exact predicates and flips while the points move: polygon vertices fixed,
   boundary points sliding along their edges in order, interior points free.
   First spring rounds (least squares towards equal edges), then Gauss-Seidel
   descent on the p-norm energy of the objective
   (:mod:`~uniform2d.optimize.objective`) for growing p, keeping the best state
   by the true objective; last, sweeps that lower the spread of the edge
   lengths (the CV) with the objective's extremes held.  How long each stage
   runs is :mod:`~uniform2d.optimize.schedule`.  Small meshes then try
   relocation moves (:mod:`~uniform2d.optimize.relocate`): a point from where
   the edges are shortest to the middle of the longest edge, kept if the
   objective improves.
4. **Certification.**  The mesh is the kernel's own triangulation of the final
   points, the exact CDT it kept throughout, checked once
   (:func:`uniform2d.validity.ensure_valid`); its measures are compared
   with the paper's T+ on the objective and the better mesh is returned, with
   its certificates (when n is too small for T+, the optimised one).

With a size field (:func:`improve` ``size=``, used by the surface layer) every
length is measured against the local target size, so the same moves make a
graded mesh uniform in the field's metric.
"""

from .moves import improve
from .objective import OBJECTIVES, objective_value
from .pipeline import optimize_mesh
from .boundary import target_size
from .lattice import lattice_seed

__all__ = [
    "optimize_mesh",
    "improve",
    "lattice_seed",
    "target_size",
    "OBJECTIVES",
    "objective_value",
]
