"""Weighted Lloyd iterations (uniform2d.optimize.lloyd): the density's power decides
how the cells follow the size (a centroidal Voronoi tessellation of density ρ has
cells of diameter about ρ^(-1/4)), checked on the triangulation of the result."""

from __future__ import annotations

import numpy as np

from uniform2d import Polygon, SizeField
from uniform2d.geometry import unique_edges
from uniform2d.insert import insert
from uniform2d.optimize.lloyd import weighted_lloyd
from uniform2d.triangulation import triangulate

STRIP = Polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
ITER = 400  # Lloyd redistributes over long distances slowly
FIELD = SizeField([0, 4], [0, 1], [[0.05, 0.45], [0.05, 0.45]])  # h = 0.05 + 0.1 x


def _slope(power: int) -> float:
    """Least-squares slope of log(edge length / h(midpoint)) against log h over the
    interior edges after Lloyd: 0 when the cells follow h."""
    start = insert(STRIP, 400, size=FIELD).points[len(STRIP.vertices):]
    on = (start[:, 1] <= 0) | (start[:, 1] >= 1) | (start[:, 0] <= 0) | (start[:, 0] >= 4)
    moved = weighted_lloyd(STRIP, start, on, FIELD, iterations=ITER, omega=1.8, power=power)
    assert np.array_equal(moved[on], start[on])
    P, T = triangulate(STRIP, moved, None)
    E = unique_edges(T)
    mid = 0.5 * (P[E[:, 0]] + P[E[:, 1]])
    inner = (mid[:, 1] > 0.15) & (mid[:, 1] < 0.85) & (mid[:, 0] > 0.3) & (mid[:, 0] < 3.7)
    h = FIELD(mid[inner])
    q = np.linalg.norm(P[E[inner, 0]] - P[E[inner, 1]], axis=1) / h
    return float(np.polyfit(np.log(h), np.log(q), 1)[0])


def test_density_power_four_follows_the_size():
    s2, s4 = _slope(2), _slope(4)
    # with 1 / h² the edges grow like sqrt(h): q falls where h is large
    assert s2 < -0.15
    assert abs(s4) < 0.5 * abs(s2)
