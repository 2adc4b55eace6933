"""The unique edges of a triangle list, bucketed by their smaller vertex.

A sort of all edge keys at once is the obvious way; bucketing each edge under
its smaller vertex (a counting sort) and sorting the buckets, which hold a
vertex's few larger neighbours, does the same in a tenth of the time at 1e6
points.
"""

import numpy as np

from ._jit import njit

__all__ = ["edges_by_vertex"]


@njit(cache=True)
def _sort_bucket(a, lo, hi):
    """Sort a[lo:hi] in place: a Shell sort (Knuth's gaps 1, 4, 13, ...), which
    is insertion sort for the usual handful of entries and not quadratic on a
    vertex of high degree (a fan's apex).  Not numpy's sort: compiling that for
    numba takes longer than the first run can spare."""
    gap = 1
    while gap < (hi - lo) // 3:
        gap = 3 * gap + 1
    while gap >= 1:
        for j in range(lo + gap, hi):
            x = a[j]
            k = j - gap
            while k >= lo and a[k] > x:
                a[k + gap] = a[k]
                k -= gap
            a[k + gap] = x
        gap //= 3


@njit(cache=True)
def edges_by_vertex(tri, n):
    """The unique undirected edges (E, 2) int64 of (M, 3) int64 triangles over n
    points, i < j, sorted, and how many triangles use each (E,) int64."""
    start = np.zeros(n + 1, np.int64)
    for t in range(tri.shape[0]):
        for k in range(3):
            start[min(tri[t, k], tri[t, (k + 1) % 3]) + 1] += 1
    for i in range(n):
        start[i + 1] += start[i]
    nb = np.empty(start[n], np.int64)  # the larger ends, bucketed by the smaller
    fill = start[:n].copy()
    for t in range(tri.shape[0]):
        for k in range(3):
            a, b = tri[t, k], tri[t, (k + 1) % 3]
            lo = min(a, b)
            nb[fill[lo]] = max(a, b)
            fill[lo] += 1
    n_edges = 0
    for i in range(n):  # sort each bucket and count its distinct ends
        _sort_bucket(nb, start[i], start[i + 1])
        for j in range(start[i], start[i + 1]):
            if j == start[i] or nb[j] != nb[j - 1]:
                n_edges += 1
    edges = np.empty((n_edges, 2), np.int64)
    counts = np.zeros(n_edges, np.int64)
    e = -1
    for i in range(n):
        for j in range(start[i], start[i + 1]):
            if j == start[i] or nb[j] != nb[j - 1]:
                e += 1
                edges[e, 0] = i
                edges[e, 1] = nb[j]
            counts[e] += 1
    return edges, counts
