"""Distances from points to segments in the plane, compiled, for the outline
stages' many small sets (:mod:`uniform2d._kernel.segdist`); other
dimensions go to numpy.

The same bits as :func:`uniform2d.geometry.point_segment_distance` (and as
numpy's broadcast of it), at a fraction of the cost on the few dozen points
and segments the resampling and the ring moves measure at a time.  Inputs
are read as (K, 2) float64 arrays and never modified.

Examples
--------
>>> import numpy as np
>>> A, B = np.array([[0.0, 0.0], [2.0, 0.0]]), np.array([[1.0, 0.0], [2.0, 1.0]])
>>> from_point(np.array([2.0, 2.0]), A, B)
array([2.23606798, 1.        ])
>>> nearest(np.array([[2.0, 2.0], [0.5, -1.0]]), A, B)
array([1., 1.])
"""

from __future__ import annotations

import numpy as np

from . import geometry
from ._kernel import segdist

__all__ = ["point_segment_distance", "from_point", "nearest"]


def _xy(a) -> np.ndarray:
    # contiguous and writable: numba compiles a kernel again for a read-only array
    return np.require(a, np.float64, ("C", "W"))


def point_segment_distance(P, A, B) -> np.ndarray:
    """(K,): the distance from P[i] to the segment A[i]-B[i] (all (K, D)); the
    compiled loop for D = 2, :func:`uniform2d.geometry.point_segment_distance`
    in any other dimension (the surface layer's boundary loops are 3-D)."""
    P, A, B = _xy(P), _xy(A), _xy(B)
    if P.ndim != 2 or P.shape[1] != 2:
        return geometry.point_segment_distance(P, A, B)
    return segdist.rowwise(P, A, B)


def from_point(X, A, B) -> np.ndarray:
    """(E,): the distance from the point X (2,) to each segment A[e]-B[e] ((E, 2))."""
    return segdist.from_point(_xy(X), _xy(A), _xy(B))


def nearest(Z, A, B) -> np.ndarray:
    """(K,): the distance from each point Z[k] ((K, 2)) to the nearest of the
    segments A[e]-B[e] ((E, 2)); inf where there is none."""
    return segdist.nearest(_xy(Z), _xy(A), _xy(B))
