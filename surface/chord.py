"""How far the interior of a mesh of a given edge length deviates from the patch anyway.

The boundary of the domain is refined only where it would deviate from the
input more than the interior does (:func:`surface.domain.boundary_domain`);
this is the interior's measure.
"""

from __future__ import annotations

import numpy as np

from uniform2d.geometry import point_segment_distance

from . import _igl
from .lift import barycentric
from .locate import walk
from .patch import Patch
from .sizing import vertex_scale

__all__ = ["interior_chord_error", "PLANAR"]

#: A patch whose vertices all lie within this fraction of its bounding-box
#: diagonal from their best-fitting plane is planar: its interior chord error is 0.
PLANAR = 1e-12


def interior_chord_error(patch: Patch, uv, h: float, area_scale=None) -> float:
    """The deviation from the input that the interior of an ``h``-mesh has anyway.

    At every interior vertex ``p`` of the input, three chords through ``p`` (along
    0, 60 and 120 degrees in the parameter plane, the directions of a hexagonal
    lattice) whose ends are a 3-D distance of about ``h / 2`` from ``p`` (UV
    half-length ``h / 2 * sqrt(s)``, ``s`` the smoothed area scale at ``p``), the
    ends placed on the input surface through the map (chords with an end outside
    the parameter domain are left out).  Returns the largest distance of such a
    ``p`` from its chords: the chord error of an interior edge of length ``h``,
    the input's own tessellation included (the ends lie on input faces, ``p`` is
    an input vertex, so a crease between input faces counts like curvature).

    Parameters
    ----------
    patch : Patch
    uv : (N, 2) float64
        The parameterisation (faces counter-clockwise).
    h : float
        Edge length of the mesh.
    area_scale : (M,) float64, optional
        Per-face UV area / 3-D area (default: from ``uv``).

    Returns
    -------
    float
        A 3-D length (0 for a planar patch).
    """
    V, F = patch.vertices, patch.faces
    X = V - V.mean(axis=0)
    normal = np.linalg.eigh(X.T @ X)[1][:, 0]  # of the best-fitting plane
    if np.abs(X @ normal).max() <= PLANAR * np.linalg.norm(np.ptp(V, axis=0)):
        return 0.0  # planar: chords lie in the surface (this skips 6 point locations per vertex)
    uv = np.asarray(uv, dtype=np.float64)
    if area_scale is None:
        e1, e2 = uv[F[:, 1]] - uv[F[:, 0]], uv[F[:, 2]] - uv[F[:, 0]]
        area_scale = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) / patch.face_areas
    inner = np.ones(len(V), dtype=bool)
    for lp in patch.boundary_loops:
        inner[lp] = False
    idx = np.flatnonzero(inner)
    if len(idx) == 0:
        return 0.0
    r = 0.5 * h * np.sqrt(vertex_scale(V, F, area_scale)[idx])
    ang = np.radians([0.0, 60.0, 120.0])
    d = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    ends = uv[idx][:, None, None, :] + np.stack([d, -d])[None] * r[:, None, None, None]
    q = ends.reshape(-1, 2)
    # walk from a face at each end's own vertex; a tree search where that fails
    at = np.empty(len(V), dtype=np.int64)
    at[F.ravel()] = np.repeat(np.arange(len(F)), 3)
    F64 = np.asarray(F, dtype=np.int64)
    face = walk(q, np.repeat(at[idx], 6), uv, F64, _igl.face_neighbours(F64))
    lost = face < 0
    if lost.any():
        face[lost] = _igl.closest_faces(q[lost], uv, F)[1]
    tri = F[face]
    bary = barycentric(q, uv[tri[:, 0]], uv[tri[:, 1]], uv[tri[:, 2]], clamp=False)
    X = np.einsum("ki,kij->kj", bary, V[tri]).reshape(len(idx), 2, 3, 3)
    # chords with an end outside the parameter domain (near the boundary) are skipped
    inside = (bary.min(axis=1) >= 0).reshape(len(idx), 2, 3).all(axis=1).ravel()
    if not inside.any():
        return 0.0
    A, B = X[:, 0].reshape(-1, 3)[inside], X[:, 1].reshape(-1, 3)[inside]
    P = np.repeat(V[idx], 3, axis=0)[inside]
    return float(point_segment_distance(P, A, B).max())
