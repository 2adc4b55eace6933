"""Exactness of the robust predicates in ``uniform2d._kernel.predicates``.

Every sign is checked against exact rational arithmetic (each float converted
exactly with ``Fraction``), on inputs built to defeat floating point:
ulp-grids around lines, circles and Thales circles (Shewchuk's near-degenerate
grid experiment), exactly degenerate configurations, huge / tiny / translated
coordinates and random (hypothesis, derandomized) inputs.  Separate tests pin
the sign conventions, show that the float filter is what answers easy inputs,
and show that the exact path is what answers the cases plain floating point
gets wrong.
"""

from __future__ import annotations

import itertools
import math
import sys
import subprocess
import os
from fractions import Fraction
from functools import lru_cache

import numba
from numba.core.caching import FunctionCache
import numpy as np
import pytest
from hypothesis import assume, HealthCheck, given, settings
from hypothesis import strategies as st

from uniform2d._kernel import dot as kdot
from uniform2d._kernel import expansion as xp
from uniform2d._kernel import incircle as kinc
from uniform2d._kernel import orient as korient
from uniform2d._kernel import predicates as pred
from uniform2d._kernel.predicates import dot2d, incircle, orient2d

# One fixed hypothesis profile for every random test: reproducible, no deadline.
HYP = settings(
    max_examples=250,
    derandomize=True,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)


# --------------------------------------------------------------------------
# exact references and the plain floating-point formulas
# --------------------------------------------------------------------------


def sgn(x) -> int:
    return (x > 0) - (x < 0)


def exact_orient(ax, ay, bx, by, cx, cy) -> int:
    ax, ay, bx, by, cx, cy = (Fraction(float(v)) for v in (ax, ay, bx, by, cx, cy))
    return sgn((ax - cx) * (by - cy) - (ay - cy) * (bx - cx))


def exact_incircle(ax, ay, bx, by, cx, cy, dx, dy) -> int:
    ax, ay, bx, by, cx, cy, dx, dy = (
        Fraction(float(v)) for v in (ax, ay, bx, by, cx, cy, dx, dy)
    )
    adx, ady, bdx, bdy, cdx, cdy = ax - dx, ay - dy, bx - dx, by - dy, cx - dx, cy - dy
    alift = adx * adx + ady * ady
    blift = bdx * bdx + bdy * bdy
    clift = cdx * cdx + cdy * cdy
    return sgn(
        alift * (bdx * cdy - cdx * bdy)
        + blift * (cdx * ady - adx * cdy)
        + clift * (adx * bdy - bdx * ady)
    )


def exact_dot(ax, ay, bx, by, cx, cy) -> int:
    ax, ay, bx, by, cx, cy = (Fraction(float(v)) for v in (ax, ay, bx, by, cx, cy))
    return sgn((ax - cx) * (bx - cx) + (ay - cy) * (by - cy))


# The plain formulas, evaluated exactly as the filters evaluate them (Python
# floats are IEEE doubles with the same rounding).
def naive_orient(ax, ay, bx, by, cx, cy):
    return (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)


def naive_incircle(ax, ay, bx, by, cx, cy, dx, dy):
    adx, bdx, cdx = ax - dx, bx - dx, cx - dx
    ady, bdy, cdy = ay - dy, by - dy, cy - dy
    alift = adx * adx + ady * ady
    blift = bdx * bdx + bdy * bdy
    clift = cdx * cdx + cdy * cdy
    return (
        alift * (bdx * cdy - cdx * bdy)
        + blift * (cdx * ady - adx * cdy)
        + clift * (adx * bdy - bdx * ady)
    )


def naive_dot(ax, ay, bx, by, cx, cy):
    return (ax - cx) * (bx - cx) + (ay - cy) * (by - cy)


def filter_decides_orient(ax, ay, bx, by, cx, cy) -> bool:
    left = (ax - cx) * (by - cy)
    right = (ay - cy) * (bx - cx)
    s = abs(left) + abs(right)
    return s >= pred.FILTER_FLOOR and abs(left - right) > pred.CCWERRBOUNDA * s


PREDICATES = {
    "orient2d": (orient2d, korient.orient2d_exact, exact_orient, naive_orient),
    "incircle": (incircle, kinc.incircle_exact, exact_incircle, naive_incircle),
    "dot2d": (dot2d, kdot.dot2d_exact, exact_dot, naive_dot),
}


# --------------------------------------------------------------------------
# case generators (deterministic)
# --------------------------------------------------------------------------


def ulp_walk(x: float, lo: int, hi: int) -> list[float]:
    """[x moved k ulps for k in lo..hi] with np.nextafter (k < 0 goes down)."""
    x = np.float64(x)
    up, down = [x], [x]
    for _ in range(max(hi, 0)):
        up.append(np.nextafter(up[-1], np.inf))
    for _ in range(max(-lo, 0)):
        down.append(np.nextafter(down[-1], -np.inf))
    walk = down[::-1] + up[1:]
    return [float(v) for v in walk[len(down) - 1 + lo : len(down) + hi]]


def grid_around(px: float, py: float, n: int) -> list[tuple[float, float]]:
    """All points (px, py) nudged by -n..n ulps in x and in y."""
    xs, ys = ulp_walk(px, -n, n), ulp_walk(py, -n, n)
    return [(x, y) for x in xs for y in ys]


@lru_cache(maxsize=None)
def orient_families() -> dict[str, list[tuple]]:
    fam = {}
    # Shewchuk's experiment: c walks an ulp grid next to the line y = x.
    xs = ulp_walk(0.5, 0, 63)
    fam["shewchuk"] = [(12.0, 12.0, 24.0, 24.0, x, y) for x in xs for y in xs]
    # A skew line: c nudged around the rounded point a + t (b - a).
    a, b = (-3.7, 1.3), (5.1, 9.9)
    c0 = (a[0] + 0.37 * (b[0] - a[0]), a[1] + 0.37 * (b[1] - a[1]))
    skew = [(*a, *b, x, y) for x, y in grid_around(*c0, 16)]
    fam["skew"] = skew
    # The same geometry translated far from the origin (small differences).
    a, b = (1e6 + 0.1, 1e6 + 0.2), (1e6 + 1.7, 1e6 + 3.1)
    c0 = (a[0] + 0.6 * (b[0] - a[0]), a[1] + 0.6 * (b[1] - a[1]))
    fam["translated_1e6"] = [(*a, *b, x, y) for x, y in grid_around(*c0, 16)]
    # Huge and tiny scales: scale a, b, then build the nudged grid at that scale.
    for s in (1e-30, 1e-6, 1e6, 1e30, 1e-300, 1e300):
        a = (-3.7 * s, 1.3 * s)
        b = (5.1 * s, 9.9 * s)
        c0 = (a[0] + 0.37 * (b[0] - a[0]), a[1] + 0.37 * (b[1] - a[1]))
        fam[f"scale_{s:g}"] = [(*a, *b, x, y) for x, y in grid_around(*c0, 6)]
    return fam


def circle_point(cx, cy, r, theta):
    return (cx + r * math.cos(theta), cy + r * math.sin(theta))


@lru_cache(maxsize=None)
def incircle_families() -> dict[str, list[tuple]]:
    fam = {}
    for name, (ox, oy, r) in {
        "unit": (0.0, 0.0, 1.0),
        "translated_1e3": (1e3, -2e3, 1.0),
        "translated_1e6": (1e6, 1e6, 3.0),
        "r_1e-6": (0.0, 0.0, 1e-6),
        "r_1e6": (0.0, 0.0, 1e6),
        "r_1e-30": (1e-30, 0.0, 1e-30),
        "r_1e30": (0.0, -1e30, 1e30),
        "r_1e-100": (0.0, 0.0, 1e-100),
        "r_1e100": (0.0, 0.0, 1e100),
    }.items():
        a = circle_point(ox, oy, r, 0.3)
        b = circle_point(ox, oy, r, 2.1)
        c = circle_point(ox, oy, r, 4.0)
        d0 = circle_point(ox, oy, r, 5.2)
        n = 10 if name in ("unit", "translated_1e6") else 5
        fam[name] = [(*a, *b, *c, x, y) for x, y in grid_around(*d0, n)]
    # d nudged around a corner of a rectangle (all four corners cocircular)
    x0, x1, y0, y1 = 0.1, 0.7, -0.3, 1.9
    fam["rectangle"] = [(x0, y0, x1, y0, x1, y1, x, y) for x, y in grid_around(x0, y1, 8)]
    # integer points of the circle of radius 65 (exactly cocircular grid centres)
    for name, (ox, oy) in {"pythagorean": (0.0, 0.0), "pythagorean_1e6": (1e6, -1e6)}.items():
        a, b, c = (ox + 65.0, oy), (ox, oy + 65.0), (ox - 52.0, oy - 39.0)
        fam[name] = [
            (*a, *b, *c, x, y)
            for d0 in ((ox + 39.0, oy - 52.0), (ox - 16.0, oy + 63.0), (ox + 60.0, oy + 25.0))
            for x, y in grid_around(*d0, 4)
        ]
    return fam


@lru_cache(maxsize=None)
def dot_families() -> dict[str, list[tuple]]:
    fam = {}
    for name, (a, b, thetas, n) in {
        "thales_unit": ((-1.0, 0.0), (1.0, 0.0), (0.7, 1.9, 4.4), 8),
        "skew": ((-0.35, 0.8), (0.9, -0.15), (0.2, 2.5), 8),
        "translated_1e6": ((1e6 - 0.35, 1e6 + 0.8), (1e6 + 0.9, 1e6 - 0.15), (0.2, 2.5), 8),
        "scale_1e-6": ((-0.35e-6, 0.8e-6), (0.9e-6, -0.15e-6), (1.1,), 5),
        "scale_1e6": ((-0.35e6, 0.8e6), (0.9e6, -0.15e6), (1.1,), 5),
        "scale_1e-30": ((-0.35e-30, 0.8e-30), (0.9e-30, -0.15e-30), (1.1,), 5),
        "scale_1e30": ((-0.35e30, 0.8e30), (0.9e30, -0.15e30), (1.1,), 5),
        "scale_1e-300": ((-0.35e-300, 0.8e-300), (0.9e-300, -0.15e-300), (1.1,), 5),
        "scale_1e300": ((-0.35e300, 0.8e300), (0.9e300, -0.15e300), (1.1,), 5),
    }.items():
        mx, my = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2
        r = math.hypot(b[0] - a[0], b[1] - a[1]) / 2
        cases = []
        for t in thetas:
            c0 = circle_point(mx, my, r, t)
            cases += [(*a, *b, x, y) for x, y in grid_around(*c0, n)]
        fam[name] = cases
    # Thales with integer points: the centre of each grid is an exact right angle
    for name, (ox, oy) in {"thales_pythagorean": (0.0, 0.0),
                           "thales_pythagorean_1e6": (1e6, 5.0)}.items():
        fam[name] = [
            (ox - 65.0, oy, ox + 65.0, oy, x, y)
            for c0 in ((63.0, 16.0), (-33.0, 56.0), (39.0, -52.0))
            for x, y in grid_around(ox + c0[0], oy + c0[1], 6)
        ]
    return fam


FAMILIES = {"orient2d": orient_families, "incircle": incircle_families, "dot2d": dot_families}


@lru_cache(maxsize=None)
def tally(name: str) -> dict[str, int]:
    """Check every family case of one predicate; return counts."""
    fn, exact_fn, ref, naive = PREDICATES[name]
    counts = dict(cases=0, zero=0, naive_wrong=0, naive_opposite=0, exact_diffs=0)
    for fam, cases in FAMILIES[name]().items():
        for args in cases:
            e = ref(*args)
            # the exact path has two branches: exact coordinate differences
            # (relative to the last point) or not; count which one applies
            ox, oy = args[-2:]
            counts["exact_diffs"] += all(
                Fraction(v - o) == Fraction(v) - Fraction(o)
                for v, o in zip(args[:-2], (ox, oy) * 3)
            )
            got = fn(*args)
            assert sgn(got) == e, (name, fam, args, got, e)
            assert sgn(exact_fn(*args)) == e, (name, fam, args, "exact path")
            nv = naive(*args)
            counts["cases"] += 1
            counts["zero"] += e == 0
            if math.isfinite(nv) and sgn(nv) != e:
                counts["naive_wrong"] += 1
                counts["naive_opposite"] += sgn(nv) == -e != 0
    return counts


# --------------------------------------------------------------------------
# sign conventions
# --------------------------------------------------------------------------


def test_orient2d_convention():
    assert orient2d(0.0, 0.0, 1.0, 0.0, 0.0, 1.0) > 0  # CCW: c left of a->b
    assert orient2d(0.0, 0.0, 0.0, 1.0, 1.0, 0.0) < 0  # CW
    assert orient2d(0.0, 0.0, 1.0, 1.0, 3.0, 3.0) == 0.0  # collinear
    assert orient2d(0.0, 0.0, 1.0, 1.0, 0.0, 0.0) == 0.0  # repeated point
    # value of the filter = twice the signed area
    assert orient2d(0.0, 0.0, 4.0, 0.0, 0.0, 3.0) == 12.0


def test_incircle_convention():
    a, b, c = (0.0, 0.0), (2.0, 0.0), (0.0, 2.0)  # CCW, circle centre (1, 1), r^2 = 2
    assert incircle(*a, *b, *c, 1.0, 1.0) > 0  # inside
    assert incircle(*a, *b, *c, 3.0, 3.0) < 0  # outside
    assert incircle(*a, *b, *c, 2.0, 2.0) == 0.0  # on the circle
    assert incircle(*a, *c, *b, 1.0, 1.0) < 0  # clockwise a, b, c flip the sign
    assert incircle(*a, *b, *c, *a) == 0.0  # d equal to a vertex


def test_dot2d_convention():
    a, b = (-1.0, 0.0), (1.0, 0.0)  # diametral disk: the unit disk
    assert dot2d(*a, *b, 0.0, 2.0) > 0  # outside: acute angle at c
    assert dot2d(*a, *b, 0.0, 0.5) < 0  # inside: obtuse angle at c
    assert dot2d(*a, *b, 0.0, 1.0) == 0.0  # on the circle: right angle
    assert dot2d(*a, *b, *a) == 0.0  # c == a
    assert dot2d(*a, *b, 5.0, 0.0) > 0  # beyond b on the line


# --------------------------------------------------------------------------
# near-degenerate grids: every sign exact, and plain floats fail often
# --------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["orient2d", "incircle", "dot2d"])
def test_near_degenerate_grids_exact(name):
    c = tally(name)
    assert c["cases"] > 1000
    # the grids straddle the degeneracy: both exact zeros and plenty of cases
    # where the plain float formula gets the sign wrong
    assert c["zero"] >= 5, c
    assert c["naive_wrong"] >= 50, c
    # both branches of the exact path are exercised (every case also goes
    # through the exact path directly in tally())
    assert 100 <= c["exact_diffs"] <= c["cases"] - 100, c


def test_plain_float_wrong_sign_decided_correctly():
    """Cases where the plain formula has the OPPOSITE sign exist and are right."""
    assert tally("orient2d")["naive_opposite"] >= 20
    assert tally("incircle")["naive_opposite"] >= 20
    assert tally("dot2d")["naive_opposite"] >= 5
    # a specific one from Shewchuk's grid (also in the module docstring)
    args = (12.0, 12.0, 24.0, 24.0, 0.5000000000000046, 0.5000000000000053)
    assert naive_orient(*args) < 0 < exact_orient(*args)
    assert orient2d(*args) > 0


def test_shewchuk_grid_mostly_undecidable_by_filter():
    """Most of the grid really goes through the exact path."""
    cases = orient_families()["shewchuk"]
    fallbacks = sum(not filter_decides_orient(*a) for a in cases)
    assert fallbacks > len(cases) // 2
    # exactly collinear points: the diagonal of the grid
    assert sum(orient2d(*a) == 0.0 for a in cases) == 64


# --------------------------------------------------------------------------
# exactly degenerate configurations must give exactly 0.0
# --------------------------------------------------------------------------

PYTH65 = [(65, 0), (63, 16), (60, 25), (56, 33), (52, 39), (39, 52), (33, 56), (25, 60),
          (16, 63), (0, 65), (-16, 63), (-33, 56), (-52, -39), (-60, -25), (39, -52)]


def test_incircle_exactly_cocircular():
    rng = np.random.default_rng(12345)
    n_naive_nonzero = 0
    for _ in range(60):  # rectangles with arbitrary float corners
        x0, x1 = rng.uniform(-10, 10, 2)
        y0, y1 = rng.uniform(-10, 10, 2)
        if rng.random() < 0.5:
            x0, x1, y0, y1 = x0 + 1e6, x1 + 1e6, y0 - 1e6, y1 - 1e6
        corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        for perm in itertools.permutations(corners):
            args = tuple(float(v) for p in perm for v in p)
            assert incircle(*args) == 0.0
            n_naive_nonzero += naive_incircle(*args) != 0.0
    assert n_naive_nonzero > 100  # plain floats do not see these as cocircular
    for k, (ox, oy) in itertools.product((-40, -20, 0, 30), ((0, 0), (1e6, -3e7), (2**40, 7))):
        s = 2.0**k
        pts = [(ox + s * x, oy + s * y) for x, y in PYTH65]
        if any(Fraction(px) != ox + Fraction(s * x) for (px, _), (x, _) in zip(pts, PYTH65)):
            continue  # translation not exact in float64 at this scale
        for quad in itertools.combinations(pts[:9], 4):
            assert incircle(*(v for p in quad for v in p)) == 0.0


def test_orient2d_and_dot2d_exact_zeros():
    rng = np.random.default_rng(7)
    for _ in range(200):
        # 30-bit coordinates, so that the integer offsets below are exact
        ax, ay = (float(v) * 2.0**-10 for v in rng.integers(-(2**30), 2**30, 2))
        p, q, t = (float(v) for v in rng.integers(-1000, 1000, 3))
        cx, cy = ax + p, ay + q
        assert orient2d(ax, ay, cx, cy, ax + 2 * p, ay + 2 * q) == 0.0
        # right angle at c: (a - c) = -(p, q), (b - c) = t (-q, p)
        bx, by = cx - t * q, cy + t * p
        assert dot2d(ax, ay, bx, by, cx, cy) == 0.0
    for k in (-50, -20, 0, 20, 50):
        s = 2.0**k
        for x, y in PYTH65:  # Thales: right angle on the diameter's circle
            assert dot2d(-65 * s, 0.0, 65 * s, 0.0, x * s, y * s) == 0.0
            if abs(k) <= 20:  # translation exact in float64
                assert dot2d(1e6 - 65 * s, 3.0, 1e6 + 65 * s, 3.0,
                             1e6 + x * s, 3.0 + y * s) == 0.0


def inexact_differences(args) -> list[int]:
    """Indices of the coordinate differences (relative to the last point, as
    the filters and the exact paths form them) that are not exact in float64."""
    ox, oy = args[-2:]
    return [
        i
        for i, (v, o) in enumerate(zip(args[:-2], (ox, oy) * 3))
        if Fraction(v - o) != Fraction(v) - Fraction(o)
    ]


def rounded_difference_sign(name, args) -> int:
    """Exact sign of the determinant of the ROUNDED differences: what an exact
    path that ignored the difference tails would answer."""
    ox, oy = args[-2:]
    d = [Fraction(v - o) for v, o in zip(args[:-2], (ox, oy) * 3)]
    if name == "orient2d":
        return sgn(d[0] * d[3] - d[1] * d[2])
    if name == "dot2d":
        return sgn(d[0] * d[2] + d[1] * d[3])
    adx, ady, bdx, bdy, cdx, cdy = d
    return sgn((adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
               + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
               + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady))


MIXED = [1.0, 1.0 + 2**-52, 3 * 2**-53, 2**-30, 0.1, 0.7, 1e6 + 0.5, 3.0, 2.0**53, 2**-60]


def single_inexact_zero_cases():
    """Exactly degenerate inputs in which exactly ONE coordinate difference is
    inexact, for every difference position of every predicate."""
    cases = {"orient2d": [], "incircle": [], "dot2d": []}
    for u, v in itertools.product(MIXED, repeat=2):
        # collinear through the origin: (-u, -v), s (u, v), t (u, v)
        for s, t in ((2.0, 0.5), (-0.5, 2.0), (0.25, -0.5), (1.0, 0.0)):
            for perm in itertools.permutations([(-u, -v), (s * u, s * v), (t * u, t * v)]):
                cases["orient2d"].append(tuple(x for p in perm for x in p))
    for u, w, v, z in itertools.product(MIXED[::2], MIXED[1::2], MIXED[1::3], MIXED[::3]):
        # isosceles trapezoids are cyclic (and so are their transposes)
        pts = [(-u, v), (u, v), (-w, z), (w, z)]
        for tr in (pts, [(y, x) for x, y in pts]):
            for perm in itertools.permutations(tr):
                cases["incircle"].append(tuple(x for p in perm for x in p))
    # right angle at c: a - c = (p, q), b - c = (-q, p) / m, where p = 2**e + 1
    # needs 54+ bits but p / m does not (2**53 + 1 = 3 * ..., 2**54 + 1 = 5 * ...)
    for e, m in ((53, 3), (54, 5)):
        p = 2**e + 1
        for q, tx, ty in itertools.product((m, -2 * m), (0, 4, -4), (0, 1, -5)):
            cx, cy = -1 + tx, ty
            a = (float(cx + p), float(cy + q))
            b = (float(cx - q // m), float(cy + p // m))
            c = (float(cx), float(cy))
            for (ax, ay), (bx, by) in ((a, b), (b, a)):
                for tr in (False, True):
                    args = (ax, ay, bx, by, *c)
                    if tr:
                        args = (ay, ax, by, bx, c[1], c[0])
                    cases["dot2d"].append(args)
    out = {}
    for name, lst in cases.items():
        out[name] = [
            a for a in lst
            if len(inexact_differences(a)) == 1 and rounded_difference_sign(name, a) != 0
        ]
    return out


def test_exact_path_uses_difference_tails():
    """Exact zeros where exactly one difference is inexact and ignoring its
    rounding error would give a nonzero sign -- for every difference slot."""
    for name, cases in single_inexact_zero_cases().items():
        fn, exact_fn, ref, _ = PREDICATES[name]
        slots = {inexact_differences(a)[0] for a in cases}
        assert slots == set(range(6 if name == "incircle" else 4)), (name, slots)
        for args in cases:
            assert ref(*args) == 0, (name, args)  # the construction is exact
            assert fn(*args) == 0.0, (name, args)
            assert exact_fn(*args) == 0.0, (name, args)


def test_incircle_unrounded_stage_exact_when_it_claims_to_be():
    """The exact path's first stage (the filter's formula in plain floats, kept
    when no operation rounded) answers with the exact determinant whenever it
    claims to, claims it for few-bit coordinates (lattice-like meshes), and
    leaves many-bit ones to the expansions."""
    rng = np.random.default_rng(3)
    claimed = declined = 0
    for bits in (4, 12, 20, 53):
        for _ in range(300):
            if bits == 53:
                d = rng.uniform(-1, 1, 6)
            else:
                d = rng.integers(-(2**bits), 2**bits, 6) * 2.0**-bits
            adx, ady, bdx, bdy, cdx, cdy = (float(v) for v in d)
            exact, det = kinc._without_rounding(adx, ady, bdx, bdy, cdx, cdy)
            A, B, C = ((Fraction(x), Fraction(y)) for x, y in ((adx, ady), (bdx, bdy), (cdx, cdy)))
            ref = (
                (A[0] ** 2 + A[1] ** 2) * (B[0] * C[1] - C[0] * B[1])
                + (B[0] ** 2 + B[1] ** 2) * (C[0] * A[1] - A[0] * C[1])
                + (C[0] ** 2 + C[1] ** 2) * (A[0] * B[1] - B[0] * A[1])
            )
            if exact:
                assert Fraction(det) == ref, (bits, d)
                claimed += 1
            else:
                declined += 1
            if bits <= 12:
                assert exact, (bits, d)  # 4 * 13 bits fit in a significand
    assert claimed >= 600 and declined >= 300


# --------------------------------------------------------------------------
# symmetry properties (the filter formula is not symmetric: this is exactness)
# --------------------------------------------------------------------------


def test_orient2d_permutations():
    for args in orient_families()["shewchuk"][::7] + orient_families()["translated_1e6"][::3]:
        a, b, c = args[0:2], args[2:4], args[4:6]
        s = sgn(orient2d(*a, *b, *c))
        assert sgn(orient2d(*b, *c, *a)) == s
        assert sgn(orient2d(*c, *a, *b)) == s
        assert sgn(orient2d(*b, *a, *c)) == -s
        assert sgn(orient2d(*a, *c, *b)) == -s
        assert sgn(orient2d(*c, *b, *a)) == -s


def test_incircle_permutations():
    for args in incircle_families()["unit"][::5] + incircle_families()["translated_1e6"][::5]:
        a, b, c, d = args[0:2], args[2:4], args[4:6], args[6:8]
        s = sgn(incircle(*a, *b, *c, *d))
        assert sgn(incircle(*b, *c, *a, *d)) == s  # cyclic shift of a, b, c
        assert sgn(incircle(*b, *a, *c, *d)) == -s  # swap two of a, b, c
        assert sgn(incircle(*a, *c, *b, *d)) == -s
        assert sgn(incircle(*a, *b, *d, *c)) == -s  # antisymmetric in all four
        assert sgn(incircle(*d, *b, *c, *a)) == -s


def test_dot2d_symmetry():
    for args in dot_families()["thales_unit"][::3] + dot_families()["translated_1e6"][::3]:
        a, b, c = args[0:2], args[2:4], args[4:6]
        assert sgn(dot2d(*a, *b, *c)) == sgn(dot2d(*b, *a, *c))


@pytest.mark.parametrize("k", [-1000, -600, -200, -60, 60, 200, 600, 1000])
def test_power_of_two_scaling_keeps_signs(k):
    """Scaling by 2**k is exact, so signs must not change -- even where the
    filter underflows (k < 0) or overflows (k > 0) and the exact path rescales."""
    s = 2.0**k
    for name, fam, step in (("orient2d", "shewchuk", 11), ("orient2d", "skew", 5),
                            ("incircle", "unit", 9), ("dot2d", "thales_unit", 7)):
        fn, _, ref, _ = PREDICATES[name]
        for args in FAMILIES[name]()[fam][::step]:
            scaled = tuple(v * s for v in args)
            assert sgn(fn(*scaled)) == ref(*args), (name, k, args)


# --------------------------------------------------------------------------
# the filter is what answers easy inputs; the exact path agrees in magnitude
# --------------------------------------------------------------------------


def test_filter_returns_plain_formula_on_easy_inputs():
    rng = np.random.default_rng(2024)
    checked = {name: 0 for name in PREDICATES}
    for _ in range(500):
        args = tuple(float(v) for v in rng.uniform(-1.0, 1.0, 8))
        for name, (fn, exact_fn, _, naive) in PREDICATES.items():
            a = args[:8] if name == "incircle" else args[:6]
            nv = naive(*a)
            if abs(nv) < 1e-6:
                continue
            checked[name] += 1
            assert fn(*a) == nv  # bit-identical: the filter decided
            # the exact path's magnitude approximates the determinant
            assert math.isclose(exact_fn(*a), nv, rel_tol=1e-9)
    assert min(checked.values()) > 400


# --------------------------------------------------------------------------
# random inputs (hypothesis, fixed derandomized profile)
# --------------------------------------------------------------------------

# Nonzero magnitudes stay within 1e-100..1e30 of each other: inside the
# documented dynamic range (2**-450 ~ 3e-136 for incircle, 2**-960 otherwise).
coord = st.one_of(
    st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False).map(
        lambda x: x if abs(x) >= 1e-100 else 0.0
    ),
    st.integers(-3, 3).map(float),  # small integers: exact degeneracies
    st.sampled_from([0.1, 0.2, 0.3, 1e6, 1e6 + 0.5, -1e-6, 1e-30, 1e30]),
)
scale = st.sampled_from([1.0, 1e-30, 1e-6, 1e6, 1e30, 2.0**-500, 2.0**500])


def check(name, args):
    fn, exact_fn, ref, _ = PREDICATES[name]
    e = ref(*args)
    assert sgn(fn(*args)) == e
    assert sgn(exact_fn(*args)) == e


@HYP
@given(st.tuples(*[coord] * 6), scale)
def test_random_orient2d_dot2d(args, s):
    args = tuple(v * s for v in args)
    check("orient2d", args)
    check("dot2d", args)


@HYP
@given(st.tuples(*[coord] * 8), scale)
def test_random_incircle(args, s):
    check("incircle", tuple(v * s for v in args))


@st.composite
def near_collinear(draw):
    """c = a + t (b - a) rounded, then nudged a few ulps: near-degenerate."""
    f = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)
    ax, ay, bx, by = draw(f), draw(f), draw(f), draw(f)
    t = draw(st.floats(-2.0, 3.0))
    off = draw(st.sampled_from([0.0, 1e6, -1e9]))
    cx, cy = ax + t * (bx - ax), ay + t * (by - ay)
    i, j = draw(st.integers(-3, 3)), draw(st.integers(-3, 3))
    cx, cy = ulp_walk(cx + off, i, i)[0], ulp_walk(cy + off, j, j)[0]
    return (ax + off, ay + off, bx + off, by + off, cx, cy)


@HYP
@given(near_collinear())
def test_random_near_collinear(args):
    check("orient2d", args)


@st.composite
def near_cocircular(draw):
    """Four rounded points of one circle, the last nudged a few ulps."""
    ox = draw(st.floats(-1e6, 1e6, allow_nan=False))
    oy = draw(st.floats(-1e6, 1e6, allow_nan=False))
    r = draw(st.floats(1e-3, 1e3))
    th = draw(st.lists(st.floats(0, 2 * math.pi), min_size=4, max_size=4))
    pts = [circle_point(ox, oy, r, t) for t in th]
    i, j = draw(st.integers(-3, 3)), draw(st.integers(-3, 3))
    dx, dy = ulp_walk(pts[3][0], i, i)[0], ulp_walk(pts[3][1], j, j)[0]
    return (*pts[0], *pts[1], *pts[2], dx, dy)


def _in_documented_range(args, ratio):
    """The exactness range stated in the module docstring: every nonzero coordinate
    at least ``ratio`` times the largest magnitude (no underflow)."""
    big = max(abs(a) for a in args)
    return all(a == 0.0 or abs(a) >= ratio * big for a in args)


@HYP
@given(near_cocircular())
def test_random_near_cocircular(args):
    # ulp nudges of a zero coordinate give subnormals far outside the stated range
    assume(_in_documented_range(args, 2.0**-450))
    check("incircle", args)
    # the diametral circle of the first two points, through the third
    check("dot2d", args[:2] + args[4:6] + args[6:8])


# --------------------------------------------------------------------------
# the error-free transformations themselves
# --------------------------------------------------------------------------


@HYP
@given(st.floats(-1e150, 1e150, allow_nan=False), st.floats(-1e150, 1e150, allow_nan=False))
def test_two_sum_two_product_error_free(a, b):
    x, y = xp.two_sum(a, b)
    assert x == a + b and Fraction(x) + Fraction(y) == Fraction(a) + Fraction(b)
    if a == 0.0 or b == 0.0 or abs(a * b) > 1e-200:  # Dekker needs no underflow
        x, y = xp.two_product(a, b)
        assert x == a * b and Fraction(x) + Fraction(y) == Fraction(a) * Fraction(b)


def test_expansion_arithmetic_exact():
    rng = np.random.default_rng(99)
    for _ in range(200):
        n = int(rng.integers(1, 9))
        xs = rng.normal(size=n) * 10.0 ** rng.integers(-20, 20, n)
        ys = rng.normal(size=n) * 10.0 ** rng.integers(-20, 20, n)
        out, tmp, term = np.empty(2 * n), np.empty(2 * n), np.empty(2)
        m = xp.sum_of_products(n, xs, ys, out, tmp, term)
        e = out[:m]
        assert sum(map(Fraction, e)) == sum(Fraction(x) * Fraction(y) for x, y in zip(xs, ys))
        assert all(abs(e[i]) < abs(e[i + 1]) for i in range(m - 1))  # increasing
        b = float(rng.normal() * 1e5)
        h = np.empty(2 * m)
        k = xp.scale_expansion(m, e, b, h)
        assert sum(map(Fraction, h[:k])) == sum(map(Fraction, e)) * Fraction(b)


# --------------------------------------------------------------------------
# calling conventions, compilation options
# --------------------------------------------------------------------------


@numba.njit
def _count_ccw(pts):
    n = 0
    for i in range(pts.shape[0] - 2):
        if orient2d(pts[i, 0], pts[i, 1], pts[i + 1, 0], pts[i + 1, 1], pts[i + 2, 0], pts[i + 2, 1]) > 0:
            n += 1
        if incircle(0.0, 0.0, 1.0, 0.0, 0.0, 1.0, pts[i, 0], pts[i, 1]) > 0:
            n += 1000
        if dot2d(0.0, 0.0, 1.0, 0.0, pts[i, 0], pts[i, 1]) < 0:
            n += 1000000
    return n


def test_callable_from_njit_and_python():
    pts = np.random.default_rng(3).uniform(-1, 1, (200, 2))
    expect = 0
    for i in range(len(pts) - 2):
        expect += exact_orient(*pts[i], *pts[i + 1], *pts[i + 2]) > 0
        expect += 1000 * (exact_incircle(0, 0, 1, 0, 0, 1, *pts[i]) > 0)
        expect += 1000000 * (exact_dot(0, 0, 1, 0, *pts[i]) < 0)
    assert _count_ccw(pts) == expect
    assert orient2d(0, 0, 1, 0, 0, 1) > 0  # Python ints are converted to float64
    assert math.isnan(orient2d(math.nan, 0.0, 1.0, 0.0, 0.0, 1.0))
    assert math.isnan(incircle(math.inf, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0))
    assert math.isnan(dot2d(0.0, 0.0, 1.0, -math.inf, 0.0, 1.0))


def test_compiled_with_cache_and_without_fastmath():
    for mod, name in ((pred, "orient2d"), (pred, "incircle"), (pred, "dot2d"),
                      (korient, "orient2d_exact"), (kinc, "incircle_exact"),
                      (kdot, "dot2d_exact"), (xp, "two_sum"), (xp, "two_product"),
                      (xp, "split"), (xp, "expansion_sum"), (xp, "scale_expansion")):
        disp = getattr(mod, name)
        assert not disp.targetoptions.get("fastmath"), name
        assert isinstance(disp._cache, FunctionCache), name  # numba's disk cache (claimed or not)



def test_no_jit_at_import(tmp_path):
    """Importing the package compiles nothing (an empty numba cache, a fresh process)."""
    code = (
        "import uniform2d, uniform2d._kernel.predicates as p, uniform2d._kernel.insert as k;"
        "print([len(f.signatures) for f in (p.orient2d, p.incircle, p.dot2d, k.run)])"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, check=True, timeout=120)
    assert out.stdout.strip() == "[0, 0, 0, 0]"


def test_the_exact_paths_are_compiled_once_and_called_by_name():
    """A kernel calling a predicate holds a call to its exact path, not a copy
    (``_kernel/external.py``), and gets the exact path's answers all the same."""
    from uniform2d._kernel import external

    cases = [(orient2d, (12.0, 12.0, 24.0, 24.0, 0.5000000000000046, 0.5000000000000053),
              "orient2d_exact", exact_orient),
             (dot2d, (0.1, 0.3, 0.7, 0.9, 0.4, 0.6), "dot2d_exact", exact_dot),
             (incircle, (0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0 + 2.0**-52), "incircle_exact",
              exact_incircle)]
    for pred_, args, exact_name, reference in cases:
        assert np.sign(pred_(*args)) == np.sign(reference(*args))  # a filter failure, decided
        fresh = numba.njit(pred_.py_func)  # not cached: its code can be read
        assert fresh(*args) == pred_(*args)
        (ir,) = fresh.inspect_llvm().values()
        symbol = f"uniform2d_{pred_.py_func.__module__.rsplit('.', 1)[-1]}_{exact_name}"
        assert f"declare double @{symbol}(" in ir
        assert "scaled3" not in ir and "scaled4" not in ir  # no copy of the exact arithmetic
    assert not external._pending  # compiled (or loaded) on first need
