"""A mesh of a polygon from a jittered grid (the polish and CV stage tests move
its points) and the five measures those stages hold or lower, read from
:func:`uniform2d.quality`."""

from __future__ import annotations

import numpy as np
import shapely

import uniform2d
from uniform2d import Polygon
from uniform2d.sites import site_edges
from uniform2d.triangulation import triangulate


def jittered(polygon: Polygon, h: float, seed: int = 0):
    """A mesh of ``polygon`` (no holes) from a jittered grid of spacing ``h``, its
    boundary split evenly: (points, triangles, the polygon edge of every site)."""
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = polygon.bounds
    xs, ys = np.meshgrid(np.arange(x0 + h / 2, x1, h), np.arange(y0 + h / 2, y1, h))
    grid = np.c_[xs.ravel(), ys.ravel()] + rng.uniform(-0.2 * h, 0.2 * h, (xs.size, 2))
    inner = polygon.to_shapely().buffer(-0.3 * h)
    keep = shapely.contains_xy(inner, grid[:, 0], grid[:, 1])
    V = polygon.vertices
    on_edges = []
    for a, b in zip(V, np.roll(V, -1, axis=0)):
        k = int(round(np.hypot(*(b - a)) / h))
        on_edges += [a + (b - a) * t for t in np.arange(1, k) / k]
    sites = np.vstack([grid[keep], on_edges])
    _, edges = site_edges(polygon, sites)
    points, triangles = triangulate(polygon, sites, edges)
    return points, triangles, edges


def measures(points, triangles):
    """(edge ratio, longest edge, largest perimeter, edge CV, worst angle)."""
    q = uniform2d.quality(points, triangles)
    return q.edge_ratio, q.longest_edge, q.max_perimeter, q.cv_edge, q.min_angle
