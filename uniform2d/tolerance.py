"""The numeric policy: how the library's tolerances follow from a polygon alone.

Every tolerance the loader, INSERT and the checks use is a function of P's
bounding box and coordinates, so the same polygon, scaled or moved, is judged
the same way.  :func:`normaliser` maps P exactly onto the kernel's coordinates;
:func:`grain` and :func:`rounding` say how far rounding can move a point;
:func:`boundary_tol` is the distance within which a point is on P's boundary.
The functions read only ``polygon.bounds`` and ``polygon.vertices``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["BOUNDARY_TOL", "boundary_tol", "extent", "grain", "normaliser", "rounding"]

#: A site closer than this (relative to the polygon size) to the boundary is on it.
BOUNDARY_TOL = 1e-10


def normaliser(polygon):
    """(centre, scale) with x_norm = (x - centre) / scale, exact both ways.

    ``scale`` is the power of two nearest max(width, height), so dividing by it
    and multiplying back are exact.  A coordinate whose bounding-box centre is
    within 2 sizes of the origin is not translated; one farther away is
    translated by its centre rounded to a multiple of 2**-20 scale.  Then
    X - centre is exact for every float X in the polygon's box (Sterbenz: X and
    centre are within a factor 2 of each other), so the kernel works on an exact
    image of the caller's coordinates, and new points rounded to what those
    coordinates can hold (:func:`uniform2d._kernel.cdt.snap`) map back exactly:
    the mesh the predicates certified is the one the caller gets.
    """
    xmin, ymin, xmax, ymax = polygon.bounds
    size = max(xmax - xmin, ymax - ymin)
    # the C library's log2: numpy's differs in the last bit on some CPUs (AVX-512),
    # which would move a size near a rounding boundary to the other power of two
    scale = 2.0 ** round(math.log2(size))
    centre = np.array([(xmin + xmax) / 2.0, (ymin + ymax) / 2.0])
    q = scale * 2.0**-20
    return np.where(np.abs(centre) <= 2.0 * size, 0.0, np.round(centre / q) * q), scale


def grain(polygon, centre) -> float:
    """How far rounding a new point to the caller's coordinates
    (:func:`uniform2d._kernel.cdt.snap`) can move a distance: a few units in the
    last place of the translated coordinates, 0 where nothing is translated
    (there the rounding is exact)."""
    if not centre.any():
        return 0.0
    return 4.0 * float(np.spacing(np.abs(centre).max() + extent(polygon)))


def extent(polygon) -> float:
    """The larger side of P's bounding box."""
    xmin, ymin, xmax, ymax = polygon.bounds
    return max(xmax - xmin, ymax - ymin)


def rounding(polygon) -> float:
    """How far rounding alone can move a point computed near P's coordinates (a
    few units in their last place): far from the origin that exceeds the
    relative tolerances below."""
    return 8 * np.finfo(float).eps * float(np.abs(polygon.vertices).max())


def boundary_tol(polygon) -> float:
    """Distance within which a site counts as on P's boundary.

    :data:`BOUNDARY_TOL` of the polygon's size, or more where its coordinates are
    so large for its size (far from the origin) that rounding alone moves a point
    computed on an edge, ``a + t (b - a)``, that far off it.
    """
    return max(BOUNDARY_TOL * extent(polygon), rounding(polygon))
