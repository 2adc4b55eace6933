"""Meshing one flattened chart: the planar domain to a uniform planar mesh.

Shared by the single-patch remesh (:mod:`surface.remesh`) and the atlas
(:mod:`surface.atlas`): the compensation field of a flattening, and the one call
into the planar core that meshes a polygon with an exact count.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from uniform2d import insert
from uniform2d.errors import InternalError
from uniform2d.optimize import improve, lattice_seed
from uniform2d.optimize.lloyd import weighted_lloyd
from uniform2d.optimize.packing import rows_start

from .patch import Patch
from .sizing import compensation_field, size_variation, vertex_scale

__all__ = ["mesh_domain", "size_field", "UNIFORM_SIZE"]

#: Compensation is skipped where the size it asks for, ``h * sqrt(area scale)``,
#: varies by less than this fraction over the patch (see
#: :func:`surface.sizing.size_variation`): developable patches (plates,
#: cylinders, cones) vary only by discretisation, orders of magnitude below it,
#: curved ones (spherical caps) by orders of magnitude more.
UNIFORM_SIZE = 1e-3

#: Weighted Lloyd iterations (and over-relaxation) between the graded start and
#: the moves for a graded size, as :mod:`uniform2d.graded` does.
LLOYD_ITERATIONS = 10
LLOYD_OMEGA = 1.5

#: Grid nodes along the longer side of a chart for a graded size's field: a
#: caller's size varies faster than the smoothed compensation does.
GRADED_RESOLUTION = 129


def mesh_domain(polygon, n_interior: int, size_field, *, optimize=True, graded_start=False):
    """Mesh a polygon with exactly ``len(polygon.vertices) + n_interior`` points.

    The one 2-D meshing step.  Default: a hexagonal lattice
    (:func:`uniform2d.optimize.lattice_seed`) that
    :func:`uniform2d.optimize.improve` moves, in the metric of ``size_field``,
    towards equal size-normalised edges, keeping the mesh constrained Delaunay
    and the count exact.  With ``optimize=False``: the paper's Algorithm INSERT,
    graded by ``size_field`` (its candidates ranked by distance / size).
    Relaxing INSERT's points ends far less uniform than relaxing the lattice:
    the lattice gives the structure that point moves alone cannot.

    Parameters
    ----------
    polygon : uniform2d.Polygon
    n_interior : int
    size_field : uniform2d.SizeField or None
    optimize : bool
        Move the points (default) or keep INSERT's.
    graded_start : bool
        For a graded size (:mod:`surface.size3d`): start the moves from rows
        packed from the ring following the field, topped up by INSERT
        (:func:`uniform2d.optimize.packing.rows_start`), after a few weighted
        Lloyd iterations, instead of from the uniform lattice, whose density the
        moves cannot redistribute.

    Returns
    -------
    points : (N, 2) float64
        ``polygon.vertices`` first, then the inserted points.
    triangles : (M, 3) int64
        Counter-clockwise.
    mesher : str
        What produced the mesh (goes into the report).
    """
    graded = "" if size_field is None else " with size field"
    if graded_start and optimize and n_interior:
        seed, fixed = rows_start(polygon, n_interior, size_field, 1.0)
        if fixed.any():  # INSERT put points on the ring, which is the chart's seam
            seed, fixed = _pull_inside(polygon, seed, fixed)
        seed = weighted_lloyd(polygon, seed, fixed, size_field, iterations=LLOYD_ITERATIONS,
                              omega=LLOYD_OMEGA)
        P, T, _ = improve(polygon, seed, size=size_field)
        desc = "rows + INSERT + weighted Lloyd + uniform2d.optimize.improve" + graded
    elif optimize and n_interior:
        P, T, _ = improve(polygon, lattice_seed(polygon, n_interior), size=size_field)
        desc = "lattice + uniform2d.optimize.improve" + graded
    else:
        res = insert(polygon, n_interior, size=size_field)
        P = np.asarray(res.mesh_points, dtype=np.float64)
        T = np.asarray(res.triangles, dtype=np.int64)
        desc = "uniform2d.insert" + graded
    K = len(polygon.vertices)
    if len(P) != K + n_interior or not np.array_equal(P[:K], polygon.vertices):
        raise InternalError(
            f"planar mesher broke its contract: {len(P)} points for {K} + {n_interior} "
            "(a bug in uniform2d: please report it with the patch)"
        )
    return P, T, desc


def _pull_inside(polygon, seed, fixed):
    """The seed with its points on the ring moved halfway to their nearest interior
    point (a chart's ring is its seam samples: the mesher may add none on it), or
    the lattice where that is not strictly inside."""
    inner = np.flatnonzero(~fixed)
    off = polygon.ring_offsets
    rings = [polygon.vertices[off[r]:off[r + 1]] for r in range(len(polygon.rings))]
    shape = shapely.Polygon(rings[0], rings[1:])
    out = seed.copy()
    if len(inner):
        _, j = cKDTree(seed[inner]).query(seed[fixed])
        out[fixed] = 0.5 * (seed[fixed] + seed[inner[j]])
    if not len(inner) or not shapely.contains_xy(shape, out[fixed, 0], out[fixed, 1]).all():
        return lattice_seed(polygon, len(seed)), np.zeros(len(seed), dtype=bool)
    return out, np.zeros(len(seed), dtype=bool)


def size_field(P: Patch, prm, h: float, size3d=None):
    """The compensation field, or None where the size it asks for is constant.

    With ``size3d`` (a graded 3-D size, :class:`surface.size3d.Size3D`) the
    field is that size composed with the compensation, always a field, sampled
    on a finer grid (:data:`GRADED_RESOLUTION`)."""
    sv = vertex_scale(P.vertices, P.faces, prm.area_scale)
    if size3d is not None:
        return compensation_field(P.vertices, P.faces, prm.uv, prm.area_scale, h, scale=sv,
                                  size3d=size3d, resolution=GRADED_RESOLUTION)
    if not size_variation(sv) > UNIFORM_SIZE:  # a constant size: no field
        return None
    return compensation_field(P.vertices, P.faces, prm.uv, prm.area_scale, h, scale=sv)
