"""How INSERT ranks its candidates: value = distance / size field, and the tie rule.

Used by the loop (:mod:`.insert`), the subsegment evaluation (:mod:`.segment`)
and the point moves (:mod:`.star`, for the size field); the rule itself is
described in :mod:`.insert`.
"""

from ._jit import njit

__all__ = ["REL_TIE", "tied_above", "better", "size_at"]

REL_TIE = 1e-9


@njit(cache=True)
def tied_above(W, wg):
    """Weights above this tie with W: within REL_TIE of it, or within ``wg`` (the
    rounding of points to the caller's coordinates far from the origin, which
    can move a weight that much)."""
    return W * (1.0 - REL_TIE) - wg


@njit(cache=True, inline="always")
def better(w1, x1, y1, w2, x2, y2, xtol, wg):
    """The tie rule for two candidates: does 1 come before 2?"""
    hi = tied_above(max(w1, w2), wg)
    if w1 < hi or w2 < hi:
        return w1 > w2
    if x1 < x2 - xtol:
        return True
    if x2 < x1 - xtol:
        return False
    if y1 < y2 - xtol:
        return True
    if y2 < y1 - xtol:
        return False
    return x1 < x2


@njit(cache=True)
def _right_of(g, x):
    """np.searchsorted(g, x, side="right") for sorted g, as a plain bisection (the
    generic searchsorted costs more to compile than this loop)."""
    lo, hi = 0, g.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if g[mid] <= x:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True)
def size_at(m, x, y):
    """The size field h at (x, y): bilinear on its grid, clamped; 1 without a field.

    Candidates are ranked by value = distance / h, so a field makes points denser
    where h is small; without one every value is the plain distance.
    """
    if not m.sized:
        return 1.0
    gx, gy, gv = m.sgx, m.sgy, m.sgv
    x = min(max(x, gx[0]), gx[-1])
    y = min(max(y, gy[0]), gy[-1])
    i = min(max(_right_of(gx, x) - 1, 0), gx.shape[0] - 2)
    j = min(max(_right_of(gy, y) - 1, 0), gy.shape[0] - 2)
    return bilinear(gx, gy, gv, i, j, x, y)


@njit(cache=True, inline="always")
def bilinear(gx, gy, gv, i, j, x, y):
    """The grid values (gx, gy, gv) interpolated at (x, y) in cell (i, j): the
    one formula of the size field's kernels (:mod:`.cells` too), so that their
    sizes are the same floats as ``uniform2d.sizefield``'s."""
    tx = (x - gx[i]) / (gx[i + 1] - gx[i])
    ty = (y - gy[j]) / (gy[j + 1] - gy[j])
    return (
        gv[j, i] * (1 - tx) * (1 - ty)
        + gv[j, i + 1] * tx * (1 - ty)
        + gv[j + 1, i] * (1 - tx) * ty
        + gv[j + 1, i + 1] * tx * ty
    )
