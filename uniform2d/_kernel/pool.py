"""The pool of tied candidates of INSERT (see :mod:`.insert`): slots and their heaps.

Slot s holds payload (pa, pb), weight pw, point (px, py); pgen[s] bumps when s is
freed, so a heap entry (s, gen) is current while pgen[s] == gen; ploc[s] is 1 in
the x-window, 0 outside; free slots are stacked in pfree[:nfree].  ``bound`` is the
window bound B = x_min + xtol (-inf: no window).  Heaps: pv (value, all members),
lo ((x, y), members outside the window), wx ((x, y)) and wy ((y, x)) of the window;
sel is scratch for the y-window.
"""

import numpy as np
from numba import types
from numba.experimental import structref

from . import heap
from ._jit import njit

__all__ = ["Pool", "new_pool", "pool_add", "pool_kill", "to_window", "dump_window"]


@structref.register
class PoolType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Pool(structref.StructRefProxy):
    """The tied group (see above)."""


structref.define_proxy(
    Pool,
    PoolType,
    ["pa", "pb", "pw", "px", "py", "pgen", "ploc", "pfree", "nslots", "nfree", "bound",
     "pv", "lo", "wx", "wy", "sel"],
)  # fmt: skip


@njit(cache=True)
def new_pool(capacity):
    c = max(capacity, 16)
    return Pool(
        np.empty(c, np.int32),
        np.empty(c, np.int32),
        np.empty(c, np.float64),
        np.empty(c, np.float64),
        np.empty(c, np.float64),
        np.zeros(c, np.int32),
        np.zeros(c, np.int8),
        np.empty(c, np.int32),
        0,
        0,
        -np.inf,
        heap.new_heap(c),
        heap.new_lheap(c),
        heap.new_lheap(c),
        heap.new_lheap(c),
        np.empty(16, np.int32),
    )


@njit(cache=True)
def to_window(P, s):
    P.ploc[s] = 1
    heap.lpush(P.wx, P.px[s], P.py[s], np.int64(s), P.pgen[s])
    heap.lpush(P.wy, P.py[s], P.px[s], np.int64(s), P.pgen[s])


@njit(cache=True)
def to_outside(P, s):
    P.ploc[s] = 0
    heap.lpush(P.lo, P.px[s], P.py[s], np.int64(s), P.pgen[s])


@njit(cache=True)
def dump_window(P):
    """Move every window member back outside; the window is rebuilt next time."""
    while P.wx.size > 0:
        x, y, s, g = heap.lpop(P.wx)
        if P.pgen[s] == g and P.ploc[s] == 1:
            to_outside(P, np.int64(s))
    P.wy.size = 0
    P.bound = -np.inf


@njit(cache=True)
def _grow_pool(P):
    c = 2 * P.nslots
    P.pa = heap.grown(P.pa, c)
    P.pb = heap.grown(P.pb, c)
    P.pw = heap.grown(P.pw, c)
    P.px = heap.grown(P.px, c)
    P.py = heap.grown(P.py, c)
    P.pgen = heap.grown(P.pgen, c)  # a new slot's generation may start anywhere
    P.ploc = heap.grown(P.ploc, c)  # set when the slot is filed
    P.pfree = heap.grown(P.pfree, c)


@njit(cache=True)
def pool_add(P, a, b, w, x, y, xtol):
    if P.nfree > 0:
        P.nfree -= 1
        s = P.pfree[P.nfree]
    else:
        s = P.nslots
        if s == P.pa.shape[0]:
            _grow_pool(P)
        P.nslots = s + 1
    P.pa[s] = a
    P.pb[s] = b
    P.pw[s] = w
    P.px[s] = x
    P.py[s] = y
    heap.push(P.pv, w, np.int32(s), P.pgen[s])
    if x < P.bound - xtol:  # a new smallest x: the window must be rebuilt around it
        dump_window(P)
        to_outside(P, np.int64(s))
    elif x <= P.bound:
        to_window(P, np.int64(s))
    else:
        to_outside(P, np.int64(s))


@njit(cache=True)
def pool_kill(P, s):
    P.pgen[s] += 1
    P.pfree[P.nfree] = s
    P.nfree += 1
