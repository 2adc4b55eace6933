"""The one place the surface layer asks trimesh about a mesh's geometry."""

from __future__ import annotations

import numpy as np

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
    import trimesh

    m = trimesh.Trimesh(np.asarray(vertices), np.asarray(faces), process=False)
    edges = np.sort(np.asarray(m.face_adjacency_edges, dtype=np.int64), axis=1)
    angles = np.asarray(m.face_adjacency_angles, dtype=np.float64)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    return edges[order], angles[order]


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

    m = trimesh.Trimesh(np.asarray(vertices), np.asarray(faces), process=False)
    pairs = np.asarray(m.face_adjacency, dtype=np.int64).reshape(-1, 2)
    edges = np.sort(np.asarray(m.face_adjacency_edges, dtype=np.int64).reshape(-1, 2), axis=1)
    angles = np.asarray(m.face_adjacency_angles, dtype=np.float64)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    return np.sort(pairs[order], axis=1), edges[order], angles[order]

