"""Sorting points along a Hilbert curve: the order the loader inserts interior sites in.

Nearby points come one after another, so each insertion starts its walk where
the last one ended (:func:`uniform2d._kernel.cavity.insert_sites`).
"""

import numpy as np

from ._jit import njit

__all__ = ["hilbert_order"]


def hilbert_order(points: np.ndarray, bits: int = 16) -> np.ndarray:
    """Indices sorting points (K, 2) along a Hilbert curve over their bounding box."""
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
