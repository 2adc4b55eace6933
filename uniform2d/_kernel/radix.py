"""A stable argsort of non-negative integer keys (least-significant-digit radix sort).

``np.argsort(keys, kind="mergesort")`` gives the same order, but numba's generic
sort is costly to compile and O(n log n); the half-edge keys the kernel sorts
are bounded by the squared vertex count, so a few counting passes do.
"""

from __future__ import annotations

import numpy as np

from ._jit import njit

__all__ = ["stable_argsort"]

#: Bits of the key sorted per counting pass.
DIGIT = 8


@njit(cache=True)
def stable_argsort(keys):
    """Indices (int64) that sort the non-negative int64 ``keys``, equal keys in index
    order: exactly ``np.argsort(keys, kind="mergesort")``."""
    n = keys.shape[0]
    order = np.empty(n, np.int64)
    spare = np.empty(n, np.int64)
    top = 0
    for i in range(n):
        order[i] = i
        top = max(top, keys[i])
    base = 1 << DIGIT
    mask = base - 1
    count = np.empty(base + 1, np.int64)
    shift = 0
    while shift == 0 or (shift < 64 and (top >> shift) > 0):  # a shift >= 64 is undefined
        for d in range(base + 1):
            count[d] = 0
        for i in range(n):
            count[((keys[order[i]] >> shift) & mask) + 1] += 1
        for d in range(base):
            count[d + 1] += count[d]
        for i in range(n):
            d = (keys[order[i]] >> shift) & mask
            spare[count[d]] = order[i]
            count[d] += 1
        order, spare = spare, order
        shift += DIGIT
    return order
