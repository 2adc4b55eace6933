"""incircle: the exact sign of the in-circle determinant of four points.

Sign convention and range of exactness: :mod:`.predicates` (stated there once).
A plain floating-point determinant decides when it clears Shewchuk's
``iccerrboundA`` (slightly inflated, see below); otherwise the exact path does:
on the coordinate differences when they are exact (the usual case), else on
the coordinates themselves (:mod:`.expansion`).  On exact differences it first
evaluates the filter's formula in plain floating point and keeps the result
when no operation rounded (:func:`_without_rounding`): exactly cocircular
points with few significant bits, the common failed filter on symmetric
domains, then cost no expansion.
"""

import numpy as np
from ._jit import njit

from .expansion import (
    EPSILON,
    FILTER_FLOOR,
    TARGET_DEG4,
    expansion_sum,
    mul_expansions,
    scale_expansion,
    scaled4,
    store4,
    two_product,
    two_sum,
    two_two_sum,
    unscale,
)
from .external import compiled_once
from .orient import orient_expansion

__all__ = ["incircle", "ICCERRBOUNDA"]

#: Shewchuk's incircle filter constant (times the permanent).
ICCERRBOUNDA = (10.0 + 96.0 * EPSILON) * EPSILON

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


@njit(cache=True, borrowed=True)
def _lift_times(olen, o, px, py, sgn, t24, t48x, t48y, out):
    """out <- sgn * (px**2 + py**2) * o (o: an orientation expansion); length."""
    xlen = scale_expansion(olen, o, px, t24)
    xlen = scale_expansion(xlen, t24, sgn * px, t48x)
    ylen = scale_expansion(olen, o, py, t24)
    ylen = scale_expansion(ylen, t24, sgn * py, t48y)
    return expansion_sum(xlen, t48x, ylen, t48y, out)


@njit(cache=True, borrowed=True)
def _lift_cross(px, py, ux, uy, vx, vy, lift, cross, t8, t32, out):
    """out <- (px^2 + py^2)(ux vy - vx uy) exactly; returns its length (<= 32)."""
    s1, s0 = two_product(px, px)
    q1, q0 = two_product(py, py)
    x3, x2, x1, x0 = two_two_sum(s1, s0, q1, q0)
    llen = store4(x3, x2, x1, x0, lift)
    s1, s0 = two_product(ux, vy)
    q1, q0 = two_product(vx, uy)
    x3, x2, x1, x0 = two_two_sum(s1, s0, -q1, -q0)
    clen = store4(x3, x2, x1, x0, cross)
    return mul_expansions(llen, lift, clen, cross, out, t8, t32)


@njit(cache=True)
def _on_differences(adx, ady, bdx, bdy, cdx, cdy):
    """Leading component of the filter's formula evaluated exactly on exact
    differences: alift (bdx cdy - cdx bdy) + blift (cdx ady - adx cdy)
    + clift (adx bdy - bdx ady), three terms of <= 32 components."""
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
    ablen = expansion_sum(alen, ta, blen, tb, tab)
    n = expansion_sum(ablen, tab, clen, tc, deter)
    return deter[n - 1]


@njit(cache=True)
def _on_coordinates(ax, ay, bx, by, cx, cy, dx, dy):
    """Leading component of the 4x4 determinant on the coordinates themselves:
    det = |a|^2 [bcd] - |b|^2 [cda] + |c|^2 [dab] - |d|^2 [abc] (the determinant
    with rows (x, y, x^2 + y^2, 1), up to sign; it equals the translated 3x3
    determinant of the filter exactly)."""
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
    n = orient_expansion(bx, by, cx, cy, dx, dy, xs, ys, o, otmp, term)
    alen = _lift_times(n, o, ax, ay, 1.0, t24, t48x, t48y, adet)
    n = orient_expansion(cx, cy, dx, dy, ax, ay, xs, ys, o, otmp, term)
    blen = _lift_times(n, o, bx, by, -1.0, t24, t48x, t48y, bdet)
    n = orient_expansion(dx, dy, ax, ay, bx, by, xs, ys, o, otmp, term)
    clen = _lift_times(n, o, cx, cy, 1.0, t24, t48x, t48y, cdet)
    n = orient_expansion(ax, ay, bx, by, cx, cy, xs, ys, o, otmp, term)
    dlen = _lift_times(n, o, dx, dy, -1.0, t24, t48x, t48y, ddet)
    ablen = expansion_sum(alen, adet, blen, bdet, abdet)
    cdlen = expansion_sum(clen, cdet, dlen, ddet, cddet)
    n = expansion_sum(ablen, abdet, cdlen, cddet, deter)
    return deter[n - 1]


@njit(cache=True)
def _without_rounding(adx, ady, bdx, bdy, cdx, cdy):
    """(exact, det): the filter's formula on exact differences in plain floating
    point, and whether no operation rounded (every two_product / two_sum tail
    vanishes), in which case det is the exact determinant.

    Cocircular points with few significant bits -- the lattice-like meshes of
    symmetric domains, where most failed filters come from -- pass this, and
    it needs no expansion (no workspace to allocate): a few dozen flops where
    :func:`_on_differences` costs about a microsecond."""
    p1, e1 = two_product(bdx, cdy)
    p2, e2 = two_product(cdx, bdy)
    p3, e3 = two_product(cdx, ady)
    p4, e4 = two_product(adx, cdy)
    p5, e5 = two_product(adx, bdy)
    p6, e6 = two_product(bdx, ady)
    if e1 != 0.0 or e2 != 0.0 or e3 != 0.0 or e4 != 0.0 or e5 != 0.0 or e6 != 0.0:
        return False, 0.0
    c1, f1 = two_sum(p1, -p2)
    c2, f2 = two_sum(p3, -p4)
    c3, f3 = two_sum(p5, -p6)
    if f1 != 0.0 or f2 != 0.0 or f3 != 0.0:
        return False, 0.0
    la, ok = _lift(adx, ady)
    lb, okb = _lift(bdx, bdy)
    lc, okc = _lift(cdx, cdy)
    if not (ok and okb and okc):
        return False, 0.0
    t1, g1 = two_product(la, c1)
    t2, g2 = two_product(lb, c2)
    t3, g3 = two_product(lc, c3)
    if g1 != 0.0 or g2 != 0.0 or g3 != 0.0:
        return False, 0.0
    s, h1 = two_sum(t1, t2)
    det, h2 = two_sum(s, t3)
    return h1 == 0.0 and h2 == 0.0, det


@njit(cache=True)
def _lift(px, py):
    """(px**2 + py**2, whether it is exact)."""
    x, ex = two_product(px, px)
    y, ey = two_product(py, py)
    z, ez = two_sum(x, y)
    return z, ex == 0.0 and ey == 0.0 and ez == 0.0


@njit(cache=True, inline="always")
def incircle_exact(ax, ay, bx, by, cx, cy, dx, dy):
    """incircle by exact arithmetic (called only when the filter cannot decide)."""
    ok, k, ax, ay, bx, by, cx, cy, dx, dy = scaled4(ax, ay, bx, by, cx, cy, dx, dy, TARGET_DEG4)
    if ok <= 0:
        return np.nan if ok < 0 else 0.0
    adx, t0 = two_sum(ax, -dx)
    bdx, t1 = two_sum(bx, -dx)
    cdx, t2 = two_sum(cx, -dx)
    ady, t3 = two_sum(ay, -dy)
    bdy, t4 = two_sum(by, -dy)
    cdy, t5 = two_sum(cy, -dy)
    if t0 == 0.0 and t1 == 0.0 and t2 == 0.0 and t3 == 0.0 and t4 == 0.0 and t5 == 0.0:
        exact, det = _without_rounding(adx, ady, bdx, bdy, cdx, cdy)
        if exact:  # the exact value is one float: the expansion's only component
            return unscale(det, 4 * k)
        return unscale(_on_differences(adx, ady, bdx, bdy, cdx, cdy), 4 * k)
    return unscale(_on_coordinates(ax, ay, bx, by, cx, cy, dx, dy), 4 * k)


_incircle_exact = compiled_once(incircle_exact.py_func, 8)


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
    if permanent >= FILTER_FLOOR and abs(det) > _ICC_FILTER * permanent:
        return det
    return _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy)
