"""When a polygon's own edges make a uniform mesh impossible.

The paper keeps every polygon vertex, so a polygon edge much shorter than the
mesh spacing is a mesh edge and sets the edge ratio; :func:`short_edge_warning`
says so, and suggests resampling the outline (:mod:`uniform2d.outline`).
A resampled outline can still have such edges, and needle-sharp corners, where
the input has features narrower than the tolerance lets the resampling widen
or cut (a shoreline's piers and slips): :func:`resampled_warning` says so of
the mesh made.
"""

from __future__ import annotations

import logging

import numpy as np

from . import libm
from .geometry import size_for_count, unique_edges
from .polygon import Polygon

__all__ = ["FORCED", "NEEDLE", "SEVERE", "SHORT_EDGE", "resampled_warning",
           "short_edge_warning"]

#: A polygon edge shorter than this fraction of the mesh spacing makes a uniform
#: mesh impossible: the mesh keeps it, so its edge ratio is at least about 1 / SHORT_EDGE.
SHORT_EDGE = 1 / 3
#: The edge ratio the polygon's own edges force from which that is a warning (below,
#: information kept in ``Mesh.info``).
SEVERE = 10.0
#: The edge ratio a resampled boundary's shortest edge forces from which that is
#: said (the uniformity a resampled mesh is for: ratio 2), and a warning from
#: 1.5 times it.
FORCED = 2.0
#: A corner of a resampled ring sharper than this (degrees) is said: every mesh
#: has an angle that small there.
NEEDLE = 1.0


def short_edge_warning(polygon: Polygon, n: int) -> tuple[str, int] | None:
    """Why ``polygon``'s own edges make a uniform mesh of n points impossible, or None.

    The criterion: a constraint edge (ring or segment piece) shorter than
    :data:`SHORT_EDGE` of the spacing h of an equilateral mesh with |V| + n
    vertices; the mesh keeps that edge, so its edge ratio is at least about h
    over it.  Returns the message and its logging level: ``WARNING`` when that
    ratio is at least :data:`SEVERE` (a digitised outline far finer than the
    mesh), ``INFO`` below (a small hole's chords at a coarse n, say).

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> print(short_edge_warning(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), 100))
    None
    """
    h = size_for_count(polygon.area, polygon.perimeter, n + len(polygon.vertices), polygon.n_holes)
    E = polygon.constraint_edges
    V = polygon.vertices
    L = np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T)
    short = int((L < SHORT_EDGE * h).sum())
    if not short:
        return None
    ratio = h / L.min()
    message = (f"{short} of the polygon's {len(L)} edges are shorter than a third of the mesh "
               f"spacing {h:.4g} (the shortest {L.min():.3g}, spacing / {ratio:.3g}): the mesh "
               f"keeps every polygon vertex, so its edge ratio is at least about {ratio:.3g}; "
               "resample the outline (resample=0.25, or --resample 0.25 on the command line)")
    return message, logging.WARNING if ratio >= SEVERE else logging.INFO


def _sharpest_corner(polygon: Polygon) -> tuple[float, np.ndarray]:
    """(degrees, point): the smallest interior angle at a ring vertex (outer ring
    counter-clockwise, holes clockwise: the interior on the left of each)."""
    best, at = 360.0, polygon.vertices[0]
    for R in polygon.rings:
        R = np.asarray(R, dtype=np.float64)
        d_in, d_out = R - np.roll(R, 1, axis=0), np.roll(R, -1, axis=0) - R
        turn = libm.arctan2(d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0],
                            (d_in * d_out).sum(axis=1))
        inner = np.degrees(np.pi - turn)
        k = int(np.argmin(inner))
        if inner[k] < best:
            best, at = float(inner[k]), R[k]
    return best, at


def resampled_warning(mesh, kept=None) -> tuple[str, int] | None:
    """Why the resampled boundary of ``mesh`` (a mesh made with ``resample=``)
    keeps it from being uniform, or None; ``kept`` (optional, one per vertex of
    ``mesh.polygon``): the input vertices the resampling kept as they are.

    Every edge of the resampled polygon is a mesh edge or split into shorter
    ones, so the mesh's edge ratio is at least its mean edge over the shortest
    of them: said where that is above :data:`FORCED`; and a ring corner sharper
    than :data:`NEEDLE` degrees bounds every angle there.  Returns the message
    and its logging level (``WARNING`` for a forced ratio of 1.5 x FORCED or
    more, or a needle; ``INFO`` otherwise).

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon, uniform_mesh
    >>> t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    >>> m = uniform_mesh(Polygon(np.c_[np.cos(t), np.sin(t)]), 300, resample=0.25)
    >>> print(resampled_warning(m))
    None
    """
    poly = mesh.polygon
    h = mesh.info["resample"]["spacing"]
    V, E = poly.vertices, poly.constraint_edges
    L = np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T)
    k = int(np.argmin(L))
    # the mesh's longest edge is at least its mean edge (not the certified
    # quality: only this one figure is needed)
    M = unique_edges(mesh.triangles, len(mesh.points))
    forced = float(np.hypot(*(mesh.points[M[:, 1]] - mesh.points[M[:, 0]]).T).mean()) / L[k]
    angle, corner = _sharpest_corner(poly)
    parts = []
    both_kept = kept is not None and bool(np.asarray(kept)[E[k]].all())
    if forced > FORCED:
        x, y = 0.5 * (V[E[k, 0]] + V[E[k, 1]])
        between = (" between two vertices it keeps (corners, segment ends, fixed points)"
                   if both_kept else "")
        parts.append(f"its shortest edge, {L[k] / h:.3g} spacings at ({x:.6g}, {y:.6g}){between}, "
                     f"is a mesh edge, so the edge ratio is at least {forced:.3g}")
    if angle < NEEDLE:
        parts.append(f"a corner of {angle:.2g} degrees at ({corner[0]:.6g}, {corner[1]:.6g}) "
                     "bounds every mesh's smallest angle")
    if not parts:
        return None
    message = "the resampled boundary keeps the mesh from being uniform: " + "; ".join(parts)
    if not (both_kept and angle >= NEEDLE):
        message += (". The outline has features narrower than the tolerance lets the "
                    "resampling widen or cut at this spacing (piers, slips, spikes); a larger "
                    "tolerance (resample=0.5, or --resample 0.5 on the command line) or "
                    "resample_corners='merge' (--resample-corners merge) may do better")
    severe = forced >= 1.5 * FORCED or angle < NEEDLE
    return message, logging.WARNING if severe else logging.INFO
