"""dot2d: the exact sign of (a - c) . (b - c).

Sign convention and range of exactness: :mod:`.predicates` (stated there once).
A plain floating-point value decides when it clears :data:`DOTERRBOUNDA`
(derived below); otherwise the exact path (:mod:`.expansion`) does.
"""

import numpy as np
from ._jit import njit

from .expansion import EPSILON, FILTER_FLOOR, TARGET_DEG2, differences3, leading_of_products
from .expansion import leading_of_sum, scaled3, unscale
from .external import compiled_once

__all__ = ["dot2d", "DOTERRBOUNDA"]

# dot2d filter bound, derived.
#   The computed value is  det = fl(p + q),  p = fl(fl(ax - cx) * fl(bx - cx)),
#   q = fl(fl(ay - cy) * fl(by - cy)).  P, Q denote the exact products of the
#   exact differences.  Each of p, q carries three roundings:
#   p = P (1+d1)(1+d2)(1+d3), |di| <= e (e = EPSILON), hence
#       |p - P| = |p| |1 - 1/((1+d1)(1+d2)(1+d3))| <= g |p|,
#       g = (1-e)**-3 - 1 = 3e + 6e^2 + O(e^3),
#   and likewise for q.  So the exact real s = p + q satisfies
#       |s - (P + Q)| <= g (|p| + |q|) =: g S.
#   The final rounding det = fl(s) has the sign of s (rounding is monotone and
#   fl(s) = 0 iff s = 0), so the sign of det is right whenever |s| > g S.
#   We test |det| > fl(A * fl(S)).  Since |det| <= (1+e)|s| and
#   fl(A * fl(S)) >= A S (1-e)^2, passing the test gives
#       |s| > A S (1-e)^2 / (1+e),
#   which is >= g S as soon as A >= g (1+e) / (1-e)^2 = 3e + 15e^2 + O(e^3).
#   A = (3 + 16e) e qualifies, with an e^2 S margin.  The computation has the
#   same shape as orient2d's (two products of two differences, one sum), so
#   the constant is the same.  (Gradual underflow adds at most 2**-1075 per
#   product; with S >= FILTER_FLOOR = 2**-800 the e^2 S margin, >= 2**-906,
#   absorbs it, so the filter is valid for every finite input.)
#: dot2d filter constant (see the derivation above); equal to orient2d's CCWERRBOUNDA.
DOTERRBOUNDA = (3.0 + 16.0 * EPSILON) * EPSILON


@njit(cache=True)
def dot2d_exact(ax, ay, bx, by, cx, cy):
    """dot2d by exact arithmetic (called only when the filter cannot decide)."""
    ok, k, ax, ay, bx, by, cx, cy = scaled3(ax, ay, bx, by, cx, cy, TARGET_DEG2)
    if ok <= 0:
        return np.nan if ok < 0 else 0.0
    exact, acx, acy, bcx, bcy = differences3(ax, ay, bx, by, cx, cy)
    if exact:
        return unscale(leading_of_products(acx, bcx, acy, bcy, np.bool_(False)), 2 * k)
    # (ax - cx)(bx - cx) + (ay - cy)(by - cy), expanded into 8 monomials
    xs = np.array([ax, -ax, -cx, cx, ay, -ay, -cy, cy])
    ys = np.array([bx, cx, bx, cx, by, cy, by, cy])
    return unscale(leading_of_sum(np.int64(8), xs, ys), 2 * k)


_dot2d_exact = compiled_once(dot2d_exact.py_func, 6)


@njit(cache=True)
def dot2d(ax, ay, bx, by, cx, cy):
    """Sign of (a - c).(b - c): > 0 acute at c, 0 right angle, < 0 obtuse."""
    left = (ax - cx) * (bx - cx)
    right = (ay - cy) * (by - cy)
    det = left + right
    detsum = abs(left) + abs(right)
    if detsum >= FILTER_FLOOR and abs(det) > DOTERRBOUNDA * detsum:
        return det
    return _dot2d_exact(ax, ay, bx, by, cx, cy)
