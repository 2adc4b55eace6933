"""Gmsh's Frontal-Delaunay 2-D mesher, with a uniform size.

Options: ``Mesh.Algorithm = 6`` (Frontal-Delaunay), ``Mesh.MeshSizeMax = size``,
``Mesh.MeshSizeExtendFromBoundary = 0``, ``Mesh.MeshSizeFromPoints = 0`` and
``Mesh.MeshSizeFromCurvature = 0``, so the size field is the constant ``size``.
The size is bisected until the vertex count matches the target
(:func:`uniform2d.peers.base.tune`).  A polygon's segments and fixed points are
embedded in the surface (``gmsh.model.mesh.embed``): every segment piece as a
line between the vertices it joins, every fixed point on no segment as a point,
so Gmsh's mesh contains them as uniform2d's does.

Gmsh keeps global state and is not thread-safe: every call holds a module lock
and runs between its own ``gmsh.initialize`` / ``gmsh.finalize``, with no
configuration files read, so the result depends only on the arguments.
"""

from __future__ import annotations

import importlib.util
import threading

import numpy as np

from .base import PeerMesh, planar_result, tuned_mesh, tuned_planar_mesh

NAME = "gmsh"
KIND = "planar"
DESCRIPTION = "Gmsh Frontal-Delaunay (Mesh.Algorithm 6), constant size MeshSizeMax"
REQUIRES = ("gmsh",)
#: Segments and fixed points are embedded (see :func:`uniform2d.peers.takes_constraints`).
CONSTRAINTS = True

_LOCK = threading.Lock()


def available() -> bool:
    """Whether the ``gmsh`` Python module is installed."""
    return importlib.util.find_spec("gmsh") is not None


def version() -> str:
    import gmsh

    return str(gmsh.__version__)


def _build(gmsh, polygon, size: float) -> None:
    """The polygon as a plane surface, its segments and fixed points embedded."""
    geo = gmsh.model.geo
    V = polygon.vertices
    tag = [geo.addPoint(float(x), float(y), 0.0, size) for x, y in V]
    loops = []
    off = polygon.ring_offsets
    for r in range(len(polygon.rings)):
        ring = list(range(int(off[r]), int(off[r + 1])))
        lines = [geo.addLine(tag[a], tag[b]) for a, b in zip(ring, ring[1:] + ring[:1])]
        loops.append(geo.addCurveLoop(lines))
    surface = geo.addPlaneSurface(loops)
    curves = [geo.addLine(tag[a], tag[b]) for a, b in polygon.segment_edges.tolist()]
    on_curve = set(polygon.segment_edges.ravel().tolist())
    lone = [tag[i] for i in range(polygon.n_ring_vertices, len(V)) if i not in on_curve]
    geo.synchronize()
    if curves:
        gmsh.model.mesh.embed(1, curves, 2, surface)
    if lone:
        gmsh.model.mesh.embed(0, lone, 2, surface)


def mesh_with_size(polygon, size: float, field=None) -> tuple[np.ndarray, np.ndarray]:
    """Mesh ``polygon`` with Gmsh at the constant target edge length ``size``.

    Parameters
    ----------
    polygon : uniform2d.Polygon
    size : float
    field : callable, optional
        A size field ``h(points (k, 2)) -> (k,)``: Gmsh then gets ``size * h`` through
        its size callback (``gmsh.model.mesh.setSizeCallback``), with no upper bound.

    Returns
    -------
    points : ndarray, shape (N, 2)
    triangles : ndarray, shape (M, 3), int64, counter-clockwise
    """
    import gmsh

    with _LOCK:
        gmsh.initialize([], readConfigFiles=False, interruptible=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.option.setNumber("General.Verbosity", 0)
            gmsh.model.add("uniform2d_peer")
            _build(gmsh, polygon, float(size))
            gmsh.option.setNumber("Mesh.Algorithm", 6)
            gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
            gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
            gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
            if field is None:
                gmsh.option.setNumber("Mesh.MeshSizeMax", float(size))
            else:
                gmsh.model.mesh.setSizeCallback(
                    lambda dim, tag, x, y, z, lc: float(size) * float(field(np.array([[x, y]]))[0])
                )
            gmsh.model.mesh.generate(2)
            tags, coords, _ = gmsh.model.mesh.getNodes()
            etypes, _, enodes = gmsh.model.mesh.getElements(2)
        finally:
            gmsh.finalize()
    tags = np.asarray(tags, dtype=np.int64)
    xyz = np.asarray(coords, dtype=np.float64).reshape(-1, 3)
    order = np.argsort(tags, kind="stable")
    points = xyz[order, :2]
    tri_nodes = None
    for et, nodes in zip(etypes, enodes):
        if int(et) == 2:  # 3-node triangle
            tri_nodes = np.asarray(nodes, dtype=np.int64).reshape(-1, 3)
    if tri_nodes is None:
        raise RuntimeError("gmsh produced no triangles")
    triangles = np.searchsorted(tags[order], tri_nodes)
    return planar_result(points, triangles)


def mesh(polygon, n_vertices: int) -> PeerMesh:
    """Gmsh mesh of ``polygon`` with its size tuned to ``n_vertices`` vertices."""
    return tuned_planar_mesh(mesh_with_size, polygon, n_vertices,
                             lambda size: {"parameter": "Mesh.MeshSizeMax"})


def graded_mesh(polygon, field, n_vertices: int) -> PeerMesh:
    """Gmsh mesh of ``polygon`` following the size field ``field`` (a callable on
    (k, 2) points), its scale tuned to ``n_vertices`` vertices."""
    from ..grading import as_field, scale_for_count

    s0 = scale_for_count(polygon, as_field(polygon, field), n_vertices - len(polygon.vertices))
    return tuned_mesh(lambda s: mesh_with_size(polygon, s, field), n_vertices, s0,
                      lambda s: {"parameter": "scale of the size callback", "scale": s})
