"""uniform2d.bounds: the lower bounds checked against brute force, and attacked by
meshes of every method we have (ours, T+, Gmsh, Triangle, random constrained
Delaunay meshes): no mesh may ever beat a bound."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from uniform2d.testing import polygons
from support.benchmarks import benchmark_polygons
from uniform2d.testing import check_mesh
from uniform2d import Polygon, tplus, uniform_mesh
from uniform2d.errors import InsufficientPointsError
from uniform2d.bounds import (BOUND_SLACK, corner_ratio_floor, euler_ratio_floor,
                              triangle_ratio_floor)
from uniform2d.quality import quality

DEG = math.pi / 180


# -- g: brute force over triangles ----------------------------------------------
def ratio_with_angle(beta, t):
    """Longest / shortest side of the triangle with sides 1 and t (t <= 1) at angle beta."""
    c = np.sqrt(1.0 + t * t - 2.0 * t * np.cos(beta))
    sides = np.stack([np.ones_like(t), t, c])
    return sides.max(axis=0) / sides.min(axis=0)


@pytest.mark.parametrize("deg", [0.5, 5, 20, 30, 35, 36, 37, 45, 55, 59.9, 60, 60.1, 75, 90,
                                 120, 150, 179])
def test_g_is_the_least_ratio_of_a_triangle_with_that_angle(deg):
    """Every triangle with an angle beta is (up to scale) sides 1 >= t at that
    angle: a dense sweep of t finds the minimum, which g matches and never beats."""
    beta = deg * DEG
    t = np.concatenate([np.linspace(1e-4, 1.0, 400_001), np.random.default_rng(0).random(100_000)])
    r = ratio_with_angle(beta, t)
    best = t[np.argmin(r)]  # the minimum is a kink: sweep around it again, finer
    fine = np.clip(np.linspace(best - 1e-5, best + 1e-5, 200_001), 1e-9, 1.0)
    r = np.concatenate([r, ratio_with_angle(beta, fine)])
    g = triangle_ratio_floor(beta)
    assert r.min() >= g * (1 - 1e-12)
    assert r.min() == pytest.approx(g, rel=1e-8)


@settings(max_examples=300, deadline=None)
@given(st.floats(0.01, 179.9), st.floats(0.01, 179.9))
def test_no_triangle_beats_g_at_any_of_its_angles(a, b):
    assume(a + b < 179.99)
    angles = (a, b, 180 - a - b)
    sides = [math.sin(x * DEG) for x in angles]
    ratio = max(sides) / min(sides)
    for x in angles:
        assert ratio >= triangle_ratio_floor(x * DEG) * (1 - 1e-12)


def test_g_falls_to_one_at_60_degrees_and_rises_after():
    b = np.linspace(0.1, 179.9, 3000) * DEG
    g = np.array([triangle_ratio_floor(x) for x in b])
    below = b <= 60 * DEG
    assert (np.diff(g[below]) < 0).all() and (np.diff(g[~below]) > 0).all()
    assert triangle_ratio_floor(60 * DEG) == pytest.approx(1.0, abs=1e-15)
    assert triangle_ratio_floor(90 * DEG) == pytest.approx(math.sqrt(2))
    assert triangle_ratio_floor(20 * DEG) == pytest.approx(2 * math.cos(20 * DEG))  # 20-20-140


# -- the corner floor: brute force over splits of a corner ----------------------
def best_split(alpha, k, rng, samples=20_000):
    """Least max_i g(beta_i) over random splits of alpha into k angles < 180 deg,
    and the equal split."""
    best = max(triangle_ratio_floor(alpha / k), 1.0) if alpha / k < math.pi else math.inf
    w = rng.dirichlet(np.ones(k), size=samples) * alpha
    w = w[(w < math.pi).all(axis=1) & (w > 0).all(axis=1)]
    for split in w:
        worst = max(triangle_ratio_floor(x) for x in split)
        assert worst >= corner_ratio_floor(alpha)[0] * (1 - 1e-12), (alpha, split)
        best = min(best, worst)
    return best


@pytest.mark.parametrize("deg", [20, 45, 59, 75, 90, 100, 135, 150, 170, 200, 225, 270, 300, 330, 350])
def test_corner_floor_equals_the_best_split(deg):
    """No way of splitting the corner among 1..7 triangles beats the floor, and
    the best split found reaches it."""
    alpha = deg * DEG
    rng = np.random.default_rng(deg)
    floor, k = corner_ratio_floor(alpha)
    found = min(best_split(alpha, j, rng, 3000) for j in range(1, 8))
    assert found == pytest.approx(floor, rel=1e-12)  # the equal split into k reaches it
    assert k * math.pi > alpha and floor == pytest.approx(max(1.0, triangle_ratio_floor(alpha / k)))


@pytest.mark.parametrize("deg, want", [
    (90, 1 / (2 * math.sin(22.5 * DEG))),   # two 45-degree triangles
    (270, 1 / (2 * math.sin(27 * DEG))),    # five 54-degree triangles
    (45, 1 / (2 * math.sin(22.5 * DEG))),   # one triangle
    (150, 1 / (2 * math.sin(25 * DEG))),    # three 50-degree ones beat two of 75 (1.218)
    (60, 1.0), (120, 1.0), (180, 1.0), (240, 1.0), (300, 1.0),
])
def test_corner_floor_values(deg, want):
    assert corner_ratio_floor(deg * DEG)[0] == pytest.approx(want, rel=1e-14)


# -- the euler term: counting triangles at vertices ------------------------------
G5, G7 = 2 * math.sin(36 * DEG), 1 / (2 * math.sin(math.pi / 7))


def euler_reference(alphas, h):
    """The least ratio below g(72) that some choice of triangles per corner allows,
    by enumerating every choice: sum k = 3|V| + 6h - 6 below g(360/7), sum k <= it
    from there (degree-7 inner vertices take the rest)."""
    import itertools

    target = 3 * len(alphas) + 6 * h - 6
    best = G5
    choices = [[k for k in range(1, 10) if a < k * math.pi] for a in alphas]
    for ks in itertools.product(*choices):
        worst = max(max(triangle_ratio_floor(a / k) for a, k in zip(alphas, ks)), 1.0)
        if sum(ks) == target:
            best = min(best, worst)
        elif sum(ks) < target:
            best = min(best, max(worst, G7))
    return best


@settings(max_examples=150, deadline=None)
@given(st.lists(st.floats(20.0, 340.0), min_size=3, max_size=4), st.integers(0, 1))
def test_euler_term_equals_enumeration(angles, h):
    alphas = [a * DEG for a in angles]
    assert euler_ratio_floor(alphas, h) == pytest.approx(euler_reference(alphas, h), rel=1e-12)


def test_euler_term_values():
    regular = lambda m: [math.pi * (m - 2) / m] * m  # noqa: E731
    assert euler_ratio_floor(regular(6), 0) == pytest.approx(1.0)   # the lattice fits
    assert euler_ratio_floor(regular(3), 0) == pytest.approx(1.0)
    assert euler_ratio_floor(regular(5), 0) == pytest.approx(G5)    # a corner or a 5-vertex
    assert euler_ratio_floor(regular(8), 0) == pytest.approx(G7)    # two 7-vertices do
    assert euler_ratio_floor(regular(40), 0) == pytest.approx(G5)   # a disc needs 5-vertices
    # A hexagonal hole in a hexagon: 12 corners, 6 of 120 and 6 of 240 degrees, fits.
    assert euler_ratio_floor([120 * DEG] * 6 + [240 * DEG] * 6, 1) == pytest.approx(1.0)


@pytest.mark.parametrize("name", ["square", "star10", "square2holes", "disc40", "pentagon"])
def test_euler_formula_on_real_meshes(name):
    """The identity behind the term: sum over inner vertices of (d - 6) plus sum over
    boundary vertices of (k - 3) is 6h - 6, d and k counting triangles at a vertex."""
    P = POLYGONS[name]
    for n in (30, 200):
        m = uniform_mesh(P, n)
        count = np.bincount(m.triangles.ravel(), minlength=len(m.points))
        e = np.sort(m.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        keys, uses = np.unique(e, axis=0, return_counts=True)
        boundary = np.zeros(len(m.points), bool)
        boundary[keys[uses == 1].ravel()] = True
        total = (count[~boundary] - 6).sum() + (count[boundary] - 3).sum()
        assert total == 6 * P.n_holes - 6


def test_a_disc_like_polygon_has_ratio_at_least_2_sin_36():
    q = quality(*_mesh(POLYGONS["disc40"], 100), POLYGONS["disc40"], d_n=False)
    assert q.edge_ratio_bound.term == "euler"
    assert q.edge_ratio_bound.value == pytest.approx(G5 * (1 - BOUND_SLACK), rel=1e-14)
    assert q.edge_ratio >= q.edge_ratio_bound.value


def _mesh(P, n):
    m = uniform_mesh(P, n)
    return m.points, m.triangles


# -- every corner that is not a multiple of 60 degrees gives a floor above 1 -----
def polygon_with_corner(deg):
    """A simple polygon with a corner of ``deg`` degrees at the origin (0 < deg < 360)."""
    a = deg * DEG
    far = [(2 * math.cos(a / 2), 2 * math.sin(a / 2))]  # on the bisector, inside the wedge
    if deg <= 180:
        return Polygon([(0, 0), (1, 0), (math.cos(a), math.sin(a))])
    return Polygon([(0, 0), (1, 0), *far, (math.cos(a), math.sin(a))])


@settings(max_examples=200, deadline=None)
@given(st.floats(1.0, 359.0))
def test_every_corner_off_a_multiple_of_60_degrees_bounds_the_ratio_above_1(deg):
    assume(abs(deg / 60 - round(deg / 60)) > 1e-6)
    P = polygon_with_corner(deg)
    angles = np.degrees(P.interior_angles())
    assert np.isclose(angles, deg).any()
    q = quality(P.vertices, np.array([[0, 1, 2]]), P, n_steiner=100, d_n=False)
    assert q.edge_ratio_bound.value > 1.0
    assert dict(q.edge_ratio_bound.terms)["corner"] > 1.0


def test_corners_at_multiples_of_60_degrees_give_no_corner_term():
    hexagon = Polygon([(math.cos(a), math.sin(a)) for a in np.arange(6) * math.pi / 3])
    trapezoid = Polygon([(0, 0), (3, 0), (2, math.sqrt(3)), (1, math.sqrt(3))])
    for P in (hexagon, trapezoid, Polygon([(0, 0), (1, 0), (2, 0), (1, math.sqrt(3))])):
        q = quality(P.vertices, np.array([[0, 1, 2]]), P, n_steiner=50, d_n=False)
        assert "corner" not in dict(q.edge_ratio_bound.terms)


def test_holes_and_reflex_corners_count():
    """A square hole has 270-degree corners in the domain: its floor is g(54), and
    Euler's formula counts them too."""
    hole = [(2, 1), (3, 1), (3, 2), (2, 2)]
    P = Polygon([(0, 0), (6, 0), (3, 3 * math.sqrt(3))], [hole])  # outer corners: 60 degrees
    q = quality(P.vertices, np.array([[0, 1, 2]]), P, n_steiner=50, d_n=False)
    want = corner_ratio_floor(270 * DEG)[0] * (1 - BOUND_SLACK)
    assert dict(q.edge_ratio_bound.terms)["corner"] == pytest.approx(want, rel=1e-14)
    terms = dict(q.edge_ratio_bound.terms)
    # Euler: the 60-degree corners take 1 triangle each, the four hole corners 4 or 5,
    # and 3 + sum = 3 * 7 + 6 - 6 = 21 needs two of each: a 67.5-degree one, 1.111.
    assert terms["euler"] == pytest.approx(2 * math.sin(33.75 * DEG) * (1 - BOUND_SLACK), rel=1e-14)
    assert q.edge_ratio_bound.term == "euler"
    framed = Polygon([(0, 0), (6, 0), (6, 6), (0, 6)], [hole])
    q = quality(framed.vertices, np.array([[0, 1, 2]]), framed, n_steiner=50, d_n=False)
    assert q.edge_ratio_bound.term == "corner"  # the outer 90-degree corners: 1.307
    assert dict(q.edge_ratio_bound.terms)["corner"] > terms["corner"]


def test_bounds_are_scale_and_translation_invariant():
    P = polygons.star(np.random.default_rng(5), 9)
    m = uniform_mesh(P, 80)
    ref = quality(m.points, m.triangles, P, d_n=False)
    for s, off in ((1e-6, (0, 0)), (1e6, (0, 0)), (1.0, (1e6, -3e6)), (1e3, (-7e8, 2e8))):
        Q = P.transformed(scale=s, offset=off)
        q = quality(m.points * s + np.asarray(off), m.triangles, Q, d_n=False)
        for name, b in q.bounds.items():
            r = ref.bounds[name]
            assert b.term == r.term, name
            assert b.factor == pytest.approx(r.factor, rel=1e-7), name
            assert b.value <= b.achieved


# -- break it: no mesh of any method beats a bound -------------------------------
def assert_not_beaten(q, what=""):
    for name, b in q.bounds.items():
        assert b.value <= b.achieved, (what, name, b)


def cdt_of_random_points(P, n, rng):
    """A constrained Delaunay triangulation (Triangle, no added points) of V and n
    random points of P, a fifth of them on the boundary; None if Triangle added
    points (it never should with these switches)."""
    triangle = pytest.importorskip("triangle")
    import shapely

    shp = P.to_shapely()
    x0, y0, x1, y1 = shp.bounds
    n_edge = n // 5
    inner = np.zeros((0, 2))
    while len(inner) < n - n_edge:
        cand = rng.uniform((x0, y0), (x1, y1), size=(4 * n + 8, 2))
        inner = np.vstack([inner, cand[shapely.contains_xy(shp, cand[:, 0], cand[:, 1])]])
    inner = inner[: n - n_edge]
    which = rng.integers(0, len(P.edges), n_edge)
    t = np.sort(rng.uniform(0.02, 0.98, n_edge))
    pts = np.vstack([P.vertices, inner])
    segments = []
    for j, (a, b) in enumerate(P.edges):  # each boundary point splits its polygon edge
        ts = t[which == j]
        chain = [a, *range(len(pts), len(pts) + len(ts)), b]
        pts = np.vstack([pts, P.vertices[a] + np.outer(ts, P.vertices[b] - P.vertices[a])])
        segments += list(zip(chain[:-1], chain[1:]))
    data = {"vertices": pts, "segments": np.array(segments, dtype=np.int32)}
    if P.n_holes:
        data["holes"] = np.array([shapely.Polygon(h).point_on_surface().coords[0] for h in P.holes])
    out = triangle.triangulate(data, "p")
    if len(out["vertices"]) != len(pts):
        return None
    return np.asarray(out["vertices"]), np.asarray(out["triangles"], dtype=np.int64)


def sharp_and_reflex_polygons():
    rng = np.random.default_rng(19)
    out = dict(benchmark_polygons())
    out["sliver 12deg"] = Polygon([(0, 0), (1, 0), (math.cos(12 * DEG), math.sin(12 * DEG))])
    out["obtuse 150deg"] = Polygon([(0, 0), (2, 0), (1 + math.cos(30 * DEG), math.sin(30 * DEG)),
                                    (-1, 1)])
    out["disc40"] = Polygon([(math.cos(a), math.sin(a)) for a in np.arange(40) * 2 * math.pi / 40])
    out["pentagon"] = Polygon([(math.cos(a), math.sin(a)) for a in np.arange(5) * 2 * math.pi / 5])
    out["comb"] = Polygon([(0, 0), (4, 0), (4, 1), (3, 1), (3, 0.3), (2.5, 0.3), (2.5, 1),
                           (1, 1), (0.7, 0.4), (0.3, 1), (0, 1)])
    for i in range(3):
        out[f"star {i}"] = polygons.star(rng)
        out[f"holes {i}"] = polygons.with_holes(rng)
        out[f"convex {i}"] = polygons.convex(rng)
    return out


POLYGONS = sharp_and_reflex_polygons()


@pytest.mark.parametrize("name", sorted(POLYGONS))
def test_no_mesh_of_any_method_beats_a_bound(name):
    """Ours (each objective), T+, Gmsh, Triangle and random constrained Delaunay
    meshes with the same vertex count, at two sizes."""
    from uniform2d.peers import base as peers

    P = POLYGONS[name]
    rng = np.random.default_rng(len(name))
    for n in (40, 250):
        meshes, d_n = {}, None
        try:
            meshes["T+"] = tplus(P, n)
            d_n = meshes["T+"].info["d_n"]
        except InsufficientPointsError:  # T+ needs more points on this polygon
            pass
        for obj in ("balanced", "ratio", "max_edge", "max_perimeter"):
            meshes[obj] = uniform_mesh(P, n, objective=obj)
        meshes = {k: (m.points, m.triangles) for k, m in meshes.items()}
        for peer in ("gmsh", "triangle"):
            if peers.available(peer):
                pm = peers.mesh(peer, P, len(P.vertices) + n)
                meshes[peer] = (pm.points, pm.triangles)
        for i in range(3):
            cdt = cdt_of_random_points(P, n, rng)
            if cdt is not None:
                meshes[f"random {i}"] = cdt
        for what, (pts, tri) in meshes.items():
            check_mesh(pts, tri, P, delaunay=False, area_rtol=1e-7)
            m = len(pts) - len(P.vertices)
            assert_not_beaten(quality(pts, tri, P, n_steiner=m, d_n=False), (what, n))
            if m == n and d_n is not None:  # the same n: T+'s d_n is a valid packing distance
                assert_not_beaten(quality(pts, tri, P, n_steiner=m, d_n=d_n), (what, n, "d_n"))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.integers(0, 120), st.sampled_from(sorted(POLYGONS)))
def test_random_constrained_delaunay_meshes_never_beat_a_bound(seed, n, name):
    P = POLYGONS[name]
    cdt = cdt_of_random_points(P, n, np.random.default_rng(seed))
    assume(cdt is not None)
    pts, tri = cdt
    assert_not_beaten(quality(pts, tri, P, d_n=False))
