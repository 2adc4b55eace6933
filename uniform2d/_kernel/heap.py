"""Binary heaps in flat arrays, for numba: one keyed by value, one lexicographic.

Value heap ``Heap(keys, pa, pb, size)``: entries ``(key; a, b)`` served largest key
first.  ``keys`` (cap,) float64, ``pa``/``pb`` (cap,) int32 payload words owned by
the caller, ``size`` the number of entries: 16 bytes an entry.

Lexicographic heap ``LHeap(e, size)``: entries ``(k1, k2; a, b)`` served smallest
``k1`` first, then smallest ``k2``; entry i is ``e[4i:4i+4]`` (float64; a, b are
int32 values, held exactly), so that a step down the heap reads one place, not
four arrays.  Both are mutable structrefs.

Equal keys are served in an order fixed by the sequence of pushes and pops:
deterministic but not meaningful -- callers needing a canonical choice among
near-equal keys make it themselves (Algorithm INSERT does, see
:mod:`.insert`).  Both heaps are *lazy*: nothing is removed from the middle;
callers recognise stale entries when they are served.  ``push``/``lpush`` double
the arrays when full.

A call passing a structref costs a counted reference (two locked instructions),
so :func:`sift_up` also pushes on a heap's bare arrays, for loops that push many
entries.  (numba's ``inline="always"`` would not save it -- the inlined
arguments are counted as well -- and costs seconds of compile per call site.)
"""

import numpy as np
from numba import types
from numba.experimental import structref

from ._jit import njit

__all__ = [
    "grown", "new_heap", "grow", "push", "sift_up", "pop", "top_key", "new_lheap", "lpush", "lpop",
    "ltop",
]


@structref.register
class HeapType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


@structref.register
class LHeapType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Heap(structref.StructRefProxy):
    """Value heap (see the module docstring)."""


class LHeap(structref.StructRefProxy):
    """Lexicographic heap (see the module docstring)."""


structref.define_proxy(Heap, HeapType, ["keys", "pa", "pb", "size"])
structref.define_proxy(LHeap, LHeapType, ["e", "size"])


@njit(cache=True)
def new_heap(capacity):
    """An empty value heap with room for ``capacity`` entries."""
    c = max(capacity, 16)
    return Heap(np.empty(c, np.float64), np.empty(c, np.int32), np.empty(c, np.int32), 0)


@njit(cache=True)
def new_lheap(capacity):
    """An empty lexicographic heap with room for ``capacity`` entries."""
    return LHeap(np.empty(4 * max(capacity, 16), np.float64), 0)


@njit(cache=True)
def grown(a, need):
    """``a`` itself if it holds ``need`` entries, else a copy with at least twice the room."""
    if need <= a.shape[0]:
        return a
    out = np.empty(max(need, 2 * a.shape[0]), a.dtype)
    for i in range(a.shape[0]):  # a loop: a slice copy compiles numba's shape-error code
        out[i] = a[i]
    return out


# -- value heap ---------------------------------------------------------------------------
@njit(cache=True)
def grow(H):
    """Double the room of H (full)."""
    n = H.size
    H.keys = grown(H.keys, 2 * n)
    H.pa = grown(H.pa, 2 * n)
    H.pb = grown(H.pb, 2 * n)


@njit(cache=True)
def push(H, key, a, b):
    """Add ``(key; a, b)``."""
    n = H.size
    if n == H.keys.shape[0]:
        grow(H)
    sift_up(H.keys, H.pa, H.pb, n, key, a, b)
    H.size = n + 1


@njit(cache=True, borrowed=True)
def sift_up(K, PA, PB, n, key, a, b):
    """:func:`push` on the arrays of a heap with n entries and room for one more
    (the caller counts it): for loops that push many entries, where passing
    the structref would cost a counted reference each."""
    i = n
    while i > 0:
        p = (i - 1) >> 1
        if K[p] >= key:
            break
        K[i] = K[p]
        PA[i] = PA[p]
        PB[i] = PB[p]
        i = p
    K[i] = key
    PA[i] = a
    PB[i] = b


@njit(cache=True)
def pop(H):
    """Remove and return the entry with the largest key as (key, a, b); H not empty."""
    K, PA, PB = H.keys, H.pa, H.pb
    n = H.size - 1
    key, a, b = K[0], PA[0], PB[0]
    H.size = n
    if n > 0:
        lk, la, lb = K[n], PA[n], PB[n]
        i = 0
        while True:
            c = 2 * i + 1
            if c >= n:
                break
            if c + 1 < n and K[c + 1] > K[c]:
                c += 1
            if K[c] <= lk:
                break
            K[i] = K[c]
            PA[i] = PA[c]
            PB[i] = PB[c]
            i = c
        K[i] = lk
        PA[i] = la
        PB[i] = lb
    return key, a, b


@njit(cache=True)
def top_key(H):
    """The largest key, or -inf when empty."""
    if H.size == 0:
        return -np.inf
    return H.keys[0]


# -- lexicographic heap --------------------------------------------------------------------
@njit(cache=True)
def _lt(a1, a2, b1, b2):
    return a1 < b1 or (a1 == b1 and a2 < b2)


@njit(cache=True)
def _lgrow(L):
    L.e = grown(L.e, 8 * L.size)


@njit(cache=True)
def lpush(L, k1, k2, a, b):
    """Add ``(k1, k2; a, b)``."""
    n = L.size
    if 4 * n == L.e.shape[0]:
        _lgrow(L)
    E = L.e
    i = n
    while i > 0:
        p = (i - 1) >> 1
        if not _lt(k1, k2, E[4 * p], E[4 * p + 1]):
            break
        for q in range(4):  # entry i <- entry p
            E[4 * i + q] = E[4 * p + q]
        i = p
    E[4 * i] = k1
    E[4 * i + 1] = k2
    E[4 * i + 2] = a
    E[4 * i + 3] = b
    L.size = n + 1


@njit(cache=True)
def lpop(L):
    """Remove and return the smallest entry as (k1, k2, a, b); L not empty."""
    E = L.e
    n = L.size - 1
    k1, k2, a, b = E[0], E[1], np.int32(E[2]), np.int32(E[3])
    L.size = n
    if n > 0:
        l1, l2, la, lb = E[4 * n], E[4 * n + 1], E[4 * n + 2], E[4 * n + 3]
        i = 0
        while True:
            c = 2 * i + 1
            if c >= n:
                break
            if c + 1 < n and _lt(E[4 * c + 4], E[4 * c + 5], E[4 * c], E[4 * c + 1]):
                c += 1
            if not _lt(E[4 * c], E[4 * c + 1], l1, l2):
                break
            for q in range(4):  # entry i <- entry c
                E[4 * i + q] = E[4 * c + q]
            i = c
        E[4 * i] = l1
        E[4 * i + 1] = l2
        E[4 * i + 2] = la
        E[4 * i + 3] = lb
    return k1, k2, a, b


@njit(cache=True)
def ltop(L):
    """(k1, a, b) of the smallest entry; L not empty."""
    E = L.e
    return E[0], np.int32(E[2]), np.int32(E[3])
