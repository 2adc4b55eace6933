"""Target-size fields for graded insertion.

A :class:`SizeField` is a positive function h(x, y) sampled on a regular grid
and interpolated bilinearly.  Given one, Algorithm INSERT ranks candidates by
``distance / h(candidate)`` instead of by distance, so points are placed densely
where h is small.  With a constant h the ranking, and therefore the whole
sequence, is exactly the paper's (a constant factor changes no comparison).

The surface layer uses it to compensate the area distortion of a conformal
parameterisation: a mesh uniform in 3-D is, in the parameter plane, a mesh whose
size follows 1 / sqrt(local area scale).
"""

from __future__ import annotations

import numpy as np

from .errors import InvalidArgumentError

__all__ = ["SizeField"]


class SizeField:
    """A positive size function on a regular grid, bilinearly interpolated.

    Parameters
    ----------
    x : array_like, shape (nx,)
        Strictly increasing grid abscissae, nx >= 2.
    y : array_like, shape (ny,)
        Strictly increasing grid ordinates, ny >= 2.
    values : array_like, shape (ny, nx)
        Positive finite sizes at the grid nodes; ``values[j, i]`` is h(x[i], y[j]).
        Outside the grid the nearest grid value is used (clamping).

    Examples
    --------
    >>> f = SizeField([0, 1], [0, 1], [[1.0, 2.0], [1.0, 2.0]])
    >>> f([[0.5, 0.5], [2.0, 0.0]]).tolist()
    [1.5, 2.0]
    """

    __slots__ = ("x", "y", "values")

    def __init__(self, x, y, values):
        x = np.array(x, dtype=np.float64)
        y = np.array(y, dtype=np.float64)
        v = np.array(values, dtype=np.float64)
        if x.ndim != 1 or y.ndim != 1 or len(x) < 2 or len(y) < 2:
            raise InvalidArgumentError(
                "SizeField: x and y must be 1-D with at least 2 entries each"
            )
        if not (np.all(np.diff(x) > 0) and np.all(np.diff(y) > 0)):
            raise InvalidArgumentError("SizeField: x and y must be strictly increasing")
        if v.shape != (len(y), len(x)):
            raise InvalidArgumentError(
                f"SizeField: values must have shape (len(y), len(x)) = {(len(y), len(x))}, "
                f"got {v.shape}"
            )
        if not (np.all(np.isfinite(v)) and np.all(v > 0)):
            raise InvalidArgumentError("SizeField: values must be finite and strictly positive")
        for a in (x, y, v):
            a.setflags(write=False)
        self.x, self.y, self.values = x, y, v

    @classmethod
    def constant(cls, bounds, h=1.0) -> "SizeField":
        """A constant field over ``bounds = (xmin, ymin, xmax, ymax)``."""
        xmin, ymin, xmax, ymax = bounds
        return cls([xmin, xmax], [ymin, ymax], np.full((2, 2), float(h)))

    def __call__(self, points) -> np.ndarray:
        """Evaluate at points (K, 2) float64 -> (K,) float64."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        return _bilinear(self.x, self.y, self.values, p[:, 0], p[:, 1])

    def with_gradient(self, points) -> tuple[np.ndarray, np.ndarray]:
        """(values (K,), gradient (K, 2)) at points (K, 2): the values are
        :meth:`__call__`'s, the gradient the bilinear interpolation's in the
        point's cell (0 along an axis where the point is clamped to the grid).

        Examples
        --------
        >>> f = SizeField([0, 2], [0, 1], [[1.0, 3.0], [1.0, 3.0]])
        >>> h, g = f.with_gradient([(1.0, 0.5), (5.0, 0.5)])
        >>> h.tolist(), g.tolist()
        ([2.0, 3.0], [[1.0, 0.0], [0.0, 0.0]])
        """
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        gx, gy, v = self.x, self.y, self.values
        i, j, tx, ty = _cells(gx, gy, p[:, 0], p[:, 1])
        v00, v10, v01, v11 = v[j, i], v[j, i + 1], v[j + 1, i], v[j + 1, i + 1]
        inx = (p[:, 0] > gx[0]) & (p[:, 0] < gx[-1])
        iny = (p[:, 1] > gy[0]) & (p[:, 1] < gy[-1])
        dx = ((v10 - v00) * (1 - ty) + (v11 - v01) * ty) / (gx[i + 1] - gx[i]) * inx
        dy = ((v01 - v00) * (1 - tx) + (v11 - v10) * tx) / (gy[j + 1] - gy[j]) * iny
        return _bilinear(gx, gy, v, p[:, 0], p[:, 1]), np.stack([dx, dy], axis=1)

    def scaled(self, factor: float) -> "SizeField":
        """The same field with every size multiplied by ``factor`` (> 0)."""
        return SizeField(self.x, self.y, self.values * float(factor))

    def transformed(self, scale: float, offset) -> "SizeField":
        """The field of the mapped domain ``x' = scale * x + offset`` (sizes scale too)."""
        off = np.asarray(offset, dtype=np.float64)
        return SizeField(self.x * scale + off[0], self.y * scale + off[1], self.values * scale)


def _bilinear(gx, gy, v, px, py):
    """Bilinear interpolation of the grid (gx, gy, v) at the points (px, py), clamped.

    The kernel's ``uniform2d._kernel.rank.size_at`` is the same formula for
    one point inside compiled loops (where this vectorised numpy version cannot
    run); the two must stay the same formula, so that the sizes the kernel works
    with are the field's values.
    """
    i, j, tx, ty = _cells(gx, gy, px, py)
    return (
        v[j, i] * (1 - tx) * (1 - ty)
        + v[j, i + 1] * tx * (1 - ty)
        + v[j + 1, i] * (1 - tx) * ty
        + v[j + 1, i + 1] * tx * ty
    )


def _cells(gx, gy, px, py):
    """(i, j, tx, ty): each point's grid cell and its place in it (0..1 each way),
    the points clamped to the grid."""
    px = np.clip(px, gx[0], gx[-1])
    py = np.clip(py, gy[0], gy[-1])
    i = np.clip(np.searchsorted(gx, px, side="right") - 1, 0, len(gx) - 2)
    j = np.clip(np.searchsorted(gy, py, side="right") - 1, 0, len(gy) - 2)
    return i, j, (px - gx[i]) / (gx[i + 1] - gx[i]), (py - gy[j]) / (gy[j + 1] - gy[j])
