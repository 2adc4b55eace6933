"""Point-to-segment distances with :func:`uniform2d.geometry.point_segment_distance`'s
arithmetic, compiled (2-D only).

The outline stages (:mod:`uniform2d.chord_sampling`, :mod:`uniform2d.ring_nudge`,
:mod:`uniform2d.ring_slide`, ...) measure thousands of small sets of distances
each; in numpy every set costs a dozen temporaries and calls.  These loops
give the same bits as the numpy expression, operation for operation::

    AB = B - A;  AP = P - A
    t  = (AP . AB) / |AB|^2   (0 where |AB|^2 = 0), clipped to [0, 1]
    d  = |AP - t AB|          (sqrt of the sum of the two squares)

(two products and a sum, each rounded: numba fuses no multiply-add without
fast-math, and numpy's ``einsum`` and ``norm`` on two columns round the same
way: pinned by a test against the numpy function).  The nearest of several
segments is the smallest of those distances, so ``sqrt`` of the smallest sum
of squares (``sqrt`` is correctly rounded and monotone).

Arrays are (K, 2) float64, C-contiguous (the Python callers make them so:
one compiled specialisation each).
"""

from __future__ import annotations

import numpy as np

from ._jit import njit

__all__ = ["rowwise", "from_point", "nearest"]


@njit(cache=True, inline="always")
def _sq(px, py, ax, ay, bx, by):
    """Squared distance from (px, py) to the segment (ax, ay)-(bx, by), the
    numpy expression's rounding (module notes)."""
    abx = bx - ax
    aby = by - ay
    L2 = abx * abx + aby * aby
    apx = px - ax
    apy = py - ay
    t = (apx * abx + apy * aby) / L2 if L2 > 0 else 0.0
    if t < 0.0:  # np.clip's order: NaN stays NaN
        t = 0.0
    elif t > 1.0:
        t = 1.0
    dx = apx - t * abx
    dy = apy - t * aby
    return dx * dx + dy * dy


@njit(cache=True)
def rowwise(P, A, B):
    """(K,): the distance from P[i] to the segment A[i]-B[i]."""
    out = np.empty(P.shape[0])
    for i in range(P.shape[0]):
        out[i] = np.sqrt(_sq(P[i, 0], P[i, 1], A[i, 0], A[i, 1], B[i, 0], B[i, 1]))
    return out


@njit(cache=True)
def from_point(X, A, B):
    """(E,): the distance from the point X (2,) to each segment A[e]-B[e]."""
    out = np.empty(A.shape[0])
    for e in range(A.shape[0]):
        out[e] = np.sqrt(_sq(X[0], X[1], A[e, 0], A[e, 1], B[e, 0], B[e, 1]))
    return out


@njit(cache=True)
def nearest(Z, A, B):
    """(K,): the distance from each point Z[k] to the nearest segment A[e]-B[e]
    (inf if there is none)."""
    out = np.empty(Z.shape[0])
    for k in range(Z.shape[0]):
        best = np.inf
        for e in range(A.shape[0]):
            best = min(best, _sq(Z[k, 0], Z[k, 1], A[e, 0], A[e, 1], B[e, 0], B[e, 1]))
        out[k] = np.sqrt(best)
    return out
