"""The chord heights of :func:`uniform2d.chord_sampling.sample_run`'s dynamic
programme, compiled (planar runs).

For every chord (i, i + d) between candidate positions whose length is within
[lo, hi], its height is the largest distance from it of the checked
candidates strictly between its ends, plus the largest ``excess`` (the
skipped input vertices' bound) from i up to the last of those candidates::

    u:      i ---- k1 ---- k2 ---- i+d       H[d, i] = max dist(C[k], chord)
    excess: e_i    e_k1    e_k2                        + max(e_i, e_k1, e_k2)

The same operations as the numpy version it replaces (distances with
:mod:`uniform2d._kernel.segdist`'s arithmetic, maxima exact, one sum), so the
same bits; the numpy version stays for runs in 3-D.
"""

from __future__ import annotations

import numpy as np

from ._jit import njit
from .segdist import _sq

__all__ = ["chord_heights"]


@njit(cache=True)
def chord_heights(u, C, check, excess, W, lo, hi):
    """H (W + 1, len(u)): chord (i, i + d)'s height at H[d, i], inf where its
    length ``u[i + d] - u[i]`` is not within [lo, hi]; ``check``: the sorted
    candidates whose distance counts."""
    nc = u.shape[0]
    H = np.full((W + 1, nc), np.inf)
    # after[i]: the first index into check with a candidate beyond i
    after = np.empty(nc, np.int64)
    j = 0
    for i in range(nc):
        while j < check.shape[0] and check[j] <= i:
            j += 1
        after[i] = j
    for d in range(1, W + 1):
        for i in range(nc - d):
            ell = u[i + d] - u[i]
            if not (ell >= lo and ell <= hi):
                continue
            a0, a1 = C[i, 0], C[i, 1]
            b0, b1 = C[i + d, 0], C[i + d, 1]
            hmax = 0.0
            emax = excess[i]
            j = after[i]
            while j < check.shape[0] and check[j] < i + d:
                k = check[j]
                hmax = max(hmax, np.sqrt(_sq(C[k, 0], C[k, 1], a0, a1, b0, b1)))
                emax = max(emax, excess[k])
                j += 1
            H[d, i] = hmax + emax
    return H
