"""Target sizes: from a vertex count to an edge length and back, and the
compensation size field of a parameterisation.

**Count and size.**  A triangulation of a surface with Euler characteristic
``chi``, ``N`` vertices of which ``N_b`` on the boundary has ``F = 2N - N_b -
2 chi`` triangles.  With equilateral triangles of side ``h`` covering area ``A``
and ``N_b = B / h`` for a boundary of length ``B``::

    (sqrt(3)/2) (N - chi) h**2 - (sqrt(3)/4) B h - A = 0

:func:`target_size` solves this for ``h`` and :func:`vertex_count` for ``N``.

**Compensation.**  Where the parameterisation has area scale ``s`` (UV area / 3-D
area; after the global rescale its area-weighted mean is 1) a 3-D length ``l``
becomes ``sqrt(s) * l`` in UV (exactly so for a conformal map such as LSCM, whose
Jacobian is a scaled rotation).  A mesh that is uniform with edge ``h`` in 3-D is
therefore, in UV, a mesh of size ``h * sqrt(s)``: larger where the map magnifies
(``s > 1``), smaller where it shrinks.  Said the other way round, the UV size is
proportional to ``1 / sqrt(S)`` with ``S = 1 / s`` the 3-D/UV area ratio.
:func:`compensation_field` builds that size as a :class:`uniform2d.SizeField`;
:func:`size_variation` says whether it is worth it: on a developable patch the
map is (close to) an isometry, ``s`` is constant up to discretisation, and a
constant size is meshed faster without a field.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix

from uniform2d import libm
from uniform2d.errors import InvalidArgumentError
from uniform2d.geometry import vertex_count as vertex_count_for_size
from uniform2d.sizefield import SizeField

from . import _igl
from .lift import barycentric

__all__ = [
    "target_size", "vertex_count", "vertex_scale", "size_variation", "compensation_field"
]

_R3 = math.sqrt(3.0)


def target_size(area: float, perimeter: float, n_vertices: int, chi: int = 1) -> float:
    """Edge length of an equilateral mesh with ``n_vertices`` vertices.

    The estimate of :func:`uniform2d.geometry.size_for_count` (a patch of Euler
    characteristic ``chi`` counts like a polygon with ``1 - chi`` holes), solved
    for h rather than for 1/h.  It stays in this form because every surface mesh
    depends on its last bits.

    Examples
    --------
    >>> h = target_size(1.0, 4.0, 137)
    >>> round(h, 4), vertex_count(1.0, 4.0, h)
    (0.0998, 137)
    """
    a = _R3 / 2 * (n_vertices - chi)
    if a <= 0:
        raise InvalidArgumentError(f"n_vertices={n_vertices} is too small for a patch")
    b = _R3 / 4 * perimeter
    return (b + math.sqrt(b * b + 4 * a * area)) / (2 * a)


def vertex_count(area: float, perimeter: float, h: float, chi: int = 1) -> int:
    """Vertex count of an equilateral mesh of edge ``h`` (inverse of :func:`target_size`)."""
    if not h > 0:
        raise InvalidArgumentError(f"size must be positive, got {h}")
    return int(round(vertex_count_for_size(area, perimeter, h, 1 - chi)))


def vertex_scale(V, F, area_scale, smooth: int = 2) -> np.ndarray:
    """Per-vertex area scale: area-weighted geometric mean of the incident faces,
    then ``smooth`` rounds of averaging with the edge neighbours (in log scale).

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int
    area_scale : (M,) float64
        Per-face UV area / 3-D area.
    smooth : int

    Returns
    -------
    (N,) float64
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    w = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
    n = len(V)
    logs = libm.log(np.asarray(area_scale, dtype=np.float64))
    num = np.bincount(F.ravel(), weights=np.repeat(w * logs, 3), minlength=n)
    den = np.bincount(F.ravel(), weights=np.repeat(w, 3), minlength=n)
    lv = num / den
    if smooth:
        r = np.concatenate([F[:, 0], F[:, 1], F[:, 2], F[:, 1], F[:, 2], F[:, 0]])
        c = np.concatenate([F[:, 1], F[:, 2], F[:, 0], F[:, 0], F[:, 1], F[:, 2]])
        A = coo_matrix((np.ones(len(r)), (r, c)), shape=(n, n)).tocsr()
        A.data[:] = 1.0  # each neighbour once
        deg = np.asarray(A.sum(axis=1)).ravel()
        for _ in range(smooth):
            lv = 0.5 * lv + 0.5 * (A @ lv) / deg
    return libm.exp(lv)


def size_variation(scale) -> float:
    """How much the compensated size ``sqrt(s)`` varies: ``sqrt(max s / min s) - 1``.

    Parameters
    ----------
    scale : (N,) float64
        Per-vertex area scale (:func:`vertex_scale`).

    Examples
    --------
    >>> round(size_variation([1.0, 1.21, 1.1]), 12)
    0.1
    """
    s = np.asarray(scale, dtype=np.float64)
    return float(np.sqrt(s.max() / s.min()) - 1.0)


def compensation_field(
    V, F, uv, area_scale, h: float, *, resolution: int = 64, scale=None, size3d=None
) -> SizeField:
    """The UV size field ``h * sqrt(s)`` of a parameterisation.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int
    uv : (N, 2) float64
    area_scale : (M,) float64
        Per-face UV area / 3-D area.
    h : float
        Target 3-D edge length.
    resolution : int
        Grid nodes along the longer side of the UV bounding box.  The scale is
        smoothed, so a finer grid changes the meshes very little.
    scale : (N,) float64, optional
        The per-vertex scale if already computed (:func:`vertex_scale` of
        ``area_scale``).
    size3d : callable, optional
        A graded 3-D size (:class:`surface.size3d.Size3D`) in place of the constant
        ``h``: the field is then ``size3d(x) * sqrt(s)``, ``x`` the point of the
        surface the node maps to.

    Returns
    -------
    uniform2d.SizeField
        Sampled on a regular grid over the UV bounding box: each node is located
        in the UV mesh (nearest triangle for nodes outside it) and the smoothed
        per-vertex scale interpolated barycentrically there.
    """
    uv = np.asarray(uv, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    sv = vertex_scale(V, F, area_scale) if scale is None else np.asarray(scale, dtype=np.float64)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    ext = hi - lo
    step = ext.max() / (resolution - 1)
    pad = step
    nx = max(2, int(math.ceil((ext[0] + 2 * pad) / step)) + 1)
    ny = max(2, int(math.ceil((ext[1] + 2 * pad) / step)) + 1)
    gx = lo[0] - pad + step * np.arange(nx)
    gy = lo[1] - pad + step * np.arange(ny)
    X, Y = np.meshgrid(gx, gy)
    P = np.column_stack([X.ravel(), Y.ravel()])
    _, face, c = _igl.closest_faces(P, uv, F)
    bary = barycentric(c, uv[F[face, 0]], uv[F[face, 1]], uv[F[face, 2]])
    ls = (bary * libm.log(sv[F[face]])).sum(axis=1)
    if size3d is None:
        values = h * np.sqrt(libm.exp(ls)).reshape(ny, nx)
    else:
        V = np.asarray(V, dtype=np.float64)
        xyz = np.einsum("ki,kij->kj", bary, V[F[face]])
        values = (size3d(xyz) * np.sqrt(libm.exp(ls))).reshape(ny, nx)
    return SizeField(gx, gy, values)
