"""Meshing one flattened chart: the planar domain to a uniform planar mesh.

Shared by the single-patch remesh (:mod:`surface.remesh`) and the atlas
(:mod:`surface.atlas`): the compensation field of a flattening, and the one call
into the planar core that meshes a polygon with an exact count.
"""

from __future__ import annotations

import numpy as np

from uniform2d import insert
from uniform2d.errors import InternalError
from uniform2d.optimize import improve, lattice_seed

from .patch import Patch
from .sizing import compensation_field, size_variation, vertex_scale

__all__ = ["mesh_domain", "size_field", "UNIFORM_SIZE"]

#: Compensation is skipped where the size it asks for, ``h * sqrt(area scale)``,
#: varies by less than this fraction over the patch (see
#: :func:`surface.sizing.size_variation`): developable patches (plates,
#: cylinders, cones) vary only by discretisation, orders of magnitude below it,
#: curved ones (spherical caps) by orders of magnitude more.
UNIFORM_SIZE = 1e-3


def mesh_domain(polygon, n_interior: int, size_field, *, optimize=True):
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
    if optimize and n_interior:
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


def size_field(P: Patch, prm, h: float):
    """The compensation field, or None where the size it asks for is constant."""
    sv = vertex_scale(P.vertices, P.faces, prm.area_scale)
    if not size_variation(sv) > UNIFORM_SIZE:  # a constant size: no field
        return None
    return compensation_field(P.vertices, P.faces, prm.uv, prm.area_scale, h, scale=sv)
