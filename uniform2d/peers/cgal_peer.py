"""CGAL's isotropic remeshing (Polygon_mesh_processing, SWIG bindings), for surface models.

``isotropic_remeshing`` splits edges longer than 4/3 of the target length,
collapses those shorter than 4/5, flips towards valence 6 and smooths
tangentially; the input's crease edges (dihedral angle above
:data:`CREASE_ANGLE`) are given as constrained edges.  The target length is
tuned to the vertex count like MeshLab's.  Optional: ``pip install cgal``.

Facts about the ``cgal`` 6.0 bindings this module relies on: a polygon soup is
turned into a ``Polyhedron_3`` by ``polygon_soup_to_polygon_mesh`` (which keeps
the vertex order, checked here, so crease edges can be named by index);
vertex ids are set by hand with ``set_id``.
"""

from __future__ import annotations

import importlib.util
import math

import numpy as np

from ..geometry import boundary_edges
from .base import PeerMesh, tuned_mesh

NAME = "cgal"
KIND = "surface"
DESCRIPTION = "CGAL isotropic remeshing (3 iterations, creases constrained), tuned target length"
REQUIRES = ("cgal",)

#: Remeshing iterations passed to CGAL.
ITERATIONS = 3
#: Edges bent more than this (degrees) are constrained.
CREASE_ANGLE = 30.0


def available() -> bool:
    """Whether CGAL's Python bindings are installed."""
    return importlib.util.find_spec("CGAL") is not None


def creases(V, F, angle: float = CREASE_ANGLE) -> set:
    """Edges (smaller vertex first) whose faces' normals differ by more than ``angle``."""
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    edge_faces: dict = {}
    for f, tri in enumerate(F.tolist()):
        for i in range(3):
            a, b = tri[i], tri[(i + 1) % 3]
            edge_faces.setdefault((min(a, b), max(a, b)), []).append(f)
    cos = math.cos(math.radians(angle))
    return {e for e, fs in edge_faces.items() if len(fs) == 2 and n[fs[0]] @ n[fs[1]] < cos}


def remesh(V, F, h: float, keep: set) -> tuple[np.ndarray, np.ndarray]:
    """CGAL isotropic remeshing of (V, F) at edge length h, the edges ``keep`` constrained."""
    from CGAL import CGAL_Polygon_mesh_processing as PMP
    from CGAL.CGAL_Kernel import Point_3
    from CGAL.CGAL_Polyhedron_3 import Polyhedron_3

    V = np.asarray(V, dtype=np.float64)
    pts, polys, p = PMP.Point_3_Vector(), PMP.Polygon_Vector(), Polyhedron_3()
    for v in V:
        pts.append(Point_3(*map(float, v)))
    for f in np.asarray(F).tolist():
        polys.append(PMP.Int_Vector([int(i) for i in f]))
    PMP.polygon_soup_to_polygon_mesh(pts, polys, p)
    if not np.array_equal([[q.x(), q.y(), q.z()] for q in p.points()], V):
        raise RuntimeError("CGAL reordered the vertices: the crease edges cannot be named")
    for i, v in enumerate(p.vertices()):
        v.set_id(i)

    def ends(e):
        a, b = e.vertex().id(), e.opposite().vertex().id()
        return (min(a, b), max(a, b))

    constrained = [e for e in p.halfedges() if ends(e) in keep]
    PMP.isotropic_remeshing(list(p.facets()), float(h), p, ITERATIONS, constrained, False)
    X = np.array([[q.x(), q.y(), q.z()] for q in p.points()])
    for i, v in enumerate(p.vertices()):
        v.set_id(i)
    T = [[(e := f.halfedge()).vertex().id(), e.next().vertex().id(),
          e.next().next().vertex().id()] for f in p.facets()]  # fmt: skip
    return X, np.array(T, dtype=np.int64).reshape(-1, 3)


def mesh(patch, n_vertices: int) -> PeerMesh:
    """CGAL remesh of ``patch`` (a ``(V, F)`` pair) tuned to ``n_vertices``.

    Closed meshes only: the bindings crash the process (a segmentation fault) on
    some meshes with a boundary (the cone and cylinder patches), and a child
    process to contain that breaks the report's own worker pool when Gmsh ran in
    the same worker; an open mesh is a RuntimeError, a failed peer."""
    V, F = (np.asarray(a) for a in patch)
    if len(boundary_edges(F, len(V))):
        raise RuntimeError("the cgal peer remeshes closed models only (CGAL's Python bindings "
                           "crash on some meshes with a boundary)")
    return _mesh_here(V, F, int(n_vertices))


def _mesh_here(V, F, n_vertices: int) -> PeerMesh:
    """:func:`mesh` in this process."""
    keep = creases(V, F)
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    area = 0.5 * float(np.linalg.norm(np.cross(e1, e2), axis=1).sum())
    h0 = math.sqrt(4.0 * area / (math.sqrt(3.0) * 2.0 * n_vertices))
    return tuned_mesh(lambda h: remesh(V, F, h, keep), n_vertices, h0,
                      lambda size: {"parameter": "target edge length", "iterations": ITERATIONS},
                      max_evals=12)
