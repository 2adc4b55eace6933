"""Lifting points of the parameter plane back onto the 3-D patch.

An interior point is located in the UV triangulation of the patch (the UV
triangle containing it, or the nearest one for a point a rounding error
outside), and its 3-D position is the same barycentric combination of that
triangle's 3-D corners — so it lies on the input surface, up to rounding.
Boundary points are not lifted here: they are interpolated along their input
boundary edge (see :mod:`surface.domain`), so they land exactly on it.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from . import _igl

__all__ = ["Lifted", "lift", "barycentric"]


def barycentric(p, a, b, c, *, clamp: bool = True) -> np.ndarray:
    """Barycentric coordinates (K, 3) of 2-D points p in triangles (a, b, c),
    clamped to the triangle (negative parts set to 0, then renormalised).

    Parameters
    ----------
    p, a, b, c : (K, 2) float64
    clamp : bool
        With False, the plain coordinates: some are negative for a point outside.

    Examples
    --------
    >>> import numpy as np
    >>> a, b, c = np.array([[0., 0]]), np.array([[1., 0]]), np.array([[0., 1]])
    >>> barycentric(np.array([[0.25, 0.25]]), a, b, c).tolist()
    [[0.5, 0.25, 0.25]]
    >>> barycentric(np.array([[1.0, 0.5]]), a, b, c, clamp=False).tolist()   # outside
    [[-0.5, 1.0, 0.5]]
    """
    v0 = b - a
    v1 = c - a
    v2 = p - a
    d = v0[:, 0] * v1[:, 1] - v0[:, 1] * v1[:, 0]
    l1 = (v2[:, 0] * v1[:, 1] - v2[:, 1] * v1[:, 0]) / d
    l2 = (v0[:, 0] * v2[:, 1] - v0[:, 1] * v2[:, 0]) / d
    out = np.stack([1.0 - l1 - l2, l1, l2], axis=1)
    if not clamp:
        return out
    out = np.clip(out, 0.0, None)
    return out / out.sum(axis=1, keepdims=True)


@dataclasses.dataclass(frozen=True)
class Lifted:
    """Points lifted to 3-D.

    Attributes
    ----------
    xyz : (K, 3) float64
        3-D positions on the input surface.
    face : (K,) int64
        Input face holding each point.
    bary : (K, 3) float64
        Barycentric coordinates in that face.
    uv_distance : (K,) float64
        Distance in UV from the point to the UV triangulation (0 inside it).
    """

    xyz: np.ndarray
    face: np.ndarray
    bary: np.ndarray
    uv_distance: np.ndarray


def lift(points, V, F, uv) -> Lifted:
    """Lift 2-D points through a parameterisation.

    Parameters
    ----------
    points : (K, 2) float64
        Points of the parameter plane.
    V : (N, 3) float64
        Patch vertices.
    F : (M, 3) int
        Patch faces.
    uv : (N, 2) float64
        The parameterisation.

    Returns
    -------
    Lifted
    """
    P = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    uv = np.asarray(uv, dtype=np.float64)
    if len(P) == 0:
        return Lifted(np.zeros((0, 3)), np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0))
    d2, face, c = _igl.closest_faces(P, uv, F)
    tri = F[face]
    bary = barycentric(P, uv[tri[:, 0]], uv[tri[:, 1]], uv[tri[:, 2]])
    xyz = np.einsum("ki,kij->kj", bary, V[tri])
    return Lifted(xyz, face, bary, np.sqrt(d2))
