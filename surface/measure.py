"""Uniformity measures of a triangle mesh in 3-D (numpy only).

These are the numbers the surface report gives and pymeshlab cross-checks:
unique edges and their lengths, per-face shortest/longest edge, corner angles.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> F = np.array([[0, 1, 2], [1, 3, 2]])
>>> s = edge_stats(V, F)
>>> s["n_edges"], round(s["ratio"], 6), round(s["angle_min"], 6)
(5, 1.414214, 45.0)
"""

from __future__ import annotations

import numpy as np

from uniform2d import libm
from uniform2d.geometry import unique_edges

__all__ = ["unique_edges", "edge_lengths", "face_edge_lengths", "corner_angles", "edge_stats"]


def edge_lengths(V, E) -> np.ndarray:
    """Lengths (E,) of edges (E, 2) over vertices (N, 3)."""
    V = np.asarray(V, dtype=np.float64)
    return np.linalg.norm(V[E[:, 1]] - V[E[:, 0]], axis=1)


def face_edge_lengths(V, F) -> np.ndarray:
    """Per-face edge lengths (M, 3): columns are edges (0,1), (1,2), (2,0)."""
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    return np.stack(
        [np.linalg.norm(V[F[:, (i + 1) % 3]] - V[F[:, i]], axis=1) for i in range(3)], axis=1
    )


def corner_angles(V, F) -> np.ndarray:
    """Corner angles (M, 3) in radians; column i is the angle at ``F[:, i]``."""
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    out = []
    for i in range(3):
        a = V[F[:, (i + 1) % 3]] - V[F[:, i]]
        b = V[F[:, (i + 2) % 3]] - V[F[:, i]]
        out.append(libm.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b)))
    return np.stack(out, axis=1)


def edge_stats(V, F) -> dict:
    """Edge-length and angle statistics of a triangle mesh.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int

    Returns
    -------
    dict
        ``n_edges``, ``min``, ``max``, ``mean``, ``total``, ``ratio`` (max/min),
        ``cv`` (standard deviation / mean), ``angle_min`` and ``angle_max`` in degrees,
        ``face_min`` and ``face_max``: (M,) shortest and longest edge of every face.
    """
    V = np.asarray(V, dtype=np.float64)
    if V.shape[1] == 2:
        V = np.column_stack([V, np.zeros(len(V))])
    E = unique_edges(F)
    L = edge_lengths(V, E)
    FL = face_edge_lengths(V, F)
    ang = np.degrees(corner_angles(V, F))
    return {
        "n_edges": int(len(E)),
        "min": float(L.min()),
        "max": float(L.max()),
        "mean": float(L.mean()),
        "total": float(L.sum()),
        "ratio": float(L.max() / L.min()),
        "cv": float(L.std() / L.mean()),
        "angle_min": float(ang.min()),
        "angle_max": float(ang.max()),
        "face_min": FL.min(axis=1),
        "face_max": FL.max(axis=1),
    }
