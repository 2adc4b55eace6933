"""A binary max-heap in flat arrays, for numba.

Entries are ``(key, a, b)``: a float64 key and two int32 payload words whose
meaning belongs to the caller (Algorithm INSERT stores ``(t, stamp)`` for a
triangle candidate and ``(-(u + 1), v)`` for a boundary subsegment ``u -> v``).

Key and tie-break
-----------------
The heap orders by key only, largest first.  Among equal keys the order is
whatever the sequence of pushes and pops produces: deterministic, but not
meaningful.  Callers that need a canonical choice among (near-)equal keys pop
all of them and choose themselves -- INSERT does, by the lexicographic rule on
the candidate points.

The heap is *lazy*: nothing is ever removed from the middle.  Keys are upper
bounds of the current value of their candidates; stale entries are recognised
and dropped (or re-pushed with a fresh key) by the caller when popped.

Storage: ``keys`` (cap,) float64, ``pa``/``pb`` (cap,) int32 and ``size`` (1,)
int64.  ``push`` returns the three arrays, reallocated (doubled) when full.
"""

import numpy as np
from numba import njit

__all__ = ["new_heap", "push", "pop", "top_key"]


def new_heap(capacity):
    """Empty heap arrays with room for ``capacity`` entries."""
    capacity = max(int(capacity), 16)
    return (
        np.empty(capacity, np.float64),
        np.empty(capacity, np.int32),
        np.empty(capacity, np.int32),
        np.zeros(1, np.int64),
    )


@njit(cache=True)
def push(keys, pa, pb, size, key, a, b):
    """Add an entry; returns (keys, pa, pb), grown if they were full."""
    n = size[0]
    if n == keys.shape[0]:
        cap = 2 * n
        k2 = np.empty(cap, np.float64)
        a2 = np.empty(cap, np.int32)
        b2 = np.empty(cap, np.int32)
        k2[:n] = keys[:n]
        a2[:n] = pa[:n]
        b2[:n] = pb[:n]
        keys, pa, pb = k2, a2, b2
    # sift up
    i = n
    while i > 0:
        parent = (i - 1) >> 1
        if keys[parent] >= key:
            break
        keys[i] = keys[parent]
        pa[i] = pa[parent]
        pb[i] = pb[parent]
        i = parent
    keys[i] = key
    pa[i] = a
    pb[i] = b
    size[0] = n + 1
    return keys, pa, pb


@njit(cache=True)
def pop(keys, pa, pb, size):
    """Remove and return the entry with the largest key as (key, a, b).

    The heap must not be empty.
    """
    n = size[0] - 1
    key, a, b = keys[0], pa[0], pb[0]
    size[0] = n
    if n > 0:
        lk, la, lb = keys[n], pa[n], pb[n]
        i = 0
        while True:
            c = 2 * i + 1
            if c >= n:
                break
            if c + 1 < n and keys[c + 1] > keys[c]:
                c += 1
            if keys[c] <= lk:
                break
            keys[i] = keys[c]
            pa[i] = pa[c]
            pb[i] = pb[c]
            i = c
        keys[i] = lk
        pa[i] = la
        pb[i] = lb
    return key, a, b


@njit(cache=True)
def top_key(keys, size):
    """The largest key, or -inf for an empty heap."""
    if size[0] == 0:
        return -np.inf
    return keys[0]
