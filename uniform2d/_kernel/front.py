"""The closed chains of a packing front's edges
(:mod:`uniform2d.optimize.packing`): a walk from edge to edge, compiled because
a front has thousands of edges a round and the walk is one step at a time.
"""

import numpy as np

from ._jit import njit

__all__ = ["front_loops"]


@njit(cache=True)
def front_loops(ends, n):
    """The closed chains of at least three of the edges ``ends`` (k, 2) int64
    (vertex indices below ``n``): each edge is followed by the one starting
    where it ends, where exactly one edge starts and one ends there.

    Returns (idx, lens): the chains' edge indices one after the other, each
    chain from its smallest edge index in walking order, chains in the order
    of those, and (c,) the length of each chain.
    """
    k = ends.shape[0]
    out_deg = np.zeros(n, np.int64)
    in_deg = np.zeros(n, np.int64)
    start_of = np.full(n, -1, np.int64)
    for e in range(k):
        out_deg[ends[e, 0]] += 1
        in_deg[ends[e, 1]] += 1
        start_of[ends[e, 0]] = e
    succ = np.full(k, -1, np.int64)
    for e in range(k):
        v = ends[e, 1]
        if out_deg[v] == 1 and in_deg[v] == 1:
            succ[e] = start_of[v]
    seen = np.zeros(k, np.bool_)
    idx = np.empty(k, np.int64)
    lens = np.empty(k, np.int64)
    used = 0
    nloops = 0
    for first in range(k):
        if seen[first]:
            continue
        start = used
        e = first
        while e >= 0 and not seen[e]:
            seen[e] = True
            idx[used] = e
            used += 1
            e = succ[e]
        if e == first and used - start >= 3:
            lens[nloops] = used - start
            nloops += 1
        else:
            used = start
    return idx[:used].copy(), lens[:nloops].copy()
