"""Exact arithmetic for the robust predicates: error-free transformations,
Shewchuk's expansion arithmetic and the power-of-two rescaling of the exact path.

The predicates themselves, their sign conventions and their range of exactness
are described in :mod:`.predicates`.  Here:

* error-free transformations (Knuth's ``two_sum``, Dekker's ``split`` with the
  2**27 + 1 splitter and ``two_product``, Shewchuk's ``two_two_sum``): a float
  operation and its exact rounding error;
* expansion arithmetic (Shewchuk 1997).  An expansion is ``a[0:n]``, components
  nonoverlapping and sorted by increasing magnitude; its value is their sum
  and its sign is the sign of ``a[n - 1]``;
* rescaling: the exact path multiplies every coordinate by one power of two
  (exact) so that nothing overflows, and scales the leading component back;
  :func:`scaled3` / :func:`scaled4` do it for three or four points.

Never compile this module with ``fastmath``: the error-free transformations
rely on IEEE round-to-nearest-even without reassociation or FMA contraction.
"""

import math

import numpy as np
from ._jit import njit

#: Half an ulp of 1.0: the relative rounding error bound of one operation.
EPSILON = 2.0**-53
#: Dekker's splitter for 53-bit significands: 2**ceil(53/2) + 1.
_SPLITTER = 2.0**27 + 1.0
#: Below this scale a filter is not trusted (possible underflow).
FILTER_FLOOR = 2.0**-800
#: Smallest positive subnormal: returned (signed) if the exact result's
#: magnitude would underflow when scaled back.
_TINIEST = 5e-324
# The exact path rescales so that the largest |coordinate| is in
# [2**(T-1), 2**T): degree-2 determinants stay below ~2**963 and degree-4
# below ~2**966 (no overflow), while tiny coordinates keep as much headroom
# above the subnormal range as possible.
TARGET_DEG2 = 480
TARGET_DEG4 = 240


# ----------------------------------------------------------------------------
# error-free transformations (Knuth's two_sum, Dekker's split / two_product)
# ----------------------------------------------------------------------------


@njit(cache=True)
def two_sum(a, b):
    """x + y == a + b exactly, x = fl(a + b) (any order of magnitudes)."""
    x = a + b
    bvirt = x - a
    avirt = x - bvirt
    bround = b - bvirt
    around = a - avirt
    return x, around + bround


@njit(cache=True)
def split(a):
    """a == hi + lo exactly, each half with at most 26 significant bits."""
    c = _SPLITTER * a
    abig = c - a
    hi = c - abig
    return hi, a - hi


@njit(cache=True)
def two_product(a, b):
    """x + y == a * b exactly, x = fl(a * b) (Dekker, no FMA needed)."""
    x = a * b
    ahi, alo = split(a)
    bhi, blo = split(b)
    err1 = x - ahi * bhi
    err2 = err1 - alo * bhi
    err3 = err2 - ahi * blo
    return x, alo * blo - err3


@njit(cache=True)
def two_two_sum(a1, a0, b1, b0):
    """(x3, x2, x1, x0): nonoverlapping expansion of (a1 + a0) + (b1 + b0).

    Shewchuk's Two_Two_Sum; the inputs must be nonoverlapping pairs (e.g.
    two_product results).  Components may be zero; the nonzero ones increase
    in magnitude from x0 to x3.
    """
    i, x0 = two_sum(a0, b0)
    j, z = two_sum(a1, i)
    i, x1 = two_sum(z, b1)
    x3, x2 = two_sum(j, i)
    return x3, x2, x1, x0


@njit(cache=True)
def leading(x3, x2, x1, x0):
    """Most significant nonzero component (it carries the sign of the sum)."""
    if x3 != 0.0:
        return x3
    if x2 != 0.0:
        return x2
    if x1 != 0.0:
        return x1
    return x0


@njit(cache=True, borrowed=True)
def _keep(h, n, x):
    """Append x to h[:n] unless it is zero (zero elimination); returns the new length."""
    if x != 0.0:
        h[n] = x
        n += 1
    return n


@njit(cache=True, borrowed=True)
def store4(x3, x2, x1, x0, out):
    """Write x0..x3 to out as a zero-eliminated expansion; returns its length."""
    n = _keep(out, np.int64(0), x0)  # not a literal 0: _keep compiles once
    n = _keep(out, n, x1)
    n = _keep(out, n, x2)
    n = _keep(out, n, x3)
    if n == 0:
        out[0] = 0.0
        n = 1
    return n


# ----------------------------------------------------------------------------
# expansion arithmetic
# ----------------------------------------------------------------------------


@njit(cache=True, inline="always")
def _close(h, hindex, q):
    """Append the last component q (even a zero, if h is empty); returns len(h)."""
    if q != 0.0 or hindex == 0:
        h[hindex] = q
        hindex += 1
    return hindex


@njit(cache=True, inline="always")
def _drain(q, e, i, n, h, hindex):
    """q plus the rest e[i:n] of an expansion, the nonzero roundoff appended to
    h[hindex:]; returns (q, hindex)."""
    while i < n:
        q, hh = two_sum(q, e[i])
        i += 1
        hindex = _keep(h, hindex, hh)
    return q, hindex


@njit(cache=True, borrowed=True)
def expansion_sum(elen, e, flen, f, h):
    """h <- e + f; returns len(h) (>= 1, <= elen + flen).

    Shewchuk's fast_expansion_sum_zeroelim (needs round-to-even), with
    two_sum in place of fast_two_sum for the first step (same result,
    no magnitude precondition).  Zero components are dropped.
    """
    eindex = 0
    findex = 0
    enow = e[0]
    fnow = f[0]
    if (fnow > enow) == (fnow > -enow):
        q = enow
        eindex += 1
        if eindex < elen:
            enow = e[eindex]
    else:
        q = fnow
        findex += 1
        if findex < flen:
            fnow = f[findex]
    hindex = np.int64(0)  # not a literal 0: _keep compiles once
    while eindex < elen and findex < flen:
        if (fnow > enow) == (fnow > -enow):
            q, hh = two_sum(q, enow)
            eindex += 1
            if eindex < elen:
                enow = e[eindex]
        else:
            q, hh = two_sum(q, fnow)
            findex += 1
            if findex < flen:
                fnow = f[findex]
        hindex = _keep(h, hindex, hh)
    q, hindex = _drain(q, e, eindex, elen, h, hindex)
    q, hindex = _drain(q, f, findex, flen, h, hindex)
    return _close(h, hindex, q)


@njit(cache=True, borrowed=True)
def scale_expansion(elen, e, b, h):
    """h <- b * e; returns len(h) (>= 1, <= 2 * elen).

    Shewchuk's scale_expansion_zeroelim, two_sum in place of fast_two_sum.
    """
    q, hh = two_product(e[0], b)
    hindex = _keep(h, np.int64(0), hh)  # not a literal 0: _keep compiles once
    for i in range(1, elen):
        p1, p0 = two_product(e[i], b)
        s, hh = two_sum(q, p0)
        hindex = _keep(h, hindex, hh)
        q, hh = two_sum(p1, s)
        hindex = _keep(h, hindex, hh)
    return _close(h, hindex, q)


@njit(cache=True, borrowed=True)
def mul_expansions(elen, e, flen, f, h, t, u):
    """h <- e * f = sum_i e[i] * f; returns len(h) (<= 2 * elen * flen).

    t needs 2 * flen slots, u as many as h.
    """
    hlen = scale_expansion(flen, f, e[0], h)
    for i in range(1, elen):
        tlen = scale_expansion(flen, f, e[i], t)
        hlen = expansion_sum(hlen, h, tlen, t, u)
        for k in range(hlen):
            h[k] = u[k]
    return hlen


@njit(cache=True, borrowed=True)
def sum_of_products(n, xs, ys, out, tmp, term):
    """out <- exact expansion of sum(xs[i] * ys[i], i < n); returns its length.

    out and tmp need 2 * n slots, term 2.
    """
    hi, lo = two_product(xs[0], ys[0])
    out[0] = lo
    out[1] = hi
    length = np.int64(2)
    for i in range(1, n):
        hi, lo = two_product(xs[i], ys[i])
        term[0] = lo
        term[1] = hi
        length = expansion_sum(length, out, np.int64(2), term, tmp)
        for k in range(length):
            out[k] = tmp[k]
    return length


@njit(cache=True)
def differences3(ax, ay, bx, by, cx, cy):
    """(exact, ax - cx, ay - cy, bx - cx, by - cy): the rounded differences, and
    whether every one is exact (its two_sum tail vanishes)."""
    acx, t0 = two_sum(ax, -cx)
    acy, t1 = two_sum(ay, -cy)
    bcx, t2 = two_sum(bx, -cx)
    bcy, t3 = two_sum(by, -cy)
    return t0 == 0.0 and t1 == 0.0 and t2 == 0.0 and t3 == 0.0, acx, acy, bcx, bcy


@njit(cache=True)
def leading_of_products(a, b, c, d, subtract):
    """Leading component (so the sign) of the exact a b + c d, or a b - c d if
    ``subtract``."""
    l1, l0 = two_product(a, b)
    r1, r0 = two_product(c, d)
    if subtract:
        r1, r0 = -r1, -r0
    x3, x2, x1, x0 = two_two_sum(l1, l0, r1, r0)
    return leading(x3, x2, x1, x0)


@njit(cache=True)
def leading_of_sum(n, xs, ys):
    """Leading component (so the sign) of the exact sum(xs[i] * ys[i], i < n)."""
    w = np.empty(4 * n + 2)
    out = w[0 : 2 * n]
    length = sum_of_products(n, xs, ys, out, w[2 * n : 4 * n], w[4 * n :])
    return out[length - 1]


# ----------------------------------------------------------------------------
# rescaling for the exact path
# ----------------------------------------------------------------------------


@njit(cache=True)
def shift_for(m, target):
    """Power-of-two exponent k such that m * 2**k lies in [2**(target-1), 2**target)."""
    return target - math.frexp(m)[1]


@njit(cache=True)
def pow2(k):
    """2.0**k if that is a normal float (|k| <= 1000), else 0.0."""
    if -1000 <= k <= 1000:
        return math.ldexp(1.0, k)
    return 0.0


@njit(cache=True)
def scale2(x, f, k):
    """x * 2**k, exactly; f = pow2(k) (a plain multiplication when f != 0)."""
    if f != 0.0:
        return x * f
    return math.ldexp(x, k)


@njit(cache=True)
def unscale(top, k):
    """top * 2**-k, as +0.0 for zero and never flushed to zero otherwise."""
    if top == 0.0:
        return 0.0
    r = math.ldexp(top, -k)
    if r == 0.0:
        return math.copysign(_TINIEST, top)
    return r


@njit(cache=True)
def scaled3(ax, ay, bx, by, cx, cy, target):
    """(status, k, a, b, c scaled by 2**k) with the largest |coordinate| in
    [2**(target-1), 2**target).  status -1: a coordinate is not finite; 0: all
    are zero (k = 0, nothing scaled); 1: scaled."""
    if not (
        math.isfinite(ax) and math.isfinite(ay) and math.isfinite(bx)
        and math.isfinite(by) and math.isfinite(cx) and math.isfinite(cy)
    ):
        return -1, 0, ax, ay, bx, by, cx, cy
    m = max(abs(ax), abs(ay), abs(bx), abs(by), abs(cx), abs(cy))
    if m == 0.0:
        return 0, 0, ax, ay, bx, by, cx, cy
    k = shift_for(m, np.int64(target))
    f = pow2(k)
    return (
        1, k, scale2(ax, f, k), scale2(ay, f, k), scale2(bx, f, k),
        scale2(by, f, k), scale2(cx, f, k), scale2(cy, f, k),
    )


@njit(cache=True)
def scaled4(ax, ay, bx, by, cx, cy, dx, dy, target):
    """:func:`scaled3` for four points: (status, k, a, b, c, d scaled by 2**k)."""
    if not (
        math.isfinite(ax) and math.isfinite(ay) and math.isfinite(bx)
        and math.isfinite(by) and math.isfinite(cx) and math.isfinite(cy)
        and math.isfinite(dx) and math.isfinite(dy)
    ):
        return -1, 0, ax, ay, bx, by, cx, cy, dx, dy
    m = max(
        max(abs(ax), abs(ay), abs(bx), abs(by)),
        max(abs(cx), abs(cy), abs(dx), abs(dy)),
    )
    if m == 0.0:
        return 0, 0, ax, ay, bx, by, cx, cy, dx, dy
    k = shift_for(m, np.int64(target))
    f = pow2(k)
    return (
        1, k, scale2(ax, f, k), scale2(ay, f, k), scale2(bx, f, k), scale2(by, f, k),
        scale2(cx, f, k), scale2(cy, f, k), scale2(dx, f, k), scale2(dy, f, k),
    )
