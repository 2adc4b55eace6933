"""Tests of the brute-force reference of Algorithm INSERT (tests/reference_insert.py).

The reference is what the fast kernel is judged by, so it is checked here on its
own, without the kernel: against hand computations (unit square, 4x1 rectangle,
L-shape, a square with a boundary site), its two independent candidate
enumerations against each other (the paper's literal Voronoi Step 3 versus brute-
force triples and pairs), its pruning against no pruning, its visibility test
against shapely's, the tie rule on synthetic candidates, and at every step
against a dense sampling of the polygon (tests/support/dense_check.py).
"""

import math

import numpy as np
import pytest

from uniform2d.testing import polygons
from support.benchmarks import benchmark_polygons
from support.dense_check import _Vis, check_sequence, dense_samples, max_visible_distance
from support.reference_insert import PolygonGeometry, reference_insert, tie_break
from uniform2d import Polygon

BENCH = benchmark_polygons()
SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
RECT4 = Polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
METHODS = ["voronoi", "general"]


def _size(p: Polygon) -> float:
    x0, y0, x1, y1 = p.bounds
    return max(x1 - x0, y1 - y0)


def _assert_run(res, points, weights, on_boundary, atol=1e-12):
    n = len(points)
    np.testing.assert_allclose(res.points[:n], points, rtol=0, atol=atol)
    np.testing.assert_allclose(res.weights[:n], weights, rtol=1e-12, atol=0)
    assert res.on_boundary[:n].tolist() == list(on_boundary)


def _same_run(a, b, size, tol=1e-12):
    np.testing.assert_allclose(a.points, b.points, rtol=0, atol=tol * size)
    np.testing.assert_allclose(a.weights, b.weights, rtol=tol, atol=0)
    assert a.on_boundary.tolist() == b.on_boundary.tolist()


# -- hand computations -----------------------------------------------------------------
@pytest.mark.parametrize("method", METHODS)
def test_square_first_point_is_centre(method):
    pts, w, onb = reference_insert(SQUARE, 1, method=method)
    assert pts.tolist() == [[0.5, 0.5]]
    assert w[0] == pytest.approx(math.sqrt(2) / 2, rel=1e-15)
    assert not onb[0]


@pytest.mark.parametrize("method", METHODS)
def test_square_hand_sequence_and_ties(method):
    # Step 2: the four edge midpoints tie at 1/2; the tie rule takes the smallest x,
    # (0, .5); then among (.5, 0) and (.5, 1) (equal x) the smallest y; then (1, .5).
    # Steps 6-8: the four cell centres tie at sqrt(2)/4: (.25, .25), (.25, .75), (.75, .25).
    r = reference_insert(SQUARE, 8, method=method)
    s = math.sqrt(2)
    _assert_run(
        r,
        [[0.5, 0.5], [0, 0.5], [0.5, 0], [0.5, 1], [1, 0.5], [0.25, 0.25], [0.25, 0.75], [0.75, 0.25]],
        [s / 2, 0.5, 0.5, 0.5, 0.5, s / 4, s / 4, s / 4],
        [False, True, True, True, True, False, False, False],
    )
    assert r.n_tied[1:5] == [4, 3, 2, 1]
    assert r.n_tied[5:8] == [4, 3, 2]


@pytest.mark.parametrize("method", METHODS)
def test_rect4x1_hand_sequence(method):
    # 1: centre (2, .5), w = sqrt(4.25).
    # 2: six-way tie at 17/16: Voronoi vertices (15/16, .5), (49/16, .5) (circumcentres
    #    of two corners and the centre) and boundary points (17/16, 0), (17/16, 1),
    #    (47/16, 0), (47/16, 1) (bisector of a corner and the centre on the long
    #    edges).  Smallest x wins: (15/16, .5).
    # 3: remaining tie (49/16, .5), (47/16, 0), (47/16, 1): smallest x, then y: (47/16, 0).
    # 4: on y = 1, equidistant from (47/16, 0) and (2, .5): x = 2.86875.
    r = reference_insert(RECT4, 4, method=method)
    _assert_run(
        r,
        [[2, 0.5], [15 / 16, 0.5], [47 / 16, 0], [2.86875, 1]],
        [math.sqrt(4.25), 17 / 16, 17 / 16, math.sqrt(0.06875**2 + 1)],
        [False, False, True, True],
    )
    assert r.n_tied[:4] == [1, 6, 3, 1]


def test_lshape_hand_sequence():
    # L-shape of arm width a = 1/sqrt(3): the reflex corner (a, a) is a site.
    # 1-2: (0, a) and (a, 0) tie at a (circumcentres of a right triangle with its
    #      hypotenuse on the boundary); smallest x first.
    # 3-5: the three a x a cells' centres at a / sqrt(2); order by x then y.
    # 6:   the subsegment (0,0)-(0,a) midpoint, w = a / 2.
    P = BENCH["lshape"]
    a = 1 / math.sqrt(3)
    r = reference_insert(P, 6)
    _assert_run(
        r,
        [[0, a], [a, 0], [a / 2, a / 2], [a / 2, 3 * a / 2], [3 * a / 2, a / 2], [0, a / 2]],
        [a, a, a / math.sqrt(2), a / math.sqrt(2), a / math.sqrt(2), a / 2],
        [True, True, False, False, False, True],
        atol=1e-15,
    )


@pytest.mark.parametrize("method", METHODS)
def test_extra_sites_hand_sequence(method):
    # Square with an extra boundary site (.5, 0).
    # 1: (.5, 5/8), circumcentre of the top corners and (.5, 0), w = 5/8 (the centre
    #    is now only 1/2 from a site; the left/right edge midpoints have w = 1/2).
    # 2: (1/64, 1/2), circumcentre of (0,0), (0,1) and p1 -- slightly inside the
    #    square, so it beats the left edge midpoint; ties with (63/64, 1/2).
    r = reference_insert(SQUARE, 2, sites=[(0.5, 0.0)], method=method)
    _assert_run(
        r, [[0.5, 0.625], [1 / 64, 0.5]], [0.625, math.sqrt(0.25 + 1 / 64**2)], [False, False]
    )
    # Thin rectangle 1 x 0.2 with a site at the top edge's midpoint: the centre drops
    # to w = 0.1 and the best points are on the bottom edge, equidistant from a bottom
    # corner and the new site: x = 0.29 (then 0.71), w = 0.29.
    thin = Polygon([(0, 0), (1, 0), (1, 0.2), (0, 0.2)])
    r = reference_insert(thin, 2, sites=[(0.5, 0.2)], method=method)
    _assert_run(r, [[0.29, 0], [0.71, 0]], [0.29, 0.29], [True, True], atol=1e-15)


# -- tie rule ----------------------------------------------------------------------------
@pytest.mark.parametrize("scale", [1.0, 1e3, 1e-4])
def test_tie_rule_on_synthetic_candidates(scale):
    g = PolygonGeometry(Polygon(np.array([(0, 0), (1, 0), (1, 1), (0, 1)]) * scale))
    # centre of the bbox is (.5,.5)*scale and its size is `scale`; tolerances are in
    # those normalised units.
    pts = np.array(
        [
            [0.5, 0.5],  # A: the largest weight
            [0.2, 0.8],  # B: in C, smallest x
            [0.2 + 5e-10, 0.3],  # C: in C, within 1e-9 of x_min, smaller y -> chosen
            [0.1, 0.0],  # D: smaller x but weight below W (1 - 1e-9)
            [0.2 + 2e-9, 0.1],  # E: in C, smallest y, but x > x_min + 1e-9
        ]
    ) * scale
    w = np.array([1.0, 1 - 5e-10, 1 - 2e-10, 1 - 2e-9, 1.0]) * scale
    assert tie_break(g, pts, w) == 2
    # equal x: smallest y wins; y within 1e-9 too: smallest x
    pts2 = np.array([[0.3 + 1e-10, 0.7], [0.3 + 1e-10, 0.2], [0.3, 0.2 + 5e-10]]) * scale
    assert tie_break(g, pts2, np.ones(3) * scale) == 2
    pts3 = np.array([[0.3 + 1e-10, 0.7], [0.3 + 1e-10, 0.2], [0.3, 0.2 + 2e-9]]) * scale
    assert tie_break(g, pts3, np.ones(3) * scale) == 1


# -- the two candidate enumerations agree ----------------------------------------------
CONVEX_CASES = [pytest.param(polygons.convex(s), id=f"convex-s{s}") for s in range(6)] + [
    pytest.param(BENCH[k], id=k) for k in ("square", "hexagon", "heptagon_short", "rect4x1")
]


@pytest.mark.parametrize("polygon", CONVEX_CASES)
def test_voronoi_and_general_methods_agree(polygon):
    a = reference_insert(polygon, 60, method="voronoi")
    b = reference_insert(polygon, 60, method="general")
    _same_run(a, b, _size(polygon))


@pytest.mark.parametrize(
    "polygon",
    [
        pytest.param(polygons.star(4), id="star-s4"),
        pytest.param(polygons.with_holes(7), id="holes-s7"),
        pytest.param(BENCH["lshape"], id="lshape"),
        pytest.param(BENCH["square2holes"], id="square2holes"),
    ],
)
def test_pruning_is_exact(polygon):
    a = reference_insert(polygon, 25)
    b = reference_insert(polygon, 25, prune=False)
    _same_run(a, b, _size(polygon), tol=0)


# -- dense check and monotone weights at every step --------------------------------------
DENSE_CASES = (
    [pytest.param(p, 100, id=f"{k}-n100") for k, p in BENCH.items()]
    + [pytest.param(polygons.convex(s), 60, id=f"convex-s{s}-n60") for s in (10, 11)]
    + [pytest.param(polygons.star(s), 60, id=f"star-s{s}-n60") for s in (10, 11, 12)]
    + [pytest.param(polygons.with_holes(s), 60, id=f"holes-s{s}-n60") for s in (10, 11, 12)]
)


@pytest.mark.parametrize("polygon, n", DENSE_CASES)
def test_reference_dense_check_and_monotone(polygon, n):
    r = reference_insert(polygon, n)
    problems = check_sequence(polygon, r.points, r.weights, m=2500)
    assert not problems, "\n".join(problems[:5])
    inc = np.flatnonzero(r.weights[1:] > r.weights[:-1] * (1 + 1e-12))
    assert inc.size == 0, f"weights increase at steps {inc + 1}"


def test_reference_with_sites_dense_and_methods():
    sites = np.array([(0.5, 0.0), (0.3, 0.6), (1.0, 0.25), (0.8, 0.8)])
    a = reference_insert(SQUARE, 40, sites, method="voronoi")
    b = reference_insert(SQUARE, 40, sites, method="general")
    _same_run(a, b, 1.0)
    assert not check_sequence(SQUARE, a.points, a.weights, sites)
    P = polygons.with_holes(3)
    h = P.holes[0]
    sites = np.array(
        [0.5 * (h[0] + h[1]), 0.5 * (P.outer[0] + P.outer[1]), 0.9 * P.outer.mean(0) + 0.1 * P.outer[2]]
    )
    r = reference_insert(P, 40, sites)
    problems = check_sequence(P, r.points, r.weights, sites)
    assert not problems, "\n".join(problems[:5])


# -- the dense check itself ----------------------------------------------------------------
def test_dense_check_catches_wrong_runs():
    P = polygons.star(10)
    r = reference_insert(P, 30)
    assert not check_sequence(P, r.points, r.weights)
    w = r.weights.copy()
    w[12] *= 0.999  # a weight below the true maximum
    assert any(s.startswith("step 12:") for s in check_sequence(P, r.points, w))
    pts = r.points.copy()
    pts[7] += 1e-3 * _size(P) * np.array([0.6, 0.8])  # a point that is not the argmax
    assert any(s.startswith("step 7:") for s in check_sequence(P, pts, r.weights))


def test_dense_samples_cover_polygon():
    P = BENCH["square2holes"]
    X = dense_samples(P, 2000)
    assert 1800 < len(X) < 4000
    g = PolygonGeometry(P)
    assert g.inside_closed(X).all()
    # the maximum over the samples is close to the true maximum
    r = reference_insert(P, 1)
    m = max_visible_distance(P, P.vertices, X)
    assert r.weights[0] * 0.95 < m <= r.weights[0]  # grid spacing ~0.022


# -- visibility ------------------------------------------------------------------------------
def test_visibility_lshape_hand():
    P = BENCH["lshape"]
    a = 1 / math.sqrt(3)
    g = PolygonGeometry(P)
    seg = np.array(
        [
            [(0.5 * a, 1.9 * a), (1.9 * a, 0.5 * a)],  # crosses the notch: hidden
            [(0.5 * a, 1.9 * a), (0.5 * a, 0.1 * a)],  # inside the vertical arm
            [(0, 2 * a), (2 * a, 0)],  # passes exactly through the reflex corner
            [(0, 0), (0, 2 * a)],  # along a boundary edge
            [(0.5 * a, 1.5 * a), (a, a)],  # ends at the reflex corner
            [(0.2 * a, 2 * a), (2 * a, 0.2 * a)],  # clips the notch near the corner
        ]
    )
    vis = g.visible(seg[:, 0], seg[:, 1])
    assert vis.tolist() == [False, True, True, True, True, False]
    assert _Vis(P)(seg[:, 0], seg[:, 1]).tolist() == vis.tolist()


@pytest.mark.parametrize(
    "polygon",
    [pytest.param(polygons.star(s), id=f"star-s{s}") for s in (20, 21)]
    + [pytest.param(polygons.with_holes(s), id=f"holes-s{s}") for s in (20, 21)]
    + [pytest.param(BENCH["square2holes"], id="square2holes")],
)
def test_visibility_agrees_with_shapely(polygon):
    """The reference's segment-splitting visibility test versus shapely ``covers``,
    on random pairs of points, polygon vertices included."""
    rng = np.random.default_rng(0)
    g = PolygonGeometry(polygon)
    X = dense_samples(polygon, 400)
    X = np.concatenate([X[rng.permutation(len(X))[:300]], polygon.vertices])
    i = rng.integers(0, len(X), 4000)
    j = rng.integers(0, len(X), 4000)
    keep = i != j
    a, b = g.visible(X[i[keep]], X[j[keep]]), _Vis(polygon)(X[i[keep]], X[j[keep]])
    assert 0.05 < a.mean() < 0.98  # the test means something
    assert (a == b).all(), f"{(a != b).sum()} disagreements"


# -- invariance ---------------------------------------------------------------------------------
def _snap(p: Polygon, bits: int = 20) -> Polygon:
    f = lambda r: np.round(np.asarray(r) * 2.0**bits) / 2.0**bits  # noqa: E731
    return Polygon(f(p.outer), [f(h) for h in p.holes])


@pytest.mark.parametrize("name", ["hexagon", "star10", "square2holes"])
def test_reference_scale_and_offset_invariant(name):
    P = _snap(BENCH[name])
    r = reference_insert(P, 80)
    for scale, off in ((1e-6, (0, 0)), (1e6, (0, 0)), (1.0, (1e6, -1e6))):
        q = reference_insert(P.transformed(scale, off), 80)
        np.testing.assert_allclose(q.points, r.points * scale + off, rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(q.weights, r.weights * scale, rtol=1e-9)
        assert q.on_boundary.tolist() == r.on_boundary.tolist()


# -- generators ------------------------------------------------------------------------------------
def test_generators_are_deterministic_and_well_formed():
    for s in range(8):
        assert polygons.convex(s, 7) == polygons.convex(np.random.default_rng(s), 7)
        assert polygons.star(s) == polygons.star(s)
        assert polygons.with_holes(s, 2) == polygons.with_holes(s, 2)
        c = polygons.convex(s, 7)
        assert len(c.vertices) == 7 and (c.interior_angles() < np.pi).all()
        st = polygons.star(s)
        assert st.n_holes == 0 and (st.interior_angles() > np.pi).any()
        for k in (1, 2, 3):
            h = polygons.with_holes(s, k)
            assert h.n_holes == k
            shp = h.to_shapely()
            size = _size(h)
            holes = [Polygon(x).to_shapely() for x in h.holes]
            outer = Polygon(h.outer).to_shapely()
            for i, hp in enumerate(holes):
                assert outer.exterior.distance(hp) > 0.02 * size
                for hq in holes[i + 1 :]:
                    assert hp.distance(hq) > 0.02 * size
            assert shp.is_valid
    assert set(BENCH) >= {
        "heptagon_short", "hexagon", "lshape", "rect4x1", "square", "square2holes", "star10",
    }  # fmt: skip
