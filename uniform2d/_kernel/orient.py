"""orient2d: the exact sign of the orientation of three points.

Sign convention and range of exactness: :mod:`.predicates` (stated there once).
A plain floating-point determinant decides when it clears Shewchuk's
``ccwerrboundA``; otherwise the exact path (:mod:`.expansion`) does.
"""

import numpy as np
from numba import njit

from .expansion import (
    EPSILON,
    FILTER_FLOOR,
    TARGET_DEG2,
    leading,
    scaled3,
    sum_of_products,
    two_product,
    two_sum,
    two_two_sum,
    unscale,
)

__all__ = ["orient2d", "CCWERRBOUNDA"]

#: Shewchuk's orient2d filter constant: |det| > CCWERRBOUNDA * (|l| + |r|).
CCWERRBOUNDA = (3.0 + 16.0 * EPSILON) * EPSILON


@njit(cache=True)
def orient_expansion(ax, ay, bx, by, cx, cy, xs, ys, out, tmp, term):
    """out <- exact [abc] = ax(by - cy) + bx(cy - ay) + cx(ay - by); length."""
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
    return sum_of_products(6, xs, ys, out, tmp, term)


@njit(cache=True)
def orient2d_exact(ax, ay, bx, by, cx, cy):
    """orient2d by exact arithmetic (called only when the filter cannot decide)."""
    ok, k, ax, ay, bx, by, cx, cy = scaled3(ax, ay, bx, by, cx, cy, TARGET_DEG2)
    if ok <= 0:
        return np.nan if ok < 0 else 0.0
    # Common case (nearby points, Sterbenz): the differences are exact, and
    # the determinant is a two-term sum of two_products.  No allocation.
    acx, t0 = two_sum(ax, -cx)
    bcy, t1 = two_sum(by, -cy)
    acy, t2 = two_sum(ay, -cy)
    bcx, t3 = two_sum(bx, -cx)
    if t0 == 0.0 and t1 == 0.0 and t2 == 0.0 and t3 == 0.0:
        l1, l0 = two_product(acx, bcy)
        r1, r0 = two_product(acy, bcx)
        x3, x2, x1, x0 = two_two_sum(l1, l0, -r1, -r0)
        return unscale(leading(x3, x2, x1, x0), 2 * k)
    # General case: the 6 coordinate monomials ax by - ax cy + ...
    w = np.empty(38)
    xs = w[0:6]
    ys = w[6:12]
    out = w[12:24]
    tmp = w[24:36]
    term = w[36:38]
    n = orient_expansion(ax, ay, bx, by, cx, cy, xs, ys, out, tmp, term)
    return unscale(out[n - 1], 2 * k)


@njit(cache=True)
def orient2d(ax, ay, bx, by, cx, cy):
    """> 0 iff a, b, c counter-clockwise; 0 iff collinear (exact sign)."""
    detleft = (ax - cx) * (by - cy)
    detright = (ay - cy) * (bx - cx)
    det = detleft - detright
    detsum = abs(detleft) + abs(detright)
    if detsum >= FILTER_FLOOR and abs(det) > CCWERRBOUNDA * detsum:
        return det
    return orient2d_exact(ax, ay, bx, by, cx, cy)
