"""The pruned subsegment evaluation against the old one, bit for bit.

:func:`uniform2d._kernel.segment.eval_segment` no longer values every pair of the
sites near a subsegment against every site (O(sites^3)): it dismisses the pairs'
points by a certified upper bound and values exactly only those that may belong
to the maximum's tied group.  INSERT ranks the result against other candidates
with exact ties, so it must be the very same (value, x, y) bits as the old
evaluation, kept as the slow reference ``tests/reference_envelope.py``.

Each case builds INSERT's triangulation of a polygon with sites
(:func:`uniform2d.triangulation.load`) and evaluates every subsegment candidate
both ways, without a bound and with the bounds the kernel passes (its last
value, or more).  Site sets (hypothesis): uniform random, collinear (on lines
parallel, perpendicular and oblique to the long edge), on the long edge itself,
on a lattice (many equal distances, ties by symmetry), mirror-symmetric, and
behind constrained edges (interior segments, a zigzag outline, holes) that
block visibility, a dome whose lowest vertices hide behind long edges; with and
without a size field, and far from the origin.  Then the benchmark's shapes
(``benchmarks/bench_insert_edges.py``) at 120 vertices in the states INSERT
passes through, and the pieces of the new evaluation: the envelope of lines
and the tied group's floor.
"""

from __future__ import annotations

import struct

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from reference_envelope import reference_eval_segment, subsegment_edges

import uniform2d
from uniform2d import Polygon
from uniform2d._kernel.rank import tied_above
from uniform2d._kernel.envelope import _group_floor, _lower_envelope
from uniform2d._kernel.segment import eval_segment
from uniform2d.errors import InvalidPolygonError, InvalidSitesError
from uniform2d.sizefield import SizeField
from uniform2d.triangulation import load

W = 8.0  # the long edge (0, 0) -> (W, 0)
H = 3.0


def _bits(t) -> tuple:
    return tuple(struct.pack("<d", float(v)) for v in t)


def _check_all(polygon: Polygon, sites, size=None) -> int:
    """Every subsegment of the loaded triangulation, new vs reference; returns how
    many were compared."""
    try:
        loaded = load(polygon, None if sites is None or len(sites) == 0 else np.asarray(sites), size=size)
    except InvalidSitesError:
        assume(False)
    m = loaded.m
    xtol = 1e-9 * max(W, H) / loaded.scale
    hs = subsegment_edges(m)
    for h in hs:
        new = eval_segment(m, h, xtol, np.inf)
        old = reference_eval_segment(m, h, xtol, np.inf)
        assert _bits(new) == _bits(old), f"h={h}: new {new} != old {old}"
        for bound in (old[0], old[0] * (1 + 1e-9), old[0] * 1.7):
            new = eval_segment(m, h, xtol, bound)
            old = reference_eval_segment(m, h, xtol, bound)
            assert _bits(new) == _bits(old), f"h={h} bound={bound}: new {new} != old {old}"
    return len(hs)


def _box(segments=(), holes=()) -> Polygon:
    return Polygon([(0.0, 0.0), (W, 0.0), (W, H), (0.0, H)], holes=holes, segments=segments)


def _inside(pts, margin=1e-3):
    pts = np.asarray(pts, dtype=np.float64).reshape(-1, 2)
    keep = (pts[:, 0] > margin) & (pts[:, 0] < W - margin) & (pts[:, 1] > margin) & (pts[:, 1] < H - margin)
    pts = pts[keep]
    return np.unique(pts, axis=0) if len(pts) else pts


coord = st.floats(0.0, 1.0, allow_nan=False, allow_infinity=False)
pts = st.lists(st.tuples(coord, coord), min_size=1, max_size=45)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pts, st.floats(0.05, 1.0))
def test_random_sites(p, ymax):
    """Sites scattered above the long edge, inside its diametral disk or not."""
    s = np.array(p) * [W, H * ymax]
    _check_all(_box(), _inside(s))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(2, 40), st.floats(0.02, 2.9), st.floats(-1.0, 1.0), st.sampled_from(["par", "perp", "obl"]),
       st.floats(0.5, 7.5))
def test_collinear_sites(k, y0, slope, kind, x0):
    """Sites on one line: parallel to the edge (equal distances to it), perpendicular
    to it (pairs with den == 0 or nearly), or oblique."""
    t = np.linspace(0.0, 1.0, k)
    if kind == "par":
        s = np.c_[0.1 + 7.8 * t, np.full(k, y0)]
    elif kind == "perp":
        s = np.c_[np.full(k, x0), 0.02 + 2.9 * t]
    else:
        s = np.c_[x0 + (t - 0.5) * 4.0, y0 + slope * (t - 0.5) * 4.0]
    _check_all(_box(), _inside(s))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.floats(0.05, 7.95), min_size=1, max_size=8, unique=True), pts)
def test_sites_on_the_edge(on, p):
    """Sites on the long edge split it into subsegments (on its line), with sites above."""
    s = np.r_[np.c_[np.array(on), np.zeros(len(on))], _inside(np.array(p) * [W, H * 0.6])]
    _check_all(_box(), s)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(2, 8), st.integers(1, 5), st.floats(0.1, 1.0), st.booleans())
def test_lattice_and_symmetric_sites(nx, ny, step, jitter):
    """A lattice centred over the edge: mirror-symmetric, many equal distances and
    tied maxima (the tie rule decides)."""
    xs = W / 2 + (np.arange(nx) - (nx - 1) / 2) * step
    ys = 0.25 + np.arange(ny) * step * 0.5
    s = np.array([(x, y) for x in xs for y in ys])
    if jitter:
        s = s + np.where(np.arange(len(s))[:, None] % 3 == 0, 1e-12, 0.0)
    _check_all(_box(), _inside(s))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.floats(0.3, 7.7), st.floats(0.1, 1.2), st.floats(-1.5, 1.5), st.floats(0.2, 1.5)),
                min_size=1, max_size=4), pts)
def test_blocking_segments(segs, p):
    """Interior segments above the edge hide sites behind them from parts of it."""
    segments = []
    for x, y, dx, dy in segs:
        a = (x, y)
        b = (min(max(x + dx, 0.1), W - 0.1), min(y + dy, H - 0.1))
        if np.hypot(b[0] - a[0], b[1] - a[1]) > 0.05:
            segments.append([a, b])
    assume(segments)
    try:
        poly = _box(segments=segments)
    except InvalidPolygonError:
        assume(False)
    s = _inside(np.array(p) * [W, H * 0.7], margin=0.02)
    # keep the sites off the segments
    keep = np.ones(len(s), bool)
    for a, b in segments:
        a, b = np.array(a), np.array(b)
        d = b - a
        t = np.clip(((s - a) @ d) / (d @ d), 0.0, 1.0)
        keep &= np.hypot(*(a + t[:, None] * d - s).T) > 1e-3
    _check_all(poly, s[keep])


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(6, 60), st.floats(0.5, 2.5), st.floats(0.05, 0.4), st.integers(0, 2**31 - 1), pts)
def test_zigzag_outline(k, depth, rel, seed, p):
    """A coastline above a straight cut (the benchmark's shape, small): its notches
    are hidden from parts of the cut by the outline's own edges."""
    rng = np.random.default_rng(seed)
    amp = rel * depth
    x = np.linspace(W, 0.0, k)
    y = depth + amp * (-1.0) ** np.arange(k) + rng.uniform(-0.05, 0.05, k)
    poly = Polygon([(0.0, 0.0), (W, 0.0)] + list(zip(x, y)))
    s = np.array(p) * [W, depth - amp - 0.06]
    s = s[(s[:, 0] > 1e-3) & (s[:, 0] < W - 1e-3) & (s[:, 1] > 1e-3)]
    _check_all(poly, np.unique(s, axis=0) if len(s) else None)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(5, 60), st.floats(0.005, 0.2), st.floats(0.3, 0.95), pts)
def test_dome_outline(k, gap, r, p):
    """A dome of k vertices over the cut, its ends joined to the box's top corners
    by long edges: the dome's lowest vertices hide behind those edges from the
    box's sides (their nearest sites along a side are not the visible ones)."""
    th = np.linspace(np.pi * (1 - gap), np.pi * gap, k)[::-1]
    cx, rad = W / 2, r * W / 2
    dome = [(cx + rad * np.cos(t), 0.3 + rad * np.sin(t) * (H - 0.4) / rad) for t in th]
    poly = Polygon([(0.0, 0.0), (W, 0.0), (W, H + 0.5)] + dome + [(0.0, H + 0.5)])
    s = np.array(p) * [W, 0.25] + [0.0, 0.02]
    s = s[(s[:, 0] > 1e-3) & (s[:, 0] < W - 1e-3)]
    _check_all(poly, np.unique(s, axis=0) if len(s) else None)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pts, st.integers(2, 7), st.integers(2, 5), st.integers(0, 2**31 - 1))
def test_with_size_field(p, nx, ny, seed):
    """A size field (a random grid, coarse or fine, some of it beyond the box):
    values are distance / h at the point, and the sorting search bounds h below
    by the grid near the edge."""
    rng = np.random.default_rng(seed)
    gx = np.sort(rng.uniform(-1.0, W + 1.0, nx))
    gy = np.sort(rng.uniform(-1.0, H + 1.0, ny))
    assume(np.all(np.diff(gx) > 1e-3) and np.all(np.diff(gy) > 1e-3))
    field = SizeField(gx, gy, rng.uniform(0.2, 3.0, (ny, nx)))
    _check_all(_box(), _inside(np.array(p) * [W, H * 0.8]), size=field)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pts, st.sampled_from([1e3, 1e6, 3e7]))
def test_far_from_origin(p, far):
    """Far from the origin the kernel's distances carry the rounding grain (wg > 0),
    which widens the ties and the pruning level."""
    box = np.array([(0.0, 0.0), (W, 0.0), (W, H), (0.0, H)]) + far
    s = _inside(np.array(p) * [W, H * 0.8]) + far
    _check_all(Polygon(box), s)


@pytest.mark.parametrize("n", [60, 200])
@pytest.mark.parametrize("holes", [False, True])
def test_after_insert(n, holes):
    """The states INSERT itself reaches: all of its points loaded as sites."""
    hole = [[(3.0, 0.8), (5.0, 0.8), (4.0, 1.6)]] if holes else []
    poly = _box(segments=[[(1.0, 0.5), (2.5, 1.5)]], holes=hole)
    r = uniform2d.insert(poly, n)
    assert _check_all(poly, r.points) > 0


def _coastline(k):
    """bench_insert_edges.py's coastline above a straight cut 360 long, k vertices."""
    rng = np.random.default_rng(35)
    x = np.linspace(360.0, 0.0, k)
    u = np.linspace(0.0, 1.0, k)
    y = 80.0 - 30.0 * np.sin(np.pi * u) + 6.0 * (-1.0) ** np.arange(k) + rng.uniform(-2.0, 2.0, k)
    return Polygon([(0.0, 0.0), (360.0, 0.0)] + list(zip(x, y)))


def _dome(k):
    """bench_insert_edges.py's dome over the cut, its lowest vertices hidden from
    the sides by long edges."""
    th = np.linspace(np.pi * 0.02, np.pi * 0.98, k)
    arc = [(180.0 + 150.0 * np.cos(t), 20.0 + 150.0 * np.sin(t)) for t in th]
    return Polygon([(0.0, 0.0), (360.0, 0.0), (360.0, 200.0)] + arc + [(0.0, 200.0)])


@pytest.mark.parametrize("shape", [_coastline, _dome], ids=["coastline", "dome"])
@pytest.mark.parametrize("sized", [False, True], ids=["plain", "sized"])
def test_long_edge_states(shape, sized):
    """The benchmark's shapes (120 vertices facing the cut) in the states INSERT
    passes through (1 to 128 points), with and without a size field: hundreds of
    sites near the cut, most of them hidden or far from the maximum."""
    p = shape(120)
    size = None
    if sized:
        size = SizeField(np.array([0.0, 360.0]), np.array([0.0, 200.0]), np.array([[20.0, 35.0], [35.0, 15.0]]))
    for n in (1, 8, 128):
        r = uniform2d.insert(p, n, size=size)
        loaded = load(p, r.points, size=size)
        m = loaded.m
        xtol = 1e-9 * 360.0 / loaded.scale
        for h in subsegment_edges(m):
            old = reference_eval_segment(m, h, xtol, np.inf)
            assert _bits(eval_segment(m, h, xtol, np.inf)) == _bits(old), (n, h)
            assert _bits(eval_segment(m, h, xtol, old[0])) == _bits(reference_eval_segment(m, h, xtol, old[0]))


def test_group_floor():
    """The tied group of the maximum: values from the largest down while each is
    tied with the one above it (a chain), nothing below a gap."""
    v = np.array([1.0, 1.0 - 5e-10, 1.0 - 9e-10, 0.5, 1.0 - 1.4e-9])
    lo = _group_floor(v, len(v), 0.0)
    assert lo == 1.0 - 1.4e-9  # the chain reaches past one tie width of the maximum
    assert _group_floor(np.array([2.0, 1.0]), 2, 0.0) == 2.0
    assert tied_above(lo, 0.0) > 0.5


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(-2.0, 2.0), st.floats(0.0, 3.0)), min_size=1, max_size=30))
def test_lower_envelope(lines):
    """The envelope's pieces cover [0, 1] in order and name the lowest line there
    (up to rounding at the cuts)."""
    c = np.array([a for a, _ in lines])
    t = np.array([b for _, b in lines])
    sites, cuts = _lower_envelope(c, t)
    assert len(sites) == len(cuts) + 1
    assert np.all(np.diff(cuts) >= 0) and (len(cuts) == 0 or (cuts[0] >= 0 and cuts[-1] <= 1))
    bounds = np.r_[0.0, cuts, 1.0]
    for k, i in enumerate(sites):
        if bounds[k + 1] - bounds[k] < 1e-6:
            continue
        s = 0.5 * (bounds[k] + bounds[k + 1])
        vals = c - 2 * s * t
        assert vals[i] <= vals.min() + 1e-9 * (1 + np.abs(c).max() + np.abs(t).max())
