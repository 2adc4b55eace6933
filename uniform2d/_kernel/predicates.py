"""Robust geometric predicates: exact signs of orient2d, incircle and dot2d.

One predicate a module -- :mod:`.orient`, :mod:`.incircle`, :mod:`.dot` -- on
the exact arithmetic of :mod:`.expansion`; this module states their common
contract once and is where the rest of the kernel imports them from.

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
derived in :mod:`.dot`).  That fast path is allocation-free.  Otherwise it falls back
to exact expansion arithmetic (Dekker's ``two_product`` with the 2**27 + 1
split, ``two_sum``, Shewchuk's ``fast_expansion_sum_zeroelim`` and
``scale_expansion_zeroelim``), which decides the sign from the most
significant component.  The exact path first checks whether the coordinate
differences are exact (their ``two_sum`` tails vanish -- the usual case for
nearby points); if so it evaluates the filter's own formula exactly on them
(no allocation for orient2d/dot2d), otherwise it expands the determinant in
the coordinates themselves.  No staged adaptive middle path, except that
incircle on exact differences first keeps the plain floating-point value when
no operation rounded (few-bit cocircular points, as in the lattice-like meshes
of symmetric domains); otherwise the exact path costs tens of nanoseconds
(orient2d, dot2d with exact differences) to a few microseconds (incircle,
general case).

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

Never compile these modules with ``fastmath``: the error-free transformations
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

from .dot import DOTERRBOUNDA, dot2d
from .expansion import EPSILON, FILTER_FLOOR
from .incircle import ICCERRBOUNDA, incircle
from .orient import CCWERRBOUNDA, orient2d

__all__ = [
    "orient2d",
    "incircle",
    "dot2d",
    "EPSILON",
    "FILTER_FLOOR",
    "CCWERRBOUNDA",
    "ICCERRBOUNDA",
    "DOTERRBOUNDA",
]
