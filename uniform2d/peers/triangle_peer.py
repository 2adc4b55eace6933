"""Shewchuk's Triangle (through the ``triangle`` wrapper), quality mode ``pq20a<area>``.

The maximum triangle area is derived from a target edge length h as the area of
the equilateral triangle, sqrt(3)/4 h^2, and h is bisected until the vertex
count matches.  The area is written in fixed-point notation: the wrapper
silently ignores an area written like ``1e-6``.  The input is a PSLG: every
vertex of the polygon (fixed points included) and every constraint edge (ring
edges and interior segment pieces) as a segment, which Triangle keeps as a union
of mesh edges.  Triangle is called under a module lock (the C library keeps
global state).
"""

from __future__ import annotations

import importlib.util
import math
import threading

import numpy as np
import shapely

from .base import PeerMesh, planar_result, tuned_planar_mesh

NAME = "triangle"
KIND = "planar"
DESCRIPTION = "Triangle, quality mesh 'pq20a<area>' (min angle 20 deg, max area sqrt(3)/4 h^2)"
REQUIRES = ("triangle",)
#: Segments go in as PSLG segments, fixed points as PSLG vertices
#: (see :func:`uniform2d.peers.takes_constraints`).
CONSTRAINTS = True

#: Minimum angle asked of Triangle (the ``q`` switch).
MIN_ANGLE = 20

_LOCK = threading.Lock()


def available() -> bool:
    """Whether the ``triangle`` Python module is installed."""
    return importlib.util.find_spec("triangle") is not None


def fixed_point(x: float) -> str:
    """``x`` in fixed-point notation with all its significant digits.

    >>> fixed_point(1e-6), fixed_point(0.25)
    ('0.000001', '0.25')
    """
    return np.format_float_positional(float(x), unique=True, trim="-")


def switches(size: float) -> str:
    """Triangle's switch string for target edge length ``size``.

    >>> switches(0.1)
    'pq20a0.004330127018922193Q'
    """
    return f"pq{MIN_ANGLE}a{fixed_point(math.sqrt(3.0) / 4.0 * size * size)}Q"


def _hole_points(polygon) -> np.ndarray:
    pts = [shapely.Polygon(h).point_on_surface() for h in polygon.holes]
    return np.array([[p.x, p.y] for p in pts], dtype=np.float64).reshape(-1, 2)


def mesh_with_size(polygon, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Mesh ``polygon`` with Triangle at target edge length ``size``.

    Returns
    -------
    points : ndarray, shape (N, 2)
    triangles : ndarray, shape (M, 3), int64, counter-clockwise
    """
    import triangle

    data = {
        "vertices": np.array(polygon.vertices, dtype=np.float64),
        "segments": np.array(polygon.constraint_edges, dtype=np.int32),
    }
    if polygon.n_holes:
        data["holes"] = _hole_points(polygon)
    with _LOCK:
        out = triangle.triangulate(data, switches(size))
    pts = np.asarray(out["vertices"], dtype=np.float64)
    tri = np.asarray(out["triangles"], dtype=np.int64)
    return planar_result(pts, tri)


def mesh(polygon, n_vertices: int) -> PeerMesh:
    """Triangle mesh of ``polygon`` with its area bound tuned to ``n_vertices`` vertices."""
    return tuned_planar_mesh(
        mesh_with_size, polygon, n_vertices,
        lambda size: {"parameter": "edge length h (area sqrt(3)/4 h^2)", "switches": switches(size)},
    )
