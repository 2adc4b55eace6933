"""The surface layer's adapter around pymeshlab: the cross-check and Hausdorff distances.

(MeshLab's own remeshing, a comparison baseline, is the peer
:mod:`uniform2d.peers.meshlab_peer`.)

Facts about pymeshlab 2025.7 this module relies on: meshes are stored in double
precision, so per-face edge lengths computed by MeshLab's muparser agree with
numpy to rounding; ``get_geometric_measures`` reports ``avg_edge_length`` and
``total_edge_length`` in double precision but ``surface_area`` in single
precision (not used for the cross-check); ``get_hausdorff_distance`` reports
single-precision distances.
"""

from __future__ import annotations

import numpy as np

import pymeshlab

__all__ = ["edge_measures", "hausdorff"]

_L = [
    "sqrt((x1-x0)^2+(y1-y0)^2+(z1-z0)^2)",
    "sqrt((x2-x1)^2+(y2-y1)^2+(z2-z1)^2)",
    "sqrt((x0-x2)^2+(y0-y2)^2+(z0-z2)^2)",
]
_FACE_MAX = f"max(max({_L[0]},{_L[1]}),{_L[2]})"
_FACE_MIN = f"min(min({_L[0]},{_L[1]}),{_L[2]})"


def _meshset(*meshes):
    ms = pymeshlab.MeshSet()
    for V, F in meshes:
        ms.add_mesh(
            pymeshlab.Mesh(
                vertex_matrix=np.ascontiguousarray(V, dtype=np.float64),
                face_matrix=np.ascontiguousarray(F, dtype=np.int32),
            )
        )
    return ms


def edge_measures(V, F) -> dict:
    """MeshLab's own edge measures of a triangle mesh.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int

    Returns
    -------
    dict
        ``n_edges`` (topological measures), ``avg_edge_length`` and
        ``total_edge_length`` (geometric measures), ``face_max`` / ``face_min``:
        (M,) longest / shortest edge per face (muparser per-face scalar), and
        ``max`` / ``min``: MeshLab's per-face scalar statistics of those.
    """
    ms = _meshset((V, F))
    geo = ms.get_geometric_measures()
    topo = ms.get_topological_measures()
    ms.compute_scalar_by_function_per_face(q=_FACE_MAX)
    face_max = np.array(ms.current_mesh().face_scalar_array(), dtype=np.float64)
    stats_max = ms.get_scalar_statistics_per_face()
    ms.compute_scalar_by_function_per_face(q=_FACE_MIN)
    face_min = np.array(ms.current_mesh().face_scalar_array(), dtype=np.float64)
    stats_min = ms.get_scalar_statistics_per_face()
    return {
        "n_edges": int(topo["edges_number"]),
        "avg_edge_length": float(geo["avg_edge_length"]),
        "total_edge_length": float(geo["total_edge_length"]),
        "max": float(stats_max["max"]),
        "min": float(stats_min["min"]),
        "face_max": face_max,
        "face_min": face_min,
    }


def hausdorff(Va, Fa, Vb, Fb, samples: int) -> dict:
    """One-sided Hausdorff distance from mesh a (sampled) to mesh b (target).

    Samples are a's vertices plus ``samples`` points on its faces (MeshLab's
    Montecarlo face sampling, fixed seed).

    Returns
    -------
    dict
        ``max``, ``mean``, ``rms`` and ``n_samples``.
    """
    ms = _meshset((Va, Fa), (Vb, Fb))
    diag = float(np.linalg.norm(np.ptp(np.vstack([Va, Vb]), axis=0)))
    r = ms.get_hausdorff_distance(
        sampledmesh=0,
        targetmesh=1,
        samplevert=True,
        sampleface=True,
        samplenum=int(samples),
        maxdist=pymeshlab.PureValue(2.0 * diag),
    )
    return {
        "max": float(r["max"]),
        "mean": float(r["mean"]),
        "rms": float(r["RMS"]),
        "n_samples": int(r["n_samples"]),
    }
