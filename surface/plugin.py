"""The surface layer as uniform2d's command line and report see it.

Registered under the entry-point group ``uniform2d.patches`` (see
:mod:`uniform2d.plugins` for what this module provides and why).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uniform2d.errors import UnsupportedFormatError

from . import _igl
from ._figures import plot_result
from .io import WRITE_FORMATS, read_model, read_patch, suffix
from .measure import edge_stats, face_edge_lengths, unique_edges
from .remesh import remesh

__all__ = [
    "read_patch", "read_model", "remesh", "WRITE_FORMATS", "check_output", "measures", "deviation", "plot_result",
    "warm_up",
]


def check_output(path) -> None:
    """UnsupportedFormatError unless :func:`surface.write_patch` can write ``path``."""
    if suffix(Path(path)) not in WRITE_FORMATS:
        raise UnsupportedFormatError(
            f"cannot write a surface mesh to '{path}'; use one of "
            + ", ".join("." + e for e in WRITE_FORMATS)
        )


def _samples(V, F) -> np.ndarray:
    """Vertices, edge midpoints and face centroids of a mesh (deterministic samples)."""
    E = unique_edges(F)
    return np.vstack([V, 0.5 * (V[E[:, 0]] + V[E[:, 1]]), V[F].mean(axis=1)])


def deviation(V, F, V0, F0) -> tuple[float, float]:
    """Two-sided distance between a remesh (V, F) and its input (V0, F0).

    Each mesh is sampled at its vertices, edge midpoints and face centroids and
    the exact point-to-mesh distance to the other mesh is taken (libigl), so the
    result is deterministic (MeshLab's Hausdorff filter samples randomly, with a
    state that carries over between calls).

    Returns
    -------
    out_in, in_out : float
        Largest distance from the output's samples to the input, and back.
    """
    d_oi, _, _ = _igl.closest_points(_samples(V, F), V0, F0)
    d_io, _, _ = _igl.closest_points(_samples(V0, F0), V, F)
    return float(np.sqrt(d_oi.max())), float(np.sqrt(d_io.max()))


def _f(x):
    return float(x) if x is not None and np.isfinite(x) else None


def measures(V, F, V0, F0) -> dict:
    """Table measures of a surface mesh (V, F) remeshing the input (V0, F0).

    Edge statistics are 3-D (:func:`surface.measure.edge_stats`); the largest
    perimeter is the largest sum of a face's three edges; the deviation from
    the input is :func:`deviation` (a two-sided Hausdorff distance on
    deterministic samples), also relative to the input's bounding-box diagonal.
    No certified factors: uniform2d's bounds are planar.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    V0 = np.asarray(V0, dtype=np.float64)
    F0 = np.asarray(F0, dtype=np.int64)
    s = edge_stats(V, F)
    diag = float(np.linalg.norm(np.ptp(V0, axis=0)))
    h1, h2 = deviation(V, F, V0, F0)
    hmax = max(h1, h2)
    return {
        "n_vertices": int(len(V)),
        "n_triangles": int(len(F)),
        "edge_ratio": _f(s["ratio"]),
        "longest_edge": _f(s["max"]),
        "max_perimeter": _f(float(face_edge_lengths(V, F).sum(axis=1).max())),
        "factor_longest_edge": None,
        "factor_perimeter": None,
        "factor_edge_ratio": None,
        "min_angle": _f(s["angle_min"]),
        "cv_edge": _f(s["cv"]),
        "hausdorff_out_in": h1,
        "hausdorff_in_out": h2,
        "hausdorff_max": hmax,
        "hausdorff_max_rel": hmax / diag if diag > 0 else None,
    }


def warm_up() -> None:
    """Remesh a small curved patch, so that every kernel a remesh uses is loaded."""
    u = np.linspace(0.0, 1.0, 7)
    x, y = (a.ravel() for a in np.meshgrid(u, u))
    V = np.column_stack([x, y, 0.3 * (x * x + y * y)])  # curved: a graded mesh
    q = np.arange(36).reshape(6, 6) + np.arange(6)[:, None]  # lower-left corners
    a, b, c, d = q.ravel(), q.ravel() + 1, q.ravel() + 8, q.ravel() + 7
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    remesh((V, F), 60, check=False, hausdorff=False)
