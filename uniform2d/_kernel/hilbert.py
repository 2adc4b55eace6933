"""Sorting points along a Hilbert curve: the order the loader inserts interior sites in.

Nearby points come one after another, so each insertion starts its walk where
the last one ended (:func:`uniform2d._kernel.cavity.insert_sites`).
"""

import numpy as np

from ._jit import njit

__all__ = ["hilbert_order"]


#: Up to this many points :func:`hilbert_order` is one kernel call (the
#: optimiser's starts, 12 loads a mesh of 1000 points on several threads: a
#: dozen small numpy calls held the GIL); beyond, numpy's sort is the faster.
KERNEL_MAX = 50000


def hilbert_order(points: np.ndarray, bits: int = 16) -> np.ndarray:
    """Indices sorting points (K, 2) along a Hilbert curve over their bounding box."""
    if 0 < len(points) <= KERNEL_MAX:
        return _order(np.ascontiguousarray(points, dtype=np.float64), np.int64(1 << bits))
    lo = points.min(axis=0)
    span = max(float((points.max(axis=0) - lo).max()), 1e-300)
    side = 1 << bits
    q = np.minimum(((points - lo) / span * (side - 1)).astype(np.int64), side - 1)
    return np.argsort(_hilbert_index(q, np.int64(side)), kind="stable")


@njit(cache=True)
def _hilbert_index(q, side):
    """The distance along the Hilbert curve of each cell ``q`` (K, 2) of a
    ``side`` x ``side`` grid (one pass per point: vectorised, each of the
    log2(side) levels made a dozen K-sized temporaries)."""
    d = np.zeros(q.shape[0], np.int64)
    for k in range(q.shape[0]):
        x, y = q[k, 0], q[k, 1]
        s = side >> 1
        while s > 0:
            rx = 1 if (x & s) > 0 else 0
            ry = 1 if (y & s) > 0 else 0
            d[k] += s * s * ((3 * rx) ^ ry)
            if ry == 0:  # rotate the quadrant
                if rx == 1:
                    x, y = s - 1 - x, s - 1 - y
                x, y = y, x
            s >>= 1
    return d


@njit(cache=True)
def _order(points, side):
    """:func:`hilbert_order` in one call, the same operations: the same cells,
    the same stable order."""
    k = points.shape[0]
    lo0, lo1, hi0, hi1 = points[0, 0], points[0, 1], points[0, 0], points[0, 1]
    for a in range(1, k):
        lo0, hi0 = min(lo0, points[a, 0]), max(hi0, points[a, 0])
        lo1, hi1 = min(lo1, points[a, 1]), max(hi1, points[a, 1])
    span = max(max(hi0 - lo0, hi1 - lo1), 1e-300)
    q = np.empty((k, 2), np.int64)
    top = side - 1
    for a in range(k):
        q[a, 0] = min(np.int64((points[a, 0] - lo0) / span * top), top)
        q[a, 1] = min(np.int64((points[a, 1] - lo1) / span * top), top)
    return np.argsort(_hilbert_index(q, side), kind="mergesort")
