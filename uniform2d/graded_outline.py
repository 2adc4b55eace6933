"""A polygon's rings resampled at a size field's local spacing, for a graded mesh of n points.

``uniform_mesh(polygon, n, size=field, resample=tol)`` runs :func:`resample_for_field`
then :func:`uniform2d.graded.graded_mesh` on the resampled polygon.  The rings are
sampled as :func:`uniform2d.outline.resample_polygon` samples them, with the arc
length replaced by ``∫ ds / h``: consecutive boundary points have the same
``∫ ds / (s h)`` (one piece), s the scale the graded path chooses for the
resampled polygon and n (:func:`uniform2d.grading.scale_for_count`), found by
iterating since the resampled boundary changes the count.  Corners, and ring
vertices a segment or fixed point touches, stay (the kept vertices, V); the
other boundary points count in n.  Every input vertex lies within ``tol`` x the
*finest* local spacing on the rings of the ring edge spanning it, and every
boundary point is on the outline, so the Hausdorff distance between rings and
outline is at most ``tol`` x the local spacing everywhere.  Unlike the uniform
resample, every polygon is resampled (a ring of edges 1.1 local spacings long is
what keeps q at 1.1 there), narrow features are not widened, and a multi-edge
run's input edges are weighted by their mean ``1 / h`` (a point is placed
evenly in length within one input edge).
"""

from __future__ import annotations

import math

import numpy as np

from .grading import field_integrals, scale_for_count
from .outline import CORNER_ANGLE, Resampled, resample_weighted
from .polygon import Polygon
from .sizefield import SizeField

__all__ = ["resample_for_field"]

#: Samples of the field along each ring edge for its mean 1 / h.
EDGE_SAMPLES = 8
#: Scale iterations (the resampled boundary changes the vertex count, hence s).
ITERATIONS = 6


def resample_for_field(polygon: Polygon, n: int, field: SizeField, *, tolerance: float,
                       corner_angle: float = CORNER_ANGLE) -> tuple[Resampled, int, tuple]:
    """Resample ``polygon``'s rings at the local spacing ``s h`` of ``field`` for n Steiner points.

    Returns
    -------
    Resampled
        ``spacing`` is the finest local spacing on the rings, s x min h (the
        tolerance and ``deviation_fraction`` are relative to it).
    int
        The Steiner points left for the mesher: n minus the resampled boundary points.
    tuple
        :func:`uniform2d.grading.field_integrals` of the resampled polygon (the
        scale s follows from them, as in :func:`uniform2d.graded.graded_mesh`).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon, SizeField
    >>> t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    >>> disk = Polygon(np.c_[np.cos(t), np.sin(t)])
    >>> f = SizeField([-1, 1], [-1, 1], [[1.0, 3.0], [1.0, 3.0]])
    >>> r, left, _ = resample_for_field(disk, 300, f, tolerance=0.25)
    >>> r.n_kept, r.n_boundary + left, r.deviation <= 0.25 * r.spacing
    (0, 300, True)
    """
    weights, hmin = _inverse_sizes(polygon, field)
    integrals = field_integrals(polygon, field)
    s = scale_for_count(polygon, field, n, integrals)
    seen = set()
    for _ in range(ITERATIONS):
        r = resample_weighted(polygon, s * hmin, tolerance, corner_angle,
                              [w * hmin for w in weights])
        integrals = field_integrals(r.polygon, field)
        s_next = scale_for_count(r.polygon, field, max(n - r.n_boundary, 1), integrals)
        key = (r.n_kept, r.n_boundary)
        if key in seen or not math.isfinite(s_next) or abs(s_next - s) <= 1e-3 * s:
            break  # the same boundary count again: s is the graded path's for it
        seen.add(key)
        s = s_next
    return r, n - r.n_boundary, integrals


def _inverse_sizes(polygon: Polygon, field: SizeField):
    """(per ring, the mean 1 / h on each edge (k,)), and the smallest h sampled."""
    t = (np.arange(EDGE_SAMPLES) + 0.5) / EDGE_SAMPLES
    out, hmin = [], math.inf
    for ring in polygon.rings:
        d = np.roll(ring, -1, axis=0) - ring
        P = ring[:, None, :] + t[None, :, None] * d[:, None, :]
        h = field(np.concatenate([P.reshape(-1, 2), ring])).astype(np.float64)
        hmin = min(hmin, float(h.min()))
        out.append((1.0 / h[:-len(ring)]).reshape(len(ring), EDGE_SAMPLES).mean(axis=1))
    return out, hmin
