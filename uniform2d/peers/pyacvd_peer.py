"""pyacvd's approximated centroidal Voronoi clustering, for surface models.

ACVD (Valette and Chassery) clusters the input's vertices into exactly n
regions of near-equal area and triangulates their dual; the input is first
subdivided (each face into 4, as often as needed) until it has at least 10 n
vertices, so the clusters are not limited by the input's own vertices.  It
takes the count directly, so no tuning is needed.  Optional: ``pip install
pyacvd`` (which brings pyvista and VTK).
"""

from __future__ import annotations

import importlib.util
import warnings

import numpy as np

from .base import PeerMesh

NAME = "pyacvd"
KIND = "surface"
DESCRIPTION = "pyacvd clustering (ACVD) to exactly n vertices, input subdivided to >= 10 n points"
REQUIRES = ("pyacvd",)

#: The input is subdivided until it has this many points per output vertex.
OVERSAMPLE = 10


def available() -> bool:
    """Whether pyacvd is installed."""
    return importlib.util.find_spec("pyacvd") is not None


def remesh(V, F, n_vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """ACVD remesh of (V, F) with ``n_vertices`` clusters: (vertices, faces)."""
    import pyacvd
    import pyvista as pv

    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    with warnings.catch_warnings():  # pyvista's deprecation chatter is not ours to show
        warnings.simplefilter("ignore")
        c = pyacvd.Clustering(pv.PolyData(V, np.column_stack([np.full(len(F), 3), F]).ravel()))
        c.subdivide(next(k for k in range(12) if len(V) * 4**k >= OVERSAMPLE * n_vertices))
        c.cluster(int(n_vertices))
        out = c.create_mesh()
    return np.asarray(out.points, np.float64), np.asarray(out.faces).reshape(-1, 4)[:, 1:].astype(np.int64)


def mesh(patch, n_vertices: int) -> PeerMesh:
    """pyacvd remesh of ``patch`` (a ``(V, F)`` pair) with ``n_vertices`` clusters."""
    V, F = remesh(*patch, n_vertices)
    return PeerMesh(V, F, None, 1, {"parameter": "clusters (exact count)", "oversample": OVERSAMPLE})
