"""Loading a triangle list into the flat-array CDT: pairing its half-edges as twins.

:func:`build_adjacency` pairs every half-edge with its twin in the order of the
sorted undirected edges (:func:`_edge_order`: a counting sort on the smaller
vertex and a short sort per vertex, no key arrays); the unpaired ones are the
boundary.
"""

import numpy as np

from ._jit import njit
from .cdt import _set_triangle, nxt
from .radix import stable_argsort

__all__ = ["build_adjacency", "SHORT_RUN"]


@njit(cache=True)
def build_adjacency(m, tris):
    """Load (T, 3) CCW triangles; pair half-edges in the order of their sorted
    undirected edges (:func:`_edge_order`).

    Returns the number of boundary half-edges.
    """
    nt = tris.shape[0]
    m.vcs[:] = -1  # no constraint flags: the caller flags the segment pieces
    for t in range(nt):
        _set_triangle(m, np.int64(t), np.int64(tris[t, 0]), np.int64(tris[t, 1]), np.int64(tris[t, 2]))
        m.tc[3 * t : 3 * t + 3] = 0
    m.nt = nt
    order = _edge_order(m, nt)
    nb = 0
    i = 0
    while i < 3 * nt:
        h = order[i]
        if i + 1 < 3 * nt and _same_edge(m, h, order[i + 1]):
            g = order[i + 1]
            m.tw[h] = g
            m.tw[g] = h
            i += 2
        else:
            m.tw[h] = -1
            m.vseg[m.tv[h]] = h
            nb += 1
            i += 1
    return nb



@njit(cache=True, inline="always")
def _ends(m, h):
    """(smaller, larger) vertex of half-edge h."""
    u = np.int64(m.tv[h])
    v = np.int64(m.tv[nxt(h)])
    return min(u, v), max(u, v)



@njit(cache=True, inline="always")
def _same_edge(m, h, g):
    a, b = _ends(m, h)
    c, d = _ends(m, g)
    return a == c and b == d



#: A vertex's half-edges are put in order by insertion up to this many.
SHORT_RUN = 32



@njit(cache=True, inline="always")
def _edge_order(m, nt):
    """The half-edges of the first nt triangles sorted by their (smaller, larger)
    vertex, equal edges in index order: the order a stable sort of the keys
    smaller * nv + larger gives.  A counting sort on the smaller vertex (stable)
    and a stable sort of each vertex's few half-edges by the larger one: no
    3-per-triangle key arrays (~150 MB at 1e6 points for keys and a radix sort)."""
    n = 3 * nt
    top = m.nv
    for h in range(n):
        top = max(top, np.int64(m.tv[h]) + 1)
    start = np.zeros(top + 1, np.int64)
    for h in range(n):
        start[_ends(m, h)[0] + 1] += 1
    for v in range(top):
        start[v + 1] += start[v]
    order = np.empty(n, np.int64)
    fill = start[:-1].copy()
    for h in range(n):
        a = _ends(m, h)[0]
        order[fill[a]] = h
        fill[a] += 1
    for v in range(top):
        lo, hi = start[v], start[v + 1]
        if hi - lo <= SHORT_RUN:
            for i in range(lo + 1, hi):  # insertion: stable, equal ones keep their order
                h = order[i]
                b = _ends(m, h)[1]
                j = i - 1
                while j >= lo and _ends(m, order[j])[1] > b:
                    order[j + 1] = order[j]
                    j -= 1
                order[j + 1] = h
        else:
            run = order[lo:hi].copy()
            second = np.empty(hi - lo, np.int64)
            for i in range(hi - lo):
                second[i] = _ends(m, run[i])[1]
            idx = stable_argsort(second)
            for i in range(hi - lo):
                order[lo + i] = run[idx[i]]
    return order
