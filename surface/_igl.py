"""The one adapter around libigl (no other module imports :mod:`igl`).

Facts about libigl 2.6.3's Python bindings this module relies on:

- ``igl.lscm(V, F, b, bc)`` returns a tuple ``(uv, Q)``; its global scale is
  fixed by the pinned values ``bc``, not by the surface, so callers rescale;
- ARAP is ``igl.ARAPData()`` (``igl.ARAP`` is an enum, not a class) with
  ``with_dynamics = False``, ``igl.arap_precomputation(V, F, 2, b, data)`` with
  ``b`` an int32 index array, then ``igl.arap_solve(bc, data, U0)``;
- ``igl.map_vertices_to_circle`` wants a Fortran-ordered V and an int32 loop;
- ``igl.AABB`` built on 2-column UV coordinates crashes the process, so 2-D point
  location pads UV with z = 0 (an ``igl.AABB`` on the padded mesh works and
  answers like ``igl.point_mesh_squared_distance``, which builds a new tree on
  every call).

Every function takes and returns plain numpy arrays with the dtypes the bindings
want made explicit here, so callers never see binding details.
"""

from __future__ import annotations

import hashlib

import numpy as np

import igl

__all__ = [
    "lscm", "arap", "harmonic_disk", "closest_faces", "closest_points", "SurfaceTree",
    "face_neighbours",
]


def _V(V) -> np.ndarray:
    return np.ascontiguousarray(V, dtype=np.float64)


def _F(F) -> np.ndarray:
    return np.ascontiguousarray(F, dtype=np.int64)


def face_neighbours(F) -> np.ndarray:
    """Neighbour of every face across each edge, -1 on the boundary.

    Parameters
    ----------
    F : (M, 3) int
        Faces of an oriented manifold mesh.

    Returns
    -------
    (M, 3) int64
        Column i: the face across edge ``(F[:, i], F[:, (i + 1) % 3])``
        (``igl.triangle_triangle_adjacency``).

    Examples
    --------
    >>> face_neighbours([[0, 1, 2], [2, 1, 3]]).tolist()
    [[-1, 1, -1], [0, -1, -1]]
    """
    TT, _ = igl.triangle_triangle_adjacency(_F(F))
    return np.asarray(TT, dtype=np.int64)


def lscm(V, F, pins) -> np.ndarray:
    """Free-boundary least-squares conformal map with two pinned vertices.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int
    pins : (2,) int
        Two distinct vertices (far apart on the boundary works best); they are
        placed on the u axis at their 3-D distance.

    Returns
    -------
    (N, 2) float64
        UV coordinates, up to a global similarity.
    """
    V, F = _V(V), _F(F)
    b = np.ascontiguousarray(pins, dtype=np.int64)
    d = float(np.linalg.norm(V[b[1]] - V[b[0]])) or 1.0
    bc = np.array([[0.0, 0.0], [d, 0.0]])
    uv, _ = igl.lscm(V, F, b, bc)
    return np.asarray(uv, dtype=np.float64)[:, :2].copy()


def arap(V, F, uv0, pin: int, iterations: int = 20) -> np.ndarray:
    """As-rigid-as-possible parameterisation started from ``uv0``.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int
    uv0 : (N, 2) float64
        Initial map (flip-free works best); also fixes the pinned vertex's position.
    pin : int
        The one vertex held fixed (removes the translation freedom).
    iterations : int
        Local-global iterations.

    Returns
    -------
    (N, 2) float64
    """
    V, F = _V(V), _F(F)
    uv0 = np.ascontiguousarray(uv0, dtype=np.float64)
    data = igl.ARAPData()
    data.with_dynamics = False
    data.max_iter = int(iterations)
    b = np.array([pin], dtype=np.int32)
    igl.arap_precomputation(V, F, 2, b, data)
    uv = igl.arap_solve(np.ascontiguousarray(uv0[b]), data, uv0)
    return np.asarray(uv, dtype=np.float64).copy()


def harmonic_disk(V, F, loop) -> np.ndarray:
    """Harmonic map with the boundary loop fixed on the unit circle (by arc length).

    Only for patches with a single boundary loop.  On non-round patches it can
    flip triangles; the caller checks.

    Returns
    -------
    (N, 2) float64
    """
    V, F = _V(V), _F(F)
    bnd = np.ascontiguousarray(loop, dtype=np.int32)
    bc = igl.map_vertices_to_circle(np.asfortranarray(V), bnd)
    uv = igl.harmonic(V, F, bnd.astype(np.int64), np.ascontiguousarray(bc), 1)
    return np.asarray(uv, dtype=np.float64)[:, :2].copy()


#: The last UV mesh's tree: (content digest, tree, padded UV, faces).  One remesh
#: locates points in the same UV mesh three times (interior chord error, size
#: field, lift), in three modules that should not have to pass a tree around.
#: This module-level cache is safe without being explicit: it is keyed by the
#: mesh's bytes, so a tree is only ever reused for identical coordinates and
#: faces (never stale); it holds one entry, so memory is bounded; and it is read
#: once and replaced whole, so concurrent threads at worst build a tree twice.
_LAST_TREE = None


def _uv_tree(UV, F):
    global _LAST_TREE
    U3 = np.zeros((len(UV), 3))
    U3[:, :2] = UV
    F = _F(F)
    key = hashlib.blake2b(U3.tobytes() + F.tobytes(), digest_size=16).digest()
    last = _LAST_TREE  # one read: another thread may replace it
    if last is not None and last[0] == key:
        return last[1:]
    tree = igl.AABB()
    tree.init(U3, F)
    _LAST_TREE = (key, tree, U3, F)
    return tree, U3, F


def closest_faces(P, UV, F):
    """Locate 2-D points in a 2-D triangle mesh.

    Parameters
    ----------
    P : (K, 2) float64
        Query points.
    UV : (N, 2) float64
        Mesh vertices in the plane.
    F : (M, 3) int

    Returns
    -------
    dist2 : (K,) float64
        Squared distance to the mesh (0 inside).
    face : (K,) int64
        A closest face (one containing the point if dist2 == 0).
    closest : (K, 2) float64
        The closest point of the mesh.
    """
    P3 = np.zeros((len(P), 3))
    P3[:, :2] = P
    tree, U3, F = _uv_tree(np.asarray(UV, dtype=np.float64), F)
    d2, idx, c = tree.squared_distance(U3, F, P3)
    return np.asarray(d2), np.asarray(idx, dtype=np.int64), np.asarray(c)[:, :2].copy()


def closest_points(P, V, F):
    """Squared distances, closest faces and closest points from 3-D points to a mesh.

    Returns
    -------
    dist2 : (K,) float64
    face : (K,) int64
    closest : (K, 3) float64
    """
    d2, idx, c = igl.point_mesh_squared_distance(_V(P).reshape(-1, 3), _V(V), _F(F))
    return np.asarray(d2), np.asarray(idx, dtype=np.int64), np.asarray(c)


class SurfaceTree:
    """A 3-D mesh's AABB tree, built once for many closest-point queries (the
    relaxation of an atlas asks dozens of times; :func:`closest_points` builds a
    tree every call)."""

    def __init__(self, V, F):
        self._V, self._F = _V(V), _F(F)
        self._tree = igl.AABB()
        self._tree.init(self._V, self._F)

    def closest(self, P):
        """Like :func:`closest_points`: ``(dist2, face, closest)``."""
        d2, idx, c = self._tree.squared_distance(self._V, self._F, _V(P).reshape(-1, 3))
        return np.asarray(d2), np.asarray(idx, dtype=np.int64), np.asarray(c)
