"""orient2d: the exact sign of the orientation of three points.

Sign convention and range of exactness: :mod:`.predicates` (stated there once).
A plain floating-point determinant decides when it clears Shewchuk's
``ccwerrboundA``; otherwise the exact path (:mod:`.expansion`) does.
"""

import numpy as np
from ._jit import njit

from .expansion import EPSILON, FILTER_FLOOR, TARGET_DEG2, differences3, leading_of_products
from .expansion import leading_of_sum, scaled3, sum_of_products, unscale
from .external import compiled_once

__all__ = ["orient2d", "CCWERRBOUNDA"]

#: Shewchuk's orient2d filter constant: |det| > CCWERRBOUNDA * (|l| + |r|).
CCWERRBOUNDA = (3.0 + 16.0 * EPSILON) * EPSILON


@njit(cache=True, borrowed=True)
def orient_expansion(ax, ay, bx, by, cx, cy, xs, ys, out, tmp, term):
    """out <- exact [abc] = ax(by - cy) + bx(cy - ay) + cx(ay - by); length."""
    _monomials(ax, ay, bx, by, cx, cy, xs, ys)
    return sum_of_products(np.int64(6), xs, ys, out, tmp, term)


@njit(cache=True, borrowed=True)
def _monomials(ax, ay, bx, by, cx, cy, xs, ys):
    """[abc] as sum(xs[i] * ys[i], i < 6)."""
    xs[0] = ax
    ys[0] = by
    xs[1] = -ax
    ys[1] = cy
    xs[2] = bx
    ys[2] = cy
    xs[3] = -bx
    ys[3] = ay
    xs[4] = cx
    ys[4] = ay
    xs[5] = -cx
    ys[5] = by


@njit(cache=True)
def orient2d_exact(ax, ay, bx, by, cx, cy):
    """orient2d by exact arithmetic (called only when the filter cannot decide)."""
    ok, k, ax, ay, bx, by, cx, cy = scaled3(ax, ay, bx, by, cx, cy, TARGET_DEG2)
    if ok <= 0:
        return np.nan if ok < 0 else 0.0
    # Common case (nearby points, Sterbenz): the differences are exact, and
    # the determinant is a two-term sum of two_products.  No allocation.
    exact, acx, acy, bcx, bcy = differences3(ax, ay, bx, by, cx, cy)
    if exact:
        return unscale(leading_of_products(acx, bcy, acy, bcx, np.bool_(True)), 2 * k)
    # General case: the 6 coordinate monomials ax by - ax cy + ...
    xs = np.empty(6)
    ys = np.empty(6)
    _monomials(ax, ay, bx, by, cx, cy, xs, ys)
    return unscale(leading_of_sum(np.int64(6), xs, ys), 2 * k)


_orient2d_exact = compiled_once(orient2d_exact.py_func, 6)


@njit(cache=True)
def orient2d(ax, ay, bx, by, cx, cy):
    """> 0 iff a, b, c counter-clockwise; 0 iff collinear (exact sign)."""
    detleft = (ax - cx) * (by - cy)
    detright = (ay - cy) * (bx - cx)
    det = detleft - detright
    detsum = abs(detleft) + abs(detright)
    if detsum >= FILTER_FLOOR and abs(det) > CCWERRBOUNDA * detsum:
        return det
    return _orient2d_exact(ax, ay, bx, by, cx, cy)
