"""MeshLab's isotropic explicit remeshing (through pymeshlab), for surface patches.

Wraps :func:`surface.isotropic_remesh` (10 iterations, absolute target edge
length) and bisects the target length until the vertex count matches.  The
starting guess is :func:`surface.sizing.target_size` for the patch's area,
boundary length and Euler characteristic.
"""

from __future__ import annotations

import importlib.util

import numpy as np

from .base import PeerMesh, tune

NAME = "meshlab"
KIND = "surface"
DESCRIPTION = "MeshLab isotropic explicit remeshing (pymeshlab), 10 iterations, absolute target length"
REQUIRES = ("pymeshlab", "trimesh", "libigl")

#: Remeshing iterations passed to MeshLab.
ITERATIONS = 10


def available() -> bool:
    """Whether pymeshlab and the surface layer's other dependencies are installed."""
    return all(importlib.util.find_spec(m) is not None for m in ("pymeshlab", "trimesh", "igl"))


def mesh_with_size(V, F, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Isotropic remesh of (V, F) at target edge length ``size``."""
    from surface import isotropic_remesh

    return isotropic_remesh((V, F), size, ITERATIONS)


def mesh(patch, n_vertices: int) -> PeerMesh:
    """MeshLab remesh of ``patch`` (a ``(V, F)`` pair or Patch) tuned to ``n_vertices``."""
    from surface import as_patch
    from surface.sizing import target_size

    P = as_patch(patch)
    V, F = P.vertices, P.faces
    B = float(sum(np.linalg.norm(V[np.roll(lp, -1)] - V[lp], axis=1).sum() for lp in P.boundary_loops))
    size0 = target_size(P.area, B, n_vertices, P.euler_characteristic)
    t = tune(lambda h: mesh_with_size(V, F, h), lambda m: len(m[0]), n_vertices, size0, max_evals=30)
    pts, tri = t.result
    return PeerMesh(
        pts, tri, t.size, t.evaluations,
        {"parameter": "targetlen (absolute)", "iterations": ITERATIONS, "history": t.history},
    )
