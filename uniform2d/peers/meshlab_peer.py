"""MeshLab's isotropic explicit remeshing (through pymeshlab), for surface patches.

Runs ``meshing_isotropic_explicit_remeshing`` (10 iterations, absolute target
edge length) and bisects the target length until the vertex count matches.
The starting guess is the edge length of an equilateral mesh with that many
vertices for the patch's area, boundary length and Euler characteristic.

Facts about pymeshlab 2025.7 this module relies on: the filter takes
``targetlen`` as a ``PercentageValue`` by default, so an absolute length is
passed as ``PureValue``; its ``maxsurfdist`` default (1 % of the bounding-box
diagonal) is not reliably computed on the input (in some processes the same
call behaved as if the surface-distance check were off), so that default is
passed explicitly.
"""

from __future__ import annotations

import importlib.util

import numpy as np

from ..geometry import boundary_edges, size_for_count
from .base import PeerMesh, tuned_mesh

NAME = "meshlab"
KIND = "surface"
DESCRIPTION = "MeshLab isotropic explicit remeshing (pymeshlab), 10 iterations, absolute target length"
REQUIRES = ("pymeshlab",)

#: Remeshing iterations passed to MeshLab.
ITERATIONS = 10
#: MeshLab's own default for the remeshing's surface-distance check, as a
#: fraction of the input's bounding-box diagonal (passed explicitly, see above).
MAX_SURFACE_DISTANCE = 0.01


def available() -> bool:
    """Whether pymeshlab is installed."""
    return importlib.util.find_spec("pymeshlab") is not None


def isotropic_remesh(V, F, target_length: float, iterations: int = ITERATIONS):
    """MeshLab's isotropic explicit remeshing with an absolute target edge length.

    MeshLab's defaults otherwise, with its surface-distance check at
    :data:`MAX_SURFACE_DISTANCE` of the bounding-box diagonal passed explicitly.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int
    target_length : float
        Target edge length in model units.
    iterations : int

    Returns
    -------
    vertices : (N', 3) float64
    faces : (M', 3) int64
    """
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.add_mesh(
        pymeshlab.Mesh(
            vertex_matrix=np.ascontiguousarray(V, dtype=np.float64),
            face_matrix=np.ascontiguousarray(F, dtype=np.int32),
        )
    )
    diag = float(np.linalg.norm(np.ptp(np.asarray(V, dtype=np.float64), axis=0)))
    ms.meshing_isotropic_explicit_remeshing(
        iterations=int(iterations),
        targetlen=pymeshlab.PureValue(float(target_length)),
        maxsurfdist=pymeshlab.PureValue(MAX_SURFACE_DISTANCE * diag),
    )
    m = ms.current_mesh()
    return (
        np.array(m.vertex_matrix(), dtype=np.float64),
        np.array(m.face_matrix(), dtype=np.int64),
    )


def mesh_with_size(V, F, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Isotropic remesh of (V, F) at target edge length ``size``."""
    return isotropic_remesh(V, F, size, ITERATIONS)


def _start_size(V, F, n_vertices: int) -> float:
    """Edge length of an equilateral mesh of the patch with ``n_vertices`` vertices."""
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    area = 0.5 * float(np.linalg.norm(np.cross(e1, e2), axis=1).sum())
    B = boundary_edges(F, len(V))
    length = float(np.linalg.norm(V[B[:, 1]] - V[B[:, 0]], axis=1).sum())
    n_edges = (3 * len(F) + len(B)) // 2
    chi = len(np.unique(F)) - n_edges + len(F)  # 1 - holes for a disk with holes
    return size_for_count(area, length, n_vertices, 1 - chi)


def mesh(patch, n_vertices: int) -> PeerMesh:
    """MeshLab remesh of ``patch`` (a ``(V, F)`` pair) tuned to ``n_vertices``."""
    V, F = (np.asarray(a) for a in patch)
    return tuned_mesh(
        lambda h: mesh_with_size(V, F, h), n_vertices, _start_size(V, F, n_vertices),
        lambda size: {"parameter": "targetlen (absolute)", "iterations": ITERATIONS},
        max_evals=30,
    )
