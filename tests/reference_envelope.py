"""The subsegment evaluation as it was before the envelope pruning: the slow reference.

``reference_eval_segment(m, h, xtol, bound)`` is :func:`uniform2d._kernel.segment.eval_segment`
as of the main branch before the pruned envelope (issue 35, part 2): every pair of
gathered sites gives a point of h equidistant from both, each point's visible
distance is computed against every site (O(sites^3)), and the best by the tie
rule wins.  The kernel's new evaluation must return the very same bits;
``tests/test_segment_envelope.py`` compares the two.  It shares the gathering
(:func:`_collect`) and the visible distance of one point (:func:`_nearest_visible`)
with the kernel, which the new evaluation keeps unchanged.
"""

import numpy as np
from numba import njit

from uniform2d._kernel.cdt import counts, nxt, prv
from uniform2d._kernel.insert import _subsegment
from uniform2d._kernel.predicates import dot2d
from uniform2d._kernel.rank import better, size_at
from uniform2d._kernel.segment import DISK_SLACK, NEAR_SLACK, _collect
from uniform2d._kernel.visible import _nearest_visible


@njit(cache=True)
def _envelope_max_reference(m, h, nv, ne, mx, my, xtol):
    xy = m.xy
    a = m.tv[h]
    b = m.tv[nxt(h)]
    ax, ay = xy[a, 0], xy[a, 1]
    dx, dy = xy[b, 0] - ax, xy[b, 1] - ay
    ns = nv + 2
    sites = np.empty(ns, np.int32)
    sites[0] = a
    sites[1] = b
    for i in range(nv):
        sites[2 + i] = m.vbuf[i]
    bv, bx_, by_ = -1.0, mx, my
    for i in range(ns):
        p = sites[i]
        pa2 = (xy[p, 0] - ax) ** 2 + (xy[p, 1] - ay) ** 2
        for j in range(i + 1, ns):
            q = sites[j]
            qa2 = (xy[q, 0] - ax) ** 2 + (xy[q, 1] - ay) ** 2
            den = 2.0 * (dx * (xy[q, 0] - xy[p, 0]) + dy * (xy[q, 1] - xy[p, 1]))
            if den == 0.0:
                continue
            s = (qa2 - pa2) / den
            if not (0.0 < s < 1.0):
                continue
            x = ax + s * dx
            y = ay + s * dy
            val = np.sqrt(_nearest_visible(m, sites, ne, x, y)) / size_at(m, x, y)
            if bv < 0.0 or better(val, x, y, bv, bx_, by_, xtol, m.wg):
                bv, bx_, by_ = val, x, y
    return bv, bx_, by_


@njit(cache=True)
def reference_eval_segment(m, h, xtol, bound):
    """The old ``eval_segment``: (value, x, y) of subsegment h (see the module doc)."""
    xy = m.xy
    a = m.tv[h]
    b = m.tv[nxt(h)]
    c = m.tv[prv(h)]
    ax, ay, bx, by = xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1]
    dx, dy = bx - ax, by - ay
    half = 0.5 * np.sqrt(dx * dx + dy * dy)
    mx, my = ax + 0.5 * dx, ay + 0.5 * dy
    if dot2d(ax, ay, bx, by, xy[c, 0], xy[c, 1]) >= 0.0:
        return half / size_at(m, mx, my), mx, my
    near2 = np.inf
    if not m.sized and bound < np.inf:
        near = bound * (1.0 + NEAR_SLACK) + m.wg
        near2 = near * near
    nv, ne = _collect(m, h, mx, my, half * half * (1.0 + DISK_SLACK), near2)
    bv, bx_, by_ = _envelope_max_reference(m, h, nv, ne, mx, my, xtol)
    if bv < 0.0:
        return half / size_at(m, mx, my), mx, my
    return bv, bx_, by_


@njit(cache=True)
def subsegment_edges(m):
    """Every subsegment candidate half-edge of the triangulation m (INSERT's own test)."""
    nt = counts(m)[1]
    out = np.empty(3 * nt, np.int64)
    k = 0
    for h in range(3 * nt):
        if _subsegment(m, h):
            out[k] = h
            k += 1
    return out[:k]
