"""Robust geometric predicates: exact signs of orient2d, incircle and dot2d.

Sign conventions (stated here once; ``tests/test_predicates.py`` pins them)
---------------------------------------------------------------------------
``orient2d(ax, ay, bx, by, cx, cy)``
    sign of ``(ax - cx)(by - cy) - (ay - cy)(bx - cx)``.
    > 0 iff a, b, c are in counter-clockwise order (c lies strictly left of
    the directed line a -> b); < 0 iff clockwise; 0 iff exactly collinear.

``incircle(ax, ay, bx, by, cx, cy, dx, dy)``
    sign of the lifted determinant (Shewchuk's ``incircle``).  For a, b, c
    in counter-clockwise order: > 0 iff d lies strictly inside the circle
    through a, b, c; 0 iff the four points are exactly cocircular; < 0 iff d
    lies strictly outside.  The value is antisymmetric in the four points:
    clockwise a, b, c flip the sign, and so does swapping any two points.

``dot2d(ax, ay, bx, by, cx, cy)``
    sign of ``(a - c) . (b - c)``.  > 0 iff the angle at c of triangle abc is
    acute, i.e. c lies strictly outside the closed disk with diameter ab;
    0 iff it is a right angle (c on that circle; also when c == a or c == b);
    < 0 iff c lies strictly inside that disk.

Only the SIGN of the returned float64 is promised, and it is the exact sign
for the float64 inputs as given (each input taken as the exact rational it
represents).  The magnitude is approximate: it is the plain floating-point
determinant when the filter decides, otherwise the leading component of the
exact expansion.  A zero is always returned as ``+0.0``.

How
---
Every predicate evaluates the determinant once in plain floating point and
returns it if its magnitude exceeds a proven forward error bound
(Shewchuk's ``ccwerrboundA`` / ``iccerrboundA``; the bound for ``dot2d`` is
derived below).  That fast path is allocation-free.  Otherwise it falls back
to exact expansion arithmetic (Dekker's ``two_product`` with the 2**27 + 1
split, ``two_sum``, Shewchuk's ``fast_expansion_sum_zeroelim`` and
``scale_expansion_zeroelim``), which decides the sign from the most
significant component.  The exact path first checks whether the coordinate
differences are exact (their ``two_sum`` tails vanish -- the usual case for
nearby points); if so it evaluates the filter's own formula exactly on them
(no allocation for orient2d/dot2d), otherwise it expands the determinant in
the coordinates themselves.  No staged adaptive middle path: degenerate
inputs are rare, and the exact path costs tens of nanoseconds (orient2d,
dot2d with exact differences) to a few microseconds (incircle, general case).

Range of exactness
------------------
* Inputs must be finite (a NaN or infinity gives NaN).
* The exact path first rescales all coordinates by one power of two (exact),
  so overflow can never happen in it: any magnitude up to the float64 maximum
  is fine.  Products of tiny numbers could still underflow; this is ruled out
  whenever every nonzero coordinate is at least 2**-960 (about 1e-289) times
  the largest coordinate magnitude for ``orient2d`` and ``dot2d``, and at
  least 2**-450 (about 3e-136) times it for ``incircle``.  (Proof: after the
  rescaling every intermediate value is an integer multiple of the product of
  the coordinates' ulps over a monomial of the determinant, which these ratios
  keep >= 2**-1074, the subnormal spacing; so gradual underflow rounds exactly
  as an unbounded exponent would and Shewchuk's proofs apply.)
* The filter falls through to the exact path when its bound could be invalid:
  an overflow makes the bound inf/NaN (every comparison fails), and the bound
  is only trusted when its scale (|l| + |r|, or the permanent) is >= 2**-800,
  where the absolute error of an underflowed product (<= 2**-1075, times
  factors < 1 for incircle under the range condition above) is far below the
  bound's slack.  For orient2d and dot2d this holds for every finite input.
* Kernel inputs are normalised to about [-1, 1]; the tests cover 1e-30..1e30
  and beyond.

Never compile this module with ``fastmath``: the error-free transformations
rely on IEEE round-to-nearest-even without reassociation or FMA contraction.

Examples
--------
>>> from uniform2d._kernel.predicates import orient2d, incircle, dot2d
>>> orient2d(0.0, 0.0, 1.0, 0.0, 0.0, 1.0) > 0      # counter-clockwise
True
>>> orient2d(0.0, 0.0, 0.0, 1.0, 1.0, 0.0) < 0      # clockwise
True
>>> incircle(0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 1.0, 1.0) > 0   # centre is inside
True
>>> incircle(-5.0, 0.0, 5.0, 0.0, 3.0, 4.0, -4.0, -3.0)    # exactly cocircular
0.0
>>> dot2d(-5.0, 0.0, 5.0, 0.0, 3.0, 4.0)                   # Thales: right angle
0.0

Near-degenerate inputs where the plain formula gets the sign wrong (c lies
just above the line y = x, so a, b, c are counter-clockwise):

>>> ax, ay, bx, by = 12.0, 12.0, 24.0, 24.0
>>> cx, cy = 0.5000000000000046, 0.5000000000000053
>>> (ax - cx) * (by - cy) - (ay - cy) * (bx - cx) < 0   # plain float: wrong
True
>>> orient2d(ax, ay, bx, by, cx, cy) > 0
True
"""

import math

import numpy as np
from numba import njit

__all__ = [
    "orient2d",
    "incircle",
    "dot2d",
    "EPSILON",
    "CCWERRBOUNDA",
    "ICCERRBOUNDA",
    "DOTERRBOUNDA",
]

#: Half an ulp of 1.0: the relative rounding error bound of one operation.
EPSILON = 2.0**-53
#: Dekker's splitter for 53-bit significands: 2**ceil(53/2) + 1.
_SPLITTER = 2.0**27 + 1.0

#: Shewchuk's orient2d filter constant: |det| > CCWERRBOUNDA * (|l| + |r|).
CCWERRBOUNDA = (3.0 + 16.0 * EPSILON) * EPSILON
#: Shewchuk's incircle filter constant (times the permanent).
ICCERRBOUNDA = (10.0 + 96.0 * EPSILON) * EPSILON

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
#   product; with S >= _FILTER_FLOOR = 2**-800 the e^2 S margin, >= 2**-906,
#   absorbs it, so the filter is valid for every finite input.)
#: dot2d filter constant (see the derivation above); equal to CCWERRBOUNDA.
DOTERRBOUNDA = (3.0 + 16.0 * EPSILON) * EPSILON

# incircle: Shewchuk's bound assumes no underflow.  Under the exact path's
# range condition (nonzero |coords| >= 2**-450 M, M = max |coord|) a nonzero
# coordinate difference is >= 2**-503 M, so a product of two of them can only
# underflow when M < 2**-8, and then the factors it is multiplied by later
# (lifts, cross terms) are < 1.  Each underflowing product thus perturbs det
# by at most ~2**-1075, a dozen of them by < 2**-1070.  Inflating the
# constant by 2**-20 adds >= 2**-21 * 10e * 2**-800 > 2**-880 to the bound
# once permanent >= 2**-800, which covers that with a huge margin; it changes
# no practical decision.
_ICC_FILTER = ICCERRBOUNDA * (1.0 + 2.0**-20)

#: Below this scale the filter is not trusted (possible underflow).
_FILTER_FLOOR = 2.0**-800
#: Smallest positive subnormal: returned (signed) if the exact result's
#: magnitude would underflow when scaled back.
_TINIEST = 5e-324
# The exact path rescales so that the largest |coordinate| is in
# [2**(T-1), 2**T): degree-2 determinants stay below ~2**963 and degree-4
# below ~2**966 (no overflow), while tiny coordinates keep as much headroom
# above the subnormal range as possible.
_TARGET_DEG2 = 480
_TARGET_DEG4 = 240


# ----------------------------------------------------------------------------
# error-free transformations (Knuth's two_sum, Dekker's split / two_product)
# ----------------------------------------------------------------------------


@njit(cache=True)
def _two_sum(a, b):
    """x + y == a + b exactly, x = fl(a + b) (any order of magnitudes)."""
    x = a + b
    bvirt = x - a
    avirt = x - bvirt
    bround = b - bvirt
    around = a - avirt
    return x, around + bround


@njit(cache=True)
def _split(a):
    """a == hi + lo exactly, each half with at most 26 significant bits."""
    c = _SPLITTER * a
    abig = c - a
    hi = c - abig
    return hi, a - hi


@njit(cache=True)
def _two_product(a, b):
    """x + y == a * b exactly, x = fl(a * b) (Dekker, no FMA needed)."""
    x = a * b
    ahi, alo = _split(a)
    bhi, blo = _split(b)
    err1 = x - ahi * bhi
    err2 = err1 - alo * bhi
    err3 = err2 - ahi * blo
    return x, alo * blo - err3


@njit(cache=True)
def _two_two_sum(a1, a0, b1, b0):
    """(x3, x2, x1, x0): nonoverlapping expansion of (a1 + a0) + (b1 + b0).

    Shewchuk's Two_Two_Sum; the inputs must be nonoverlapping pairs (e.g.
    two_product results).  Components may be zero; the nonzero ones increase
    in magnitude from x0 to x3.
    """
    i, x0 = _two_sum(a0, b0)
    j, z = _two_sum(a1, i)
    i, x1 = _two_sum(z, b1)
    x3, x2 = _two_sum(j, i)
    return x3, x2, x1, x0


@njit(cache=True)
def _leading(x3, x2, x1, x0):
    """Most significant nonzero component (it carries the sign of the sum)."""
    if x3 != 0.0:
        return x3
    if x2 != 0.0:
        return x2
    if x1 != 0.0:
        return x1
    return x0


@njit(cache=True)
def _store4(x3, x2, x1, x0, out):
    """Write x0..x3 to out as a zero-eliminated expansion; returns its length."""
    n = 0
    if x0 != 0.0:
        out[n] = x0
        n += 1
    if x1 != 0.0:
        out[n] = x1
        n += 1
    if x2 != 0.0:
        out[n] = x2
        n += 1
    if x3 != 0.0:
        out[n] = x3
        n += 1
    if n == 0:
        out[0] = 0.0
        n = 1
    return n


# ----------------------------------------------------------------------------
# expansion arithmetic (Shewchuk 1997).  An expansion is a[0:n], components
# nonoverlapping and sorted by increasing magnitude; its value is their sum
# and its sign is the sign of a[n - 1].
# ----------------------------------------------------------------------------


@njit(cache=True)
def _expansion_sum(elen, e, flen, f, h):
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
    hindex = 0
    while eindex < elen and findex < flen:
        if (fnow > enow) == (fnow > -enow):
            q, hh = _two_sum(q, enow)
            eindex += 1
            if eindex < elen:
                enow = e[eindex]
        else:
            q, hh = _two_sum(q, fnow)
            findex += 1
            if findex < flen:
                fnow = f[findex]
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    while eindex < elen:
        q, hh = _two_sum(q, enow)
        eindex += 1
        if eindex < elen:
            enow = e[eindex]
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    while findex < flen:
        q, hh = _two_sum(q, fnow)
        findex += 1
        if findex < flen:
            fnow = f[findex]
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    if q != 0.0 or hindex == 0:
        h[hindex] = q
        hindex += 1
    return hindex


@njit(cache=True)
def _scale_expansion(elen, e, b, h):
    """h <- b * e; returns len(h) (>= 1, <= 2 * elen).

    Shewchuk's scale_expansion_zeroelim, two_sum in place of fast_two_sum.
    """
    q, hh = _two_product(e[0], b)
    hindex = 0
    if hh != 0.0:
        h[hindex] = hh
        hindex += 1
    for i in range(1, elen):
        p1, p0 = _two_product(e[i], b)
        s, hh = _two_sum(q, p0)
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
        q, hh = _two_sum(p1, s)
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    if q != 0.0 or hindex == 0:
        h[hindex] = q
        hindex += 1
    return hindex


@njit(cache=True)
def _mul_expansions(elen, e, flen, f, h, t, u):
    """h <- e * f = sum_i e[i] * f; returns len(h) (<= 2 * elen * flen).

    t needs 2 * flen slots, u as many as h.
    """
    hlen = _scale_expansion(flen, f, e[0], h)
    for i in range(1, elen):
        tlen = _scale_expansion(flen, f, e[i], t)
        hlen = _expansion_sum(hlen, h, tlen, t, u)
        for k in range(hlen):
            h[k] = u[k]
    return hlen


@njit(cache=True)
def _sum_of_products(n, xs, ys, out, tmp, term):
    """out <- exact expansion of sum(xs[i] * ys[i], i < n); returns its length.

    out and tmp need 2 * n slots, term 2.
    """
    hi, lo = _two_product(xs[0], ys[0])
    out[0] = lo
    out[1] = hi
    length = 2
    for i in range(1, n):
        hi, lo = _two_product(xs[i], ys[i])
        term[0] = lo
        term[1] = hi
        length = _expansion_sum(length, out, 2, term, tmp)
        for k in range(length):
            out[k] = tmp[k]
    return length


@njit(cache=True)
def _orient_expansion(ax, ay, bx, by, cx, cy, xs, ys, out, tmp, term):
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
    return _sum_of_products(6, xs, ys, out, tmp, term)


# ----------------------------------------------------------------------------
# rescaling for the exact path
# ----------------------------------------------------------------------------


@njit(cache=True)
def _shift_for(m, target):
    """Power-of-two exponent k such that m * 2**k lies in [2**(target-1), 2**target)."""
    return target - math.frexp(m)[1]


@njit(cache=True)
def _pow2(k):
    """2.0**k if that is a normal float (|k| <= 1000), else 0.0."""
    if -1000 <= k <= 1000:
        return math.ldexp(1.0, k)
    return 0.0


@njit(cache=True)
def _scale2(x, f, k):
    """x * 2**k, exactly; f = _pow2(k) (a plain multiplication when f != 0)."""
    if f != 0.0:
        return x * f
    return math.ldexp(x, k)


@njit(cache=True)
def _unscale(top, k):
    """top * 2**-k, as +0.0 for zero and never flushed to zero otherwise."""
    if top == 0.0:
        return 0.0
    r = math.ldexp(top, -k)
    if r == 0.0:
        return math.copysign(_TINIEST, top)
    return r


# ----------------------------------------------------------------------------
# exact fallbacks (called only when the filter cannot decide)
# ----------------------------------------------------------------------------


@njit(cache=True)
def _orient2d_exact(ax, ay, bx, by, cx, cy):
    if not (
        math.isfinite(ax) and math.isfinite(ay) and math.isfinite(bx)
        and math.isfinite(by) and math.isfinite(cx) and math.isfinite(cy)
    ):
        return math.nan
    m = max(abs(ax), abs(ay), abs(bx), abs(by), abs(cx), abs(cy))
    if m == 0.0:
        return 0.0
    k = _shift_for(m, _TARGET_DEG2)
    f = _pow2(k)
    ax = _scale2(ax, f, k)
    ay = _scale2(ay, f, k)
    bx = _scale2(bx, f, k)
    by = _scale2(by, f, k)
    cx = _scale2(cx, f, k)
    cy = _scale2(cy, f, k)
    # Common case (nearby points, Sterbenz): the differences are exact, and
    # the determinant is a two-term sum of two_products.  No allocation.
    acx, t0 = _two_sum(ax, -cx)
    bcy, t1 = _two_sum(by, -cy)
    acy, t2 = _two_sum(ay, -cy)
    bcx, t3 = _two_sum(bx, -cx)
    if t0 == 0.0 and t1 == 0.0 and t2 == 0.0 and t3 == 0.0:
        l1, l0 = _two_product(acx, bcy)
        r1, r0 = _two_product(acy, bcx)
        x3, x2, x1, x0 = _two_two_sum(l1, l0, -r1, -r0)
        return _unscale(_leading(x3, x2, x1, x0), 2 * k)
    # General case: the 6 coordinate monomials ax by - ax cy + ...
    w = np.empty(38)
    xs = w[0:6]
    ys = w[6:12]
    out = w[12:24]
    tmp = w[24:36]
    term = w[36:38]
    n = _orient_expansion(ax, ay, bx, by, cx, cy, xs, ys, out, tmp, term)
    return _unscale(out[n - 1], 2 * k)


@njit(cache=True)
def _dot2d_exact(ax, ay, bx, by, cx, cy):
    if not (
        math.isfinite(ax) and math.isfinite(ay) and math.isfinite(bx)
        and math.isfinite(by) and math.isfinite(cx) and math.isfinite(cy)
    ):
        return math.nan
    m = max(abs(ax), abs(ay), abs(bx), abs(by), abs(cx), abs(cy))
    if m == 0.0:
        return 0.0
    k = _shift_for(m, _TARGET_DEG2)
    f = _pow2(k)
    ax = _scale2(ax, f, k)
    ay = _scale2(ay, f, k)
    bx = _scale2(bx, f, k)
    by = _scale2(by, f, k)
    cx = _scale2(cx, f, k)
    cy = _scale2(cy, f, k)
    acx, t0 = _two_sum(ax, -cx)
    bcx, t1 = _two_sum(bx, -cx)
    acy, t2 = _two_sum(ay, -cy)
    bcy, t3 = _two_sum(by, -cy)
    if t0 == 0.0 and t1 == 0.0 and t2 == 0.0 and t3 == 0.0:  # exact differences
        l1, l0 = _two_product(acx, bcx)
        r1, r0 = _two_product(acy, bcy)
        x3, x2, x1, x0 = _two_two_sum(l1, l0, r1, r0)
        return _unscale(_leading(x3, x2, x1, x0), 2 * k)
    w = np.empty(50)
    xs = w[0:8]
    ys = w[8:16]
    out = w[16:32]
    tmp = w[32:48]
    term = w[48:50]
    # (ax - cx)(bx - cx) + (ay - cy)(by - cy), expanded into 8 monomials
    xs[0] = ax
    ys[0] = bx
    xs[1] = -ax
    ys[1] = cx
    xs[2] = -cx
    ys[2] = bx
    xs[3] = cx
    ys[3] = cx
    xs[4] = ay
    ys[4] = by
    xs[5] = -ay
    ys[5] = cy
    xs[6] = -cy
    ys[6] = by
    xs[7] = cy
    ys[7] = cy
    n = _sum_of_products(8, xs, ys, out, tmp, term)
    return _unscale(out[n - 1], 2 * k)


@njit(cache=True)
def _lift_times(olen, o, px, py, sgn, t24, t48x, t48y, out):
    """out <- sgn * (px**2 + py**2) * o (o: an orientation expansion); length."""
    xlen = _scale_expansion(olen, o, px, t24)
    xlen = _scale_expansion(xlen, t24, sgn * px, t48x)
    ylen = _scale_expansion(olen, o, py, t24)
    ylen = _scale_expansion(ylen, t24, sgn * py, t48y)
    return _expansion_sum(xlen, t48x, ylen, t48y, out)


@njit(cache=True)
def _lift_cross(px, py, ux, uy, vx, vy, lift, cross, t8, t32, out):
    """out <- (px^2 + py^2)(ux vy - vx uy) exactly; returns its length (<= 32)."""
    s1, s0 = _two_product(px, px)
    q1, q0 = _two_product(py, py)
    x3, x2, x1, x0 = _two_two_sum(s1, s0, q1, q0)
    llen = _store4(x3, x2, x1, x0, lift)
    s1, s0 = _two_product(ux, vy)
    q1, q0 = _two_product(vx, uy)
    x3, x2, x1, x0 = _two_two_sum(s1, s0, -q1, -q0)
    clen = _store4(x3, x2, x1, x0, cross)
    return _mul_expansions(llen, lift, clen, cross, out, t8, t32)


@njit(cache=True)
def _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy):
    if not (
        math.isfinite(ax) and math.isfinite(ay) and math.isfinite(bx)
        and math.isfinite(by) and math.isfinite(cx) and math.isfinite(cy)
        and math.isfinite(dx) and math.isfinite(dy)
    ):
        return math.nan
    m = max(
        max(abs(ax), abs(ay), abs(bx), abs(by)),
        max(abs(cx), abs(cy), abs(dx), abs(dy)),
    )
    if m == 0.0:
        return 0.0
    k = _shift_for(m, _TARGET_DEG4)
    f = _pow2(k)
    ax = _scale2(ax, f, k)
    ay = _scale2(ay, f, k)
    bx = _scale2(bx, f, k)
    by = _scale2(by, f, k)
    cx = _scale2(cx, f, k)
    cy = _scale2(cy, f, k)
    dx = _scale2(dx, f, k)
    dy = _scale2(dy, f, k)
    adx, t0 = _two_sum(ax, -dx)
    bdx, t1 = _two_sum(bx, -dx)
    cdx, t2 = _two_sum(cx, -dx)
    ady, t3 = _two_sum(ay, -dy)
    bdy, t4 = _two_sum(by, -dy)
    cdy, t5 = _two_sum(cy, -dy)
    if t0 == 0.0 and t1 == 0.0 and t2 == 0.0 and t3 == 0.0 and t4 == 0.0 and t5 == 0.0:
        # Common case: exact differences.  The filter's formula, exactly:
        # alift (bdx cdy - cdx bdy) + blift (cdx ady - adx cdy)
        #   + clift (adx bdy - bdx ady), three terms of <= 32 components.
        w = np.empty(4 + 4 + 8 + 32 + 3 * 32 + 64 + 96)
        lift = w[0:4]
        cross = w[4:8]
        t8 = w[8:16]
        t32 = w[16:48]
        ta = w[48:80]
        tb = w[80:112]
        tc = w[112:144]
        tab = w[144:208]
        deter = w[208:304]
        alen = _lift_cross(adx, ady, bdx, bdy, cdx, cdy, lift, cross, t8, t32, ta)
        blen = _lift_cross(bdx, bdy, cdx, cdy, adx, ady, lift, cross, t8, t32, tb)
        clen = _lift_cross(cdx, cdy, adx, ady, bdx, bdy, lift, cross, t8, t32, tc)
        ablen = _expansion_sum(alen, ta, blen, tb, tab)
        n = _expansion_sum(ablen, tab, clen, tc, deter)
        return _unscale(deter[n - 1], 4 * k)
    # General case: the 4x4 determinant on the coordinates themselves.
    # workspace: xs 6, ys 6, term 2, o 12, otmp 12, t24 24, t48x 48, t48y 48,
    # four lifted terms 96 each, two pair sums 192 each, result 384
    w = np.empty(6 + 6 + 2 + 12 + 12 + 24 + 48 + 48 + 4 * 96 + 2 * 192 + 384)
    xs = w[0:6]
    ys = w[6:12]
    term = w[12:14]
    o = w[14:26]
    otmp = w[26:38]
    t24 = w[38:62]
    t48x = w[62:110]
    t48y = w[110:158]
    adet = w[158:254]
    bdet = w[254:350]
    cdet = w[350:446]
    ddet = w[446:542]
    abdet = w[542:734]
    cddet = w[734:926]
    deter = w[926:1310]
    # det = |a|^2 [bcd] - |b|^2 [cda] + |c|^2 [dab] - |d|^2 [abc]
    # (the 4x4 determinant with rows (x, y, x^2 + y^2, 1), up to sign;
    # it equals the translated 3x3 determinant of the filter exactly)
    n = _orient_expansion(bx, by, cx, cy, dx, dy, xs, ys, o, otmp, term)
    alen = _lift_times(n, o, ax, ay, 1.0, t24, t48x, t48y, adet)
    n = _orient_expansion(cx, cy, dx, dy, ax, ay, xs, ys, o, otmp, term)
    blen = _lift_times(n, o, bx, by, -1.0, t24, t48x, t48y, bdet)
    n = _orient_expansion(dx, dy, ax, ay, bx, by, xs, ys, o, otmp, term)
    clen = _lift_times(n, o, cx, cy, 1.0, t24, t48x, t48y, cdet)
    n = _orient_expansion(ax, ay, bx, by, cx, cy, xs, ys, o, otmp, term)
    dlen = _lift_times(n, o, dx, dy, -1.0, t24, t48x, t48y, ddet)
    ablen = _expansion_sum(alen, adet, blen, bdet, abdet)
    cdlen = _expansion_sum(clen, cdet, dlen, ddet, cddet)
    n = _expansion_sum(ablen, abdet, cdlen, cddet, deter)
    return _unscale(deter[n - 1], 4 * k)


# ----------------------------------------------------------------------------
# public predicates: filter, then exact fallback
# ----------------------------------------------------------------------------

@njit(cache=True)
def orient2d(ax, ay, bx, by, cx, cy):
    """> 0 iff a, b, c counter-clockwise; 0 iff collinear (exact sign)."""
    detleft = (ax - cx) * (by - cy)
    detright = (ay - cy) * (bx - cx)
    det = detleft - detright
    detsum = abs(detleft) + abs(detright)
    if detsum >= _FILTER_FLOOR and abs(det) > CCWERRBOUNDA * detsum:
        return det
    return _orient2d_exact(ax, ay, bx, by, cx, cy)


@njit(cache=True)
def incircle(ax, ay, bx, by, cx, cy, dx, dy):
    """For CCW a, b, c: > 0 iff d strictly inside their circle; 0 iff cocircular."""
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    alift = adx * adx + ady * ady
    cdxady = cdx * ady
    adxcdy = adx * cdy
    blift = bdx * bdx + bdy * bdy
    adxbdy = adx * bdy
    bdxady = bdx * ady
    clift = cdx * cdx + cdy * cdy
    det = (
        alift * (bdxcdy - cdxbdy)
        + blift * (cdxady - adxcdy)
        + clift * (adxbdy - bdxady)
    )
    permanent = (
        (abs(bdxcdy) + abs(cdxbdy)) * alift
        + (abs(cdxady) + abs(adxcdy)) * blift
        + (abs(adxbdy) + abs(bdxady)) * clift
    )
    if permanent >= _FILTER_FLOOR and abs(det) > _ICC_FILTER * permanent:
        return det
    return _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy)


@njit(cache=True)
def dot2d(ax, ay, bx, by, cx, cy):
    """Sign of (a - c).(b - c): > 0 acute at c, 0 right angle, < 0 obtuse."""
    left = (ax - cx) * (bx - cx)
    right = (ay - cy) * (by - cy)
    det = left + right
    detsum = abs(left) + abs(right)
    if detsum >= _FILTER_FLOOR and abs(det) > DOTERRBOUNDA * detsum:
        return det
    return _dot2d_exact(ax, ay, bx, by, cx, cy)
