"""The one place the surface layer asks trimesh about a mesh's geometry."""

from __future__ import annotations

import numpy as np

__all__ = ["dihedral_edges"]


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
