"""A graded 3-D size for :func:`surface.remesh`: ``size=h`` with ``h`` a callable.

``h(points)`` takes a (k, 3) float64 array of points on the surface and returns
(k,) positive 3-D edge lengths.  :class:`Size3D` holds it with a scale ``c``:
the remesh aims at edges of 3-D length ``c h(midpoint)``.

**Count.**  As for a constant size (:mod:`surface.sizing`), a mesh of
equilateral triangles whose side follows ``c h`` on a surface of Euler
characteristic ``chi`` has about::

    N - chi = I_A / c**2 + I_B / c,
    I_A = ∫ dA / ((sqrt(3)/2) h**2),   I_B = ∮ ds / (2 h)

vertices (:func:`integrals` evaluates both on the input mesh, ``h`` at the
three edge midpoints of every face and at the midpoint of every boundary edge).
With a vertex count the remesh keeps ``h``'s shape and takes the ``c`` that
solves this for it (:func:`scale_for_count`; the vertex count is then exact, ``c``
only sets how many of the points go on the boundary and seams); without one
``c = 1`` and the count follows (:func:`count_for_size`).
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from uniform2d.errors import InvalidArgumentError
from uniform2d.grading import evaluate_size

__all__ = ["Size3D", "as_size3d", "count_for_size", "integrals", "q_stats", "scale_for_count"]

_AREA_PER_VERTEX = math.sqrt(3.0) / 2.0  # of an equilateral mesh of unit edge


class Size3D:
    """A 3-D size callable ``h`` times a scale ``c``, checked on every call.

    Parameters
    ----------
    h : callable
        ``h(points (k, 3)) -> (k,)`` finite positive sizes.
    scale : float
    counts : tuple, optional
        ``(I_A, I_B, chi)`` of the surface (:func:`integrals`), kept for the scale
        search.

    Examples
    --------
    >>> s = Size3D(lambda p: 1.0 + p[:, 0], 0.5)
    >>> s([[0.0, 0, 0], [2.0, 0, 0]]).tolist()
    [0.5, 1.5]
    >>> Size3D(lambda p: p[:, 0], 1.0)([[-1.0, 2, 3]])
    Traceback (most recent call last):
    ...
    uniform2d.errors.InvalidArgumentError: the size is -1.0 at (-1, 2, 3) on the surface; a size callable must return finite positive 3-D lengths everywhere on it
    """

    def __init__(self, h, scale: float = 1.0, counts=None):
        self.h = h
        self.scale = float(scale)
        self.counts = counts

    def scaled(self, c: float) -> Size3D:
        """The same shape at scale ``c``."""
        return Size3D(self.h, c, self.counts)

    def shape(self) -> Size3D:
        """The same shape at scale 1."""
        return self.scaled(1.0)

    def spacing_for(self, n_vertices: int) -> float:
        """The scale at which the surface takes ``n_vertices`` vertices."""
        ia, ib, chi = self.counts
        return scale_for_count(n_vertices, chi, ia, ib)

    def edge_q(self, xyz, edges) -> np.ndarray:
        """q of every edge: 3-D length over the size at its midpoint, (E,)."""
        xyz = np.asarray(xyz, dtype=np.float64)
        a, b = xyz[edges[:, 0]], xyz[edges[:, 1]]
        return np.linalg.norm(b - a, axis=1) / self(0.5 * (a + b))

    def __call__(self, points) -> np.ndarray:
        P = np.array(points, dtype=np.float64).reshape(-1, 3)
        v = evaluate_size(self.h, P, "points on the surface")
        bad = ~(np.isfinite(v) & (v > 0))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            p = ", ".join(f"{x:.6g}" for x in P[i])
            raise InvalidArgumentError(
                f"the size is {float(v[i])!r} at ({p}) on the surface; a size callable must "
                "return finite positive 3-D lengths everywhere on it"
            )
        return self.scale * v


def as_size3d(size):
    """``size`` as a :class:`Size3D` if it is a callable, else None (a number or None)."""
    if size is None or isinstance(size, numbers.Real):
        return None
    if isinstance(size, Size3D):
        return size
    if not callable(size):
        raise InvalidArgumentError(
            f"size must be a positive length or a callable h(points (k, 3)) -> (k,) sizes; "
            f"got {type(size).__name__}"
        )
    return Size3D(size)


def integrals(V, F, loops, size) -> tuple[float, float]:
    """``(I_A, I_B)`` of the module notes for the size ``size`` on the mesh ``(V, F)``
    with boundary ``loops``.

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    >>> F = np.array([[0, 1, 2], [0, 2, 3]])
    >>> ia, ib = integrals(V, F, [np.array([0, 1, 2, 3])], Size3D(lambda p: np.full(len(p), 0.5)))
    >>> round(ia, 6), round(ib, 6)
    (4.618802, 4.0)
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    mids = np.concatenate([0.5 * (V[F[:, i]] + V[F[:, (i + 1) % 3]]) for i in range(3)])
    inv2 = (1.0 / size(mids) ** 2).reshape(3, -1).mean(axis=0)  # exact for quadratics
    # a pairwise sum, not np.dot: BLAS's kernel for the CPU sums in its own order
    ia = float(np.sum(area * inv2)) / _AREA_PER_VERTEX
    ib = 0.0
    for lp in loops:
        a, b = V[lp], V[np.roll(lp, -1)]
        ib += float(np.sum(np.linalg.norm(b - a, axis=1) / size(0.5 * (a + b)))) / 2.0
    return ia, ib


def scale_for_count(n_vertices: int, chi: int, ia: float, ib: float) -> float:
    """The scale ``c`` with ``n_vertices - chi = ia / c**2 + ib / c``.

    Examples
    --------
    >>> c = scale_for_count(137, 1, 100.0, 20.0)
    >>> round(100.0 / c**2 + 20.0 / c, 9)
    136.0
    """
    m = n_vertices - chi
    if m <= 0:
        raise InvalidArgumentError(f"n_vertices={n_vertices} is too small for this surface")
    x = (-ib + math.sqrt(ib * ib + 4.0 * ia * m)) / (2.0 * ia)  # x = 1 / c
    return 1.0 / x


def count_for_size(chi: int, ia: float, ib: float) -> int:
    """The vertex count at scale 1: ``round(chi + ia + ib)``."""
    return round(chi + ia + ib)


def q_stats(q) -> dict:
    """Relative uniformity of edges ``q`` (length / size): min, max, mean, ratio, cv.

    Examples
    --------
    >>> q_stats(np.array([0.9, 1.0, 1.1]))["q_ratio"]
    1.2222222222222223
    """
    q = np.asarray(q, dtype=np.float64)
    return {"q_min": float(q.min()), "q_max": float(q.max()), "q_mean": float(q.mean()),
            "q_ratio": float(q.max() / q.min()), "q_cv": float(q.std() / q.mean())}
