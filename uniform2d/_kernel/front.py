"""The closed chains of a packing front's edges
(:mod:`uniform2d.optimize.packing`): a walk from edge to edge, compiled because
a front has thousands of edges a round and the walk is one step at a time.
"""

import numpy as np

from ._jit import njit
from .rank import _right_of

__all__ = ["front_loops", "greedy_kept", "respace_chains"]


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


@njit(cache=True)
def respace_chains(cand, idx, lens, inv, d, boundary):
    """``cand`` (k, 2) with chains of its points respaced: chain c, the points
    ``cand[idx[f:f + lens[c]]]`` (f its offset) with ``d`` the step from each to
    the next around the chain and ``inv`` the integral of 1 / h over that step,
    becomes m = rint(the chain's integral) points spaced by equal integrals
    along it, in place of the chain's first (smallest) index, the others
    dropped; unless m is the chain's length, or m is smaller and
    ``boundary[c]`` (the chain on the boundary, which only gains points).

    The formulas are numpy's of :func:`uniform2d.optimize.packing._respace_rings`
    (a cumulative sum from 0, a right-sided bisection, clipped), one float
    operation after another in the same order: the same points.
    """
    k = cand.shape[0]
    nc = lens.shape[0]
    drop = np.zeros(k, np.bool_)
    at = np.full(k, -1, np.int64)  # the chain placed at a first index
    cum = np.empty(idx.shape[0] + nc)
    size = k
    f = 0
    for c in range(nc):
        n = lens[c]
        o = f + c  # the chain's running integral: cum[o:o + n + 1]
        cum[o] = 0.0
        for e in range(n):
            cum[o + e + 1] = cum[o + e] + inv[f + e]
        m = int(np.rint(cum[o + n]))
        if not (m == n or (m < n and boundary[c])):
            for e in range(n):
                drop[idx[f + e]] = True
            at[idx[f]] = c
            size += m - n
        f += n
    offs = np.zeros(nc + 1, np.int64)
    for c in range(nc):
        offs[c + 1] = offs[c] + lens[c]
    out = np.empty((size, 2))
    w = 0
    for i in range(k):
        c = at[i]
        if c >= 0:
            f, n = offs[c], lens[c]
            o = f + c
            total = cum[o + n]
            m = int(np.rint(total))
            for j in range(m):
                goal = total * j / m
                s = _right_of(cum[o:o + n + 1], goal) - 1
                s = min(max(s, 0), n - 1)
                frac = (goal - cum[o + s]) / max(inv[f + s], 1e-300)
                frac = min(max(frac, 0.0), 1.0)
                p = idx[f + s]
                out[w, 0] = cand[p, 0] + frac * d[f + s, 0]
                out[w, 1] = cand[p, 1] + frac * d[f + s, 1]
                w += 1
        elif not drop[i]:
            out[w, 0] = cand[i, 0]
            out[w, 1] = cand[i, 1]
            w += 1
    return out


@njit(cache=True)
def greedy_kept(n, i, j):
    """(n,) bool: the points kept in order, each unless an earlier kept one is
    close to it: (i, j) the close pairs, both ways, sorted by i."""
    blocked = np.zeros(n, np.bool_)
    s = 0
    while s < i.shape[0]:
        k = i[s]
        e = s
        while e < i.shape[0] and i[e] == k:
            e += 1
        if not blocked[k]:
            for x in range(s, e):
                blocked[j[x]] = True
        s = e
    return ~blocked
