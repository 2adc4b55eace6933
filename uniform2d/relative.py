"""Uniformity relative to a size field: the measures of a graded mesh.

A graded mesh follows a size field h; what "uniform" means for it is that every
edge has the same length *relative to h*.  The one quantity measured is

    q = edge length / h(edge midpoint),

and :func:`relative_measures` reports max q / min q (the relative edge ratio), the
coefficient of variation of q, its mean (how well the scale of h was met), and the
largest triangle relative to h: the largest ``area / (√3/4 h(centroid)²)``, the
area of an equilateral triangle of side h being 1.  For a constant h these are the
absolute edge ratio and CV, and the largest triangle over the equilateral one.

The optimiser (:mod:`uniform2d.optimize`) measures an edge against
``(h(a) + h(b)) / 2``, the mean of its end points' sizes, which is h at the
midpoint up to the field's curvature; the figures here use h(midpoint) itself.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from .measures import as_points, as_triangles, edge_lengths

__all__ = ["RelativeQuality", "relative_measures"]


@dataclass(frozen=True)
class RelativeQuality:
    """The measures of a mesh relative to a size field h (see the module docstring)."""

    q_ratio: float  # max q / min q, q = edge length / h(midpoint)
    q_cv: float  # standard deviation of q over its mean
    q_mean: float  # mean q (1 when the mesh has the field's scale)
    q_min: float
    q_max: float
    max_area: float  # largest triangle area / (sqrt(3)/4 h(centroid)**2)

    def to_dict(self) -> dict:
        return {k: float(v) for k, v in asdict(self).items()}

    def summary(self) -> list[str]:
        g = "{:.4g}".format
        return [
            "Relative to the size field h (q = edge length / h(midpoint))",
            (f"  q: min {g(self.q_min)}   max {g(self.q_max)}   max/min {g(self.q_ratio)}"
            f"   mean {g(self.q_mean)}   CV {g(self.q_cv)}"),
            f"  Largest triangle / equilateral of side h: {g(self.max_area)}",
        ]


def relative_measures(points, triangles, size) -> RelativeQuality:
    """Measure a mesh against a size field.

    Parameters
    ----------
    points : array_like, shape (N, 2)
    triangles : array_like, shape (M, 3)
    size : callable
        ``size(points (k, 2)) -> (k,)`` positive sizes (a :class:`~uniform2d.SizeField`).

    Examples
    --------
    >>> from uniform2d import SizeField
    >>> f = SizeField([0, 2], [0, 1], [[1.0, 1.0], [1.0, 1.0]])
    >>> r = relative_measures([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)], f)
    >>> round(r.q_ratio, 4), round(r.max_area, 4)
    (1.4142, 1.1547)
    """
    pts = as_points(points)
    tri = as_triangles(triangles, len(pts))
    edges, lengths = edge_lengths(pts, tri)
    q = lengths / np.asarray(size(0.5 * (pts[edges[:, 0]] + pts[edges[:, 1]])), dtype=np.float64)
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    hc = np.asarray(size((a + b + c) / 3.0), dtype=np.float64)
    mean = float(q.mean())
    return RelativeQuality(
        q_ratio=float(q.max() / q.min()), q_cv=float(q.std() / mean), q_mean=mean,
        q_min=float(q.min()), q_max=float(q.max()),
        max_area=float(np.max(area / (math.sqrt(3) / 4 * hc**2))),
    )
