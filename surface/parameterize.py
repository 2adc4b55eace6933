"""Flattening a patch to the plane, checked for flips and overlaps.

Methods (all through :mod:`surface._igl`):

``"lscm"``
    least-squares conformal map, free boundary, two pinned boundary vertices.
    Angles are kept; areas are not (the *area scale* varies over a curved patch).
``"arap"``
    as-rigid-as-possible, started from LSCM: lengths are kept as well as
    possible, so the area scale stays closer to 1 but angles shear.
``"harmonic"``
    harmonic map onto a disk (one boundary loop only).  It flips triangles on
    non-round patches; then the next method is tried.

Every result is rescaled so that its UV area equals the 3-D area, centred on the
origin, and oriented so that the faces keep their input orientation
(counter-clockwise in UV).  It is then *checked*: no triangle may be flipped or
flat, every UV boundary loop must be simple, the loops must not cross, and the
triangles must cover the polygon the loops enclose exactly once (sum of triangle
areas equal to the polygon area, relative 1e-9).  A method that fails falls back
to the next in :data:`FALLBACKS`; when all fail,
:class:`~surface.errors.ParameterizationError` says why.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import shapely

from uniform2d.errors import InvalidArgumentError

from . import _igl
from .errors import ParameterizationError
from .patch import Patch

__all__ = ["Parameterization", "parameterize", "FALLBACKS", "jacobian_singular_values"]

log = logging.getLogger(__name__)

#: Methods tried, in order, for each requested method.
FALLBACKS = {
    "lscm": ("lscm", "arap"),
    "arap": ("arap",),
    "harmonic": ("harmonic", "lscm", "arap"),
}


@dataclasses.dataclass(frozen=True)
class Parameterization:
    """A checked, flip-free, non-overlapping map of a patch to the plane.

    Attributes
    ----------
    uv : (N, 2) float64
        Per-vertex coordinates; UV area equals 3-D area.
    method : str
        The method that produced ``uv``.
    attempts : tuple of (str, str)
        Every method tried, with ``"ok"`` or why it was rejected.
    area_scale : (M,) float64
        Per face UV area / 3-D area (1 everywhere for a developable patch).
    sigma : (M, 2) float64
        Singular values (largest first) of the per-face Jacobian 3-D -> UV.
    """

    uv: np.ndarray
    method: str
    attempts: tuple
    area_scale: np.ndarray
    sigma: np.ndarray

    def distortion(self, face_areas) -> dict:
        """Area-weighted distortion summary.

        Parameters
        ----------
        face_areas : (M,) float64
            3-D face areas (the weights).

        Returns
        -------
        dict
            ``method``, ``area_scale_min``/``max``, ``area_scale_ratio`` (max/min),
            ``conformal_mean``/``max`` (sigma1/sigma2, 1 for a conformal map),
            ``length_distortion_max`` (max over faces of max(sigma1, 1/sigma2)).
        """
        w = np.asarray(face_areas, dtype=np.float64)
        conf = self.sigma[:, 0] / self.sigma[:, 1]
        return {
            "method": self.method,
            "area_scale_min": float(self.area_scale.min()),
            "area_scale_max": float(self.area_scale.max()),
            "area_scale_ratio": float(self.area_scale.max() / self.area_scale.min()),
            "conformal_mean": float(np.sum(conf * w) / w.sum()),  # not BLAS: its sums are per CPU
            "conformal_max": float(conf.max()),
            "length_distortion_max": float(
                np.maximum(self.sigma[:, 0], 1.0 / self.sigma[:, 1]).max()
            ),
        }


def jacobian_singular_values(V, F, uv) -> np.ndarray:
    """Singular values of the linear map from each 3-D triangle to its UV image.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int
    uv : (N, 2) float64

    Returns
    -------
    (M, 2) float64
        ``[sigma1, sigma2]`` with sigma1 >= sigma2 >= 0; ``sigma1 * sigma2`` is the
        area scale.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> uv = np.array([[0, 0], [2, 0], [0, 0.5]])
    >>> jacobian_singular_values(V, np.array([[0, 1, 2]]), uv).tolist()
    [[2.0, 0.5]]
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    uv = np.asarray(uv, dtype=np.float64)
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    l1 = np.linalg.norm(e1, axis=1)
    x = e1 / l1[:, None]
    n = np.cross(e1, e2)
    y = np.cross(n / np.linalg.norm(n, axis=1)[:, None], x)
    # local 2-D coordinates of the triangle: (0,0), (l1, 0), (a, b)
    a = np.einsum("ij,ij->i", e2, x)
    b = np.einsum("ij,ij->i", e2, y)
    u1 = uv[F[:, 1]] - uv[F[:, 0]]
    u2 = uv[F[:, 2]] - uv[F[:, 0]]
    # J [l1 a; 0 b] = [u1 u2]  ->  J = [u1 u2] [[1/l1, -a/(l1 b)], [0, 1/b]]
    j11 = u1[:, 0] / l1
    j21 = u1[:, 1] / l1
    j12 = (u2[:, 0] - j11 * a) / b
    j22 = (u2[:, 1] - j21 * a) / b
    # closed-form singular values of a 2x2 matrix
    e = (j11 + j22) / 2
    f = (j11 - j22) / 2
    g = (j21 + j12) / 2
    h = (j21 - j12) / 2
    q = np.hypot(e, h)
    r = np.hypot(f, g)
    return np.stack([q + r, np.abs(q - r)], axis=1)


def _signed_areas(uv, F):
    p0, p1, p2 = uv[F[:, 0]], uv[F[:, 1]], uv[F[:, 2]]
    return 0.5 * (
        (p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1])
        - (p1[:, 1] - p0[:, 1]) * (p2[:, 0] - p0[:, 0])
    )


def _normalise(uv, F, area3d):
    """Orient (mirror if needed), rescale to the 3-D area and centre."""
    sa = _signed_areas(uv, F)
    if sa.sum() < 0:
        uv = uv * np.array([-1.0, 1.0])
        sa = -sa
    total = sa.sum()
    if not np.isfinite(total) or total <= 0:
        return None
    uv = uv * np.sqrt(area3d / total)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    return uv - (lo + hi) / 2


def check_map(patch: Patch, uv) -> str | None:
    """Why ``uv`` is not a valid embedding of ``patch`` (None if it is).

    Parameters
    ----------
    patch : Patch
    uv : (N, 2) float64
        Already oriented so that valid faces have positive signed area.

    Returns
    -------
    str or None
    """
    if not np.isfinite(uv).all():
        return "non-finite UV coordinates"
    F = patch.faces
    sa = _signed_areas(uv, F)
    scale = np.abs(sa).sum()
    bad = sa <= 1e-14 * scale
    if bad.any():
        return f"{int(bad.sum())} flipped or flat triangle(s) (first: face {int(np.flatnonzero(bad)[0])})"
    rings = [uv[lp] for lp in patch.boundary_loops]
    for i, r in enumerate(rings):
        if not shapely.LinearRing(r).is_simple:
            return f"boundary loop {i} overlaps itself in UV"
    areas = [shapely.Polygon(r).area for r in rings]
    k = int(np.argmax(areas))
    poly = shapely.Polygon(rings[k], [r for i, r in enumerate(rings) if i != k])
    if not poly.is_valid:
        return f"boundary loops cross or touch in UV ({shapely.is_valid_reason(poly)})"
    if abs(poly.area - scale) > 1e-9 * scale:
        return (
            f"the map covers part of the plane twice (triangle area {scale:.12g} "
            f"!= enclosed area {poly.area:.12g})"
        )
    return None


def _pins(patch: Patch):
    """Two boundary vertices far apart: the first loop's vertex farthest from its
    smallest-index vertex, and the one farthest from that (deterministic)."""
    loop = patch.boundary_loops[int(np.argmax([len(lp) for lp in patch.boundary_loops]))]
    P = patch.vertices[loop]
    i = int(np.argmax(np.linalg.norm(P - P[0], axis=1)))
    j = int(np.argmax(np.linalg.norm(P - P[i], axis=1)))
    return np.array([loop[i], loop[j]], dtype=np.int64)


def parameterize(patch: Patch, method: str = "lscm") -> Parameterization:
    """Flatten ``patch`` with ``method``, falling back as in :data:`FALLBACKS`.

    Parameters
    ----------
    patch : Patch
    method : {"lscm", "arap", "harmonic"}

    Returns
    -------
    Parameterization

    Raises
    ------
    ValueError
        For an unknown method name.
    ParameterizationError
        If every method in the fallback chain fails its check.
    """
    if method not in FALLBACKS:
        raise InvalidArgumentError(
            f"unknown parameterisation {method!r}; use one of {', '.join(FALLBACKS)}"
        )
    V, F = patch.vertices, patch.faces
    area3d = patch.area
    attempts = []
    cache = {}

    def run(name):
        if name in cache:
            return cache[name]
        if name == "lscm":
            uv = _normalise(_igl.lscm(V, F, _pins(patch)), F, area3d)
        elif name == "harmonic":
            if len(patch.boundary_loops) != 1:
                cache[name] = (None, "needs a patch without holes (one boundary loop)")
                return cache[name]
            uv = _normalise(_igl.harmonic_disk(V, F, patch.boundary_loops[0]), F, area3d)
        else:  # arap, started from the best flip-free map available
            init, why0 = run("lscm")
            if why0 is not None and len(patch.boundary_loops) == 1:
                h, why1 = run("harmonic")
                init = h if why1 is None else init
            if init is None:
                cache[name] = (None, "no usable initial map")
                return cache[name]
            uv = _normalise(_igl.arap(V, F, init, int(_pins(patch)[0])), F, area3d)
        why = "degenerate map (zero total area)" if uv is None else check_map(patch, uv)
        cache[name] = (uv, why)
        return cache[name]

    for name in FALLBACKS[method]:
        uv, why = run(name)
        attempts.append((name, why or "ok"))
        if why is None:
            if name != method:
                log.warning("%s parameterisation rejected (%s); used %s", method, attempts[0][1], name)
            sig = jacobian_singular_values(V, F, uv)
            uv.setflags(write=False)
            scale = sig[:, 0] * sig[:, 1]
            return Parameterization(uv, name, tuple(attempts), scale, sig)
        log.info("%s parameterisation rejected: %s", name, why)
    detail = "; ".join(f"{n}: {w}" for n, w in attempts)
    raise ParameterizationError(
        f"no valid flattening of the patch ({detail}); the patch is probably too curved "
        "to flatten without overlap — cut it into smaller, flatter pieces"
    )
