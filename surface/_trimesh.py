"""The one place the surface layer asks trimesh about a mesh's faces and edges."""

from __future__ import annotations

import numpy as np

from uniform2d import libm

__all__ = ["dihedral_edges", "face_adjacency"]


def dihedral_edges(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    """Interior edges and the angle between their two faces' normals.

    Returns
    -------
    edges : (E, 2) int64
        Vertex pairs, smaller index first, sorted.
    angles : (E,) float64
        Radians in [0, pi]: 0 where the two faces are coplanar.
    """
    _, edges, angles = face_adjacency(vertices, faces)
    return edges, angles


def face_adjacency(vertices, faces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pairs of faces sharing an edge, the shared edge and their normals' angle.

    Returns
    -------
    pairs : (E, 2) int64
        Face indices, sorted by the shared edge.
    edges : (E, 2) int64
        The shared edge's vertices, smaller index first.
    angles : (E,) float64
        Radians in [0, pi] between the two faces' normals.
    """
    import trimesh

    V = np.asarray(vertices, dtype=np.float64)
    F = np.asarray(faces, dtype=np.int64)
    m = trimesh.Trimesh(V, F, process=False)
    pairs = np.asarray(m.face_adjacency, dtype=np.int64).reshape(-1, 2)
    edges = np.sort(np.asarray(m.face_adjacency_edges, dtype=np.int64).reshape(-1, 2), axis=1)
    # the angles from our own unit normals: trimesh's treat faces below its absolute
    # area tolerance as degenerate, which at a scale of 1e-6 is every face
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    a, b = n[pairs[:, 0]], n[pairs[:, 1]]
    angles = libm.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    return np.sort(pairs[order], axis=1), edges[order], angles[order]

