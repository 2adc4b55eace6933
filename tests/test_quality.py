"""uniform2d.quality: every measure against a direct computation, and the lower
bounds against triangulations whose optimum is known or bounded."""

import json
import logging
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.spatial import Delaunay

from uniform2d import Polygon
from uniform2d.measures import edge_lengths
from uniform2d.quality import BOUND_SLACK, Bound, Quality, quality

SQRT3 = math.sqrt(3.0)


# -- an independent reference --------------------------------------------------
def reference(points, triangles):
    """Every measure by plain loops over the triangles."""
    points = [tuple(map(float, p)) for p in np.asarray(points)]
    use = {}
    angles, perimeters, area = [], [], 0.0
    for t in np.asarray(triangles).tolist():
        for i, j in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            key = (min(i, j), max(i, j))
            use[key] = use.get(key, 0) + 1
        p = [np.array(points[k]) for k in t]
        perimeters.append(sum(math.dist(p[k], p[(k + 1) % 3]) for k in range(3)))
        for k in range(3):
            u, v = p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]
            cos = np.dot(u, v) / (np.linalg.norm(u) * np.linalg.norm(v))
            angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
        (x0, y0), (x1, y1), (x2, y2) = p
        area += abs((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)) / 2
    keys = sorted(use)
    lengths = np.array([math.dist(points[i], points[j]) for i, j in keys])
    return dict(
        edges=np.array(keys),
        lengths=lengths,
        n_boundary_edges=sum(1 for k in keys if use[k] == 1),
        angles=np.array(angles),
        max_perimeter=max(perimeters),
        area=area,
    )


# -- meshes ----------------------------------------------------------------------
def lattice_square(k):
    """Unit square cut into a k x k grid, each cell split by a diagonal."""
    g = np.linspace(0.0, 1.0, k + 1)
    pts = np.array([(x, y) for y in g for x in g])
    idx = lambda i, j: j * (k + 1) + i  # noqa: E731
    tri = []
    for j in range(k):
        for i in range(k):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            tri += [(a, b, c), (a, c, d)]
    return pts, np.array(tri)


def with_polygon_first(polygon, points, triangles):
    """Reorder points so that the polygon vertices come first (as meshes do)."""
    points = np.asarray(points, dtype=float)
    order = []
    for v in polygon.vertices:
        order.append(int(np.flatnonzero((points == v).all(axis=1))[0]))
    rest = [i for i in range(len(points)) if i not in set(order)]
    perm = np.array(order + rest)
    inv = np.empty_like(perm)
    inv[perm] = np.arange(len(perm))
    return points[perm], inv[np.asarray(triangles)]


SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


def triangle_polygon(angle_a, angle_b, base=1.0):
    """Triangle with angles angle_a at (0, 0), angle_b at (base, 0) (degrees)."""
    a, b = math.radians(angle_a), math.radians(angle_b)
    c = math.pi - a - b
    side = base * math.sin(b) / math.sin(c)  # side from (0,0) to the apex
    return Polygon([(0, 0), (base, 0), (side * math.cos(a), side * math.sin(a))])


def corner_ratio(theta):
    return min(2 * math.cos(theta), 1 / (2 * math.sin(theta / 2)))


def random_delaunay(seed, n):
    rng = np.random.default_rng(seed)
    pts = np.vstack([SQUARE.vertices, rng.random((n, 2))])
    return pts, Delaunay(pts).simplices


MESHES = {
    "one-diagonal square": (SQUARE.vertices, np.array([(0, 1, 2), (0, 2, 3)])),
    "lattice 5x5": lattice_square(5),
    "random 60": random_delaunay(1, 60),
    "random 500": random_delaunay(2, 500),
    "int32 indices": (lattice_square(3)[0], lattice_square(3)[1].astype(np.int32)),
}


# -- measures --------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(MESHES))
def test_measures_equal_direct_computation(name):
    pts, tri = MESHES[name]
    q = quality(pts, tri)
    ref = reference(pts, tri)
    L = ref["lengths"]
    assert q.n_vertices == len(pts)
    assert q.n_triangles == len(tri)
    assert q.n_edges == len(L)
    assert q.n_boundary_edges == ref["n_boundary_edges"]
    assert q.area == pytest.approx(ref["area"], rel=1e-12)
    assert q.shortest_edge == pytest.approx(L.min(), rel=1e-12)
    assert q.longest_edge == pytest.approx(L.max(), rel=1e-12)
    assert q.edge_ratio == pytest.approx(L.max() / L.min(), rel=1e-12)
    assert q.mean_edge == pytest.approx(L.mean(), rel=1e-12)
    assert q.std_edge == pytest.approx(math.sqrt(((L - L.mean()) ** 2).mean()), rel=1e-9)
    assert q.cv_edge == pytest.approx(L.std() / L.mean(), rel=1e-9)
    assert q.min_angle == pytest.approx(ref["angles"].min(), abs=1e-6)
    assert q.max_angle == pytest.approx(ref["angles"].max(), abs=1e-6)
    assert q.max_perimeter == pytest.approx(ref["max_perimeter"], rel=1e-12)
    counts, bin_edges = np.histogram(L / L.mean(), bins=20)
    assert list(q.histogram_counts) == counts.tolist()
    np.testing.assert_allclose(q.histogram_edges, bin_edges, rtol=1e-12)
    assert q.longest_edge_bound is None and q.n_steiner is None


@pytest.mark.parametrize("name", sorted(MESHES))
def test_edge_lengths_equal_direct_computation(name):
    pts, tri = MESHES[name]
    edges, lengths = edge_lengths(pts, tri)
    ref = reference(pts, tri)
    assert edges.dtype == np.int64 and edges.shape == (len(ref["edges"]), 2)
    np.testing.assert_array_equal(edges, ref["edges"])
    np.testing.assert_allclose(lengths, ref["lengths"], rtol=1e-14)


def test_histogram_counts_sum_to_edges_and_bins_option():
    pts, tri = random_delaunay(3, 300)
    for bins in (1, 7, 20, 50):
        q = quality(pts, tri, bins=bins)
        assert len(q.histogram_counts) == bins and len(q.histogram_edges) == bins + 1
        assert sum(q.histogram_counts) == q.n_edges


def test_to_dict_round_trips_through_json():
    pts, tri = lattice_square(4)
    for q in (quality(pts, tri), quality(pts, tri, SQUARE, d_n=0.25)):
        d = q.to_dict()
        assert json.loads(json.dumps(d, allow_nan=False)) == d
        assert set(d) == {f for f in Quality.__dataclass_fields__}
    d = q.to_dict()
    assert d["longest_edge_bound"]["term"] == q.longest_edge_bound.term
    assert d["longest_edge_bound"]["terms"]["area"] == q.longest_edge_bound.terms[0][1]
    assert d["histogram_counts"] == list(q.histogram_counts)


def test_infinite_ratio_is_none_in_dict():
    pts = np.array([(0, 0), (1, 0), (0, 1), (0, 0)], dtype=float)  # point 3 duplicates 0
    q = quality(pts, [(0, 1, 2), (0, 3, 1)])  # edge 0-3 has length 0
    assert q.edge_ratio == math.inf
    d = q.to_dict()
    assert d["edge_ratio"] is None
    json.dumps(d, allow_nan=False)


def test_summary_reports_the_numbers():
    pts, tri = lattice_square(3)
    q = quality(pts, tri, SQUARE, d_n=1 / 3)
    s = q.summary()
    assert str(q) == s
    for text in ("Vertices: 16", "Triangles: 18", "Edges: 33", "Longest edge", "Edge ratio",
                 "n = 12 Steiner points", q.longest_edge_bound.term):
        assert text in s
    assert "Lower bounds" not in quality(pts, tri).summary()
    # The certificate leads: one line per measure, its factor in words and its active bound.
    lines = s.splitlines()
    assert lines[0].startswith("Certified against every triangulation") and "n = 12" in lines[0]
    assert lines[1:4] == q.certificate()[1:]
    for line, b in zip(lines[1:4], q.bounds.values()):
        assert f"within {(b.factor - 1) * 100:.3g} % of the best possible" in line
        assert line.endswith(f"bound: {b.active}")
    assert "corner (90 deg at (0, 0), best split in 2)" in lines[3]
    assert quality(pts, tri).certificate() == [] and quality(pts, tri).bounds == {}
    assert not quality(pts, tri).summary().startswith("Certified")


def test_inputs_are_not_mutated():
    pts, tri = random_delaunay(4, 50)
    pts.setflags(write=False)
    tri.setflags(write=False)
    p0, t0 = pts.copy(), tri.copy()
    quality(pts, tri, SQUARE, d_n=0.01)
    edge_lengths(pts, tri)
    np.testing.assert_array_equal(pts, p0)
    np.testing.assert_array_equal(tri, t0)


def test_quality_is_frozen():
    q = quality(*lattice_square(2))
    with pytest.raises(AttributeError):
        q.longest_edge = 0.0


@pytest.mark.parametrize(
    "points, triangles, match",
    [
        (np.zeros((3, 3)), [(0, 1, 2)], "points"),
        ([(0, 0), (1, 0), (np.nan, 1)], [(0, 1, 2)], "non-finite"),
        ([(0, 0), (1, 0), (0, 1)], [(0, 1, 3)], "outside"),
        ([(0, 0), (1, 0), (0, 1)], [(0, 1)], "triangles"),
        ([(0, 0), (1, 0), (0, 1)], [(0.0, 1.0, 2.0)], "integer"),
        ([(0, 0), (1, 0), (0, 1)], np.zeros((0, 3), int), "no triangles"),
    ],
)
def test_bad_input_raises(points, triangles, match):
    with pytest.raises(ValueError, match=match):
        quality(points, triangles)


# -- the bounds: formulas --------------------------------------------------------
def test_bound_formulas_and_terms():
    pts, tri = lattice_square(4)
    n = len(pts) - 4
    dn = 0.25
    q = quality(pts, tri, SQUARE, d_n=dn)
    t_max = 2 * n + 4 - 2
    assert (q.n_steiner, q.t_max, q.convex, q.d_n) == (n, t_max, True, dn)
    s = 1 - BOUND_SLACK
    longest = dict(q.longest_edge_bound.terms)
    assert longest["area"] == pytest.approx(math.sqrt(4 / (SQRT3 * t_max)) * s, rel=1e-14)
    assert longest["packing"] == pytest.approx(SQRT3 / 2 * dn * s, rel=1e-14)
    assert longest["boundary"] == pytest.approx(4 / (4 + n) * s, rel=1e-14)
    per = dict(q.max_perimeter_bound.terms)
    assert per["area"] == pytest.approx(math.sqrt(12 * SQRT3 / t_max) * s, rel=1e-14)
    assert per["packing"] == pytest.approx(SQRT3 * dn * s, rel=1e-14)
    assert per["boundary"] == pytest.approx(8 / (4 + n) * s, rel=1e-14)
    ratio = dict(q.edge_ratio_bound.terms)
    assert ratio["trivial"] == pytest.approx(1.0 * s, rel=1e-14)
    # Every corner is 90 degrees: two triangles of 45 degrees there at best.
    assert ratio["corner"] == pytest.approx(1 / (2 * math.sin(math.pi / 8)) * s, rel=1e-14)
    assert q.edge_ratio_bound.term == "corner"
    assert q.edge_ratio_bound.detail.startswith("90 deg at (0, 0)")
    assert ratio["boundary"] == pytest.approx(max(longest.values()) / 1.0, rel=1e-14)
    for b in (q.longest_edge_bound, q.max_perimeter_bound, q.edge_ratio_bound):
        assert b.value == max(v for _, v in b.terms)
        assert b.term == max(b.terms, key=lambda kv: kv[1])[0]
        assert b.factor == pytest.approx(b.achieved / b.value, rel=1e-14)
    assert q.longest_edge_bound.achieved == q.longest_edge
    assert q.max_perimeter_bound.achieved == q.max_perimeter
    assert q.edge_ratio_bound.achieved == q.edge_ratio


def test_n_steiner_and_holes_enter_t_max():
    P = Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (2, 1), (2, 2), (1, 2)]])
    pts = np.vstack([P.vertices, [(3, 3), (3, 0.5)]])
    tri = Delaunay(pts).simplices  # not a triangulation of P: only t_max is checked
    q = quality(pts, tri, P)
    assert q.n_steiner == 2 and q.t_max == 2 * 2 + 8 + 2 * 1 - 2
    assert q.convex is False and q.d_n is None
    q = quality(pts, tri, P, n_steiner=10)
    assert q.n_steiner == 10 and q.t_max == 2 * 10 + 8 + 2 - 2


def test_packing_term_only_for_convex_polygons_without_holes():
    L = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    pts = np.vstack([L.vertices, [(0.5, 0.5)]])
    tri = Delaunay(pts).simplices
    q = quality(pts, tri, L, d_n=0.5)  # given, but Lemma 9 does not apply
    assert q.convex is False and q.d_n is None
    assert "packing" not in dict(q.longest_edge_bound.terms)
    q = quality(*lattice_square(2), SQUARE, d_n=False)
    assert q.convex is True and q.d_n is None
    assert "packing" not in dict(q.longest_edge_bound.terms)
    q = quality(*lattice_square(2), SQUARE, n_steiner=0)  # n = 0: d_0 = l(V, V), no INSERT run
    assert q.d_n == 1.0


def test_bad_bound_arguments_raise():
    pts, tri = lattice_square(2)
    with pytest.raises(ValueError, match="l\\(V, V\\)"):
        quality(pts, tri, SQUARE, d_n=1.5)
    with pytest.raises(ValueError, match="positive"):
        quality(pts, tri, SQUARE, d_n=-1.0)
    with pytest.raises(ValueError, match="n_steiner"):
        quality(pts, tri, SQUARE, n_steiner=-1)
    big = Polygon([(0, 0), (1, 0), (1, 1), (0.5, 1.5), (0, 1)])
    with pytest.raises(ValueError, match="n_steiner"):
        quality(SQUARE.vertices, [(0, 1, 2)], big)  # 4 points, 5 polygon vertices


def test_area_mismatch_is_logged(caplog):
    with caplog.at_level(logging.WARNING, logger="uniform2d.quality"):
        quality(SQUARE.vertices, [(0, 1, 2)], SQUARE, d_n=False)  # half the square
    assert "area" in caplog.text


def test_polygon_may_be_a_ring_or_shapely():
    pts, tri = lattice_square(3)
    a = quality(pts, tri, SQUARE, d_n=False)
    b = quality(pts, tri, [(0, 0), (1, 0), (1, 1), (0, 1)], d_n=False)
    c = quality(pts, tri, SQUARE.to_shapely(), d_n=False)
    assert a == b == c


# -- the bounds are lower bounds ------------------------------------------------
def assert_not_beaten(q):
    for b in (q.longest_edge_bound, q.max_perimeter_bound, q.edge_ratio_bound):
        assert b.value <= b.achieved, b
        assert b.factor >= 1.0, b


@pytest.mark.parametrize("k", range(1, 9))
def test_lattice_square(k):
    pts, tri = with_polygon_first(SQUARE, *lattice_square(k))
    # The lattice points themselves are a packing of n points: d_n = 1/k <= d_n*.
    q = quality(pts, tri, SQUARE, d_n=1.0 / k)
    assert q.n_steiner == (k + 1) ** 2 - 4
    assert_not_beaten(q)


def test_equilateral_triangle_is_optimal_with_no_steiner_points():
    P = triangle_polygon(60, 60)
    q = quality(P.vertices, [(0, 1, 2)], P)
    assert q.t_max == 1 and q.n_steiner == 0
    assert q.longest_edge_bound.factor == pytest.approx(1.0, abs=1e-8)
    assert q.longest_edge_bound.factor >= 1.0
    assert q.max_perimeter_bound.factor == pytest.approx(1.0, abs=1e-8)
    assert q.max_perimeter_bound.factor >= 1.0
    assert q.edge_ratio_bound.value <= 1.0
    assert q.edge_ratio_bound.value == pytest.approx(1.0, abs=1e-8)
    assert q.edge_ratio_bound.term in ("trivial", "boundary")
    assert all("optimal (within 0.05 %)" in line for line in q.certificate()[1:])


@pytest.mark.parametrize("k", [2, 3, 5])
def test_subdivided_equilateral_triangle(k):
    P = triangle_polygon(60, 60)
    a, b, c = P.vertices
    pts, index = [], {}
    for i in range(k + 1):
        for j in range(k + 1 - i):
            index[i, j] = len(pts)
            pts.append(a + (b - a) * i / k + (c - a) * j / k)
    tri = []
    for i in range(k):
        for j in range(k - i):
            tri.append((index[i, j], index[i + 1, j], index[i, j + 1]))
            if i + j < k - 1:
                tri.append((index[i + 1, j], index[i + 1, j + 1], index[i, j + 1]))
    pts, tri = with_polygon_first(P, np.array(pts), np.array(tri))
    q = quality(pts, tri, P, d_n=P.min_vertex_distance() / k * (1 - 1e-12))
    assert q.edge_ratio == pytest.approx(1.0)
    assert_not_beaten(q)


def test_thin_triangle_with_a_20_degree_corner():
    """The sharpest corner is 20 degrees: the bound is 2 cos 20 = 1.879, and
    it is reached: 1 / (2 sin 10) = 2.879 would *not* be a lower bound."""
    theta = math.radians(20)
    assert corner_ratio(theta) == pytest.approx(2 * math.cos(theta))

    # Isosceles with a 20 degree apex, no Steiner points: ratio 2.879.
    thin = triangle_polygon(80, 80)
    q = quality(thin.vertices, [(0, 1, 2)], thin)
    corner = dict(q.edge_ratio_bound.terms)["corner"]
    assert corner == pytest.approx(2 * math.cos(theta), rel=1e-8)
    assert q.edge_ratio == pytest.approx(1 / (2 * math.sin(theta / 2)))
    assert_not_beaten(q)

    # The same polygon with 3 Steiner points on its legs (found by numerical
    # optimisation) has ratio 1.8801 < 2.879, just above the bound 1.8794.
    V = np.array([(0, 0), (math.cos(theta / 2), -math.sin(theta / 2)),
                  (math.cos(theta / 2), math.sin(theta / 2))])
    P = Polygon(V)
    u1, u2 = V[1] / np.linalg.norm(V[1]), V[2] / np.linalg.norm(V[2])
    steiner = np.array([0.52031150 * u2, 0.71365292 * u1, 0.27699087 * u1])
    pts = np.vstack([P.vertices, steiner])
    tri = Delaunay(pts).simplices
    q = quality(pts, tri, P)
    assert q.area == pytest.approx(P.area)
    assert q.edge_ratio < 1 / (2 * math.sin(theta / 2))
    assert q.edge_ratio == pytest.approx(1.8801, abs=1e-3)
    assert_not_beaten(q)

    # 20-20-140 triangle, no Steiner points: reaches the bound exactly.
    flat = triangle_polygon(20, 20)
    q = quality(flat.vertices, [(0, 1, 2)], flat)
    assert q.edge_ratio == pytest.approx(2 * math.cos(theta))
    assert q.edge_ratio_bound.factor == pytest.approx(1.0, abs=1e-8)
    assert_not_beaten(q)


@pytest.mark.parametrize("apex", [5, 20, 35, 36, 37, 45, 55, 59.5])
def test_corner_bound_is_reached(apex):
    """Below 36 degrees the obtuse isosceles triangle reaches the bound,
    above it the isosceles one with that apex."""
    th = math.radians(apex)
    P = triangle_polygon(apex, apex) if apex <= 36 else triangle_polygon(90 - apex / 2, 90 - apex / 2)
    q = quality(P.vertices, [(0, 1, 2)], P)
    assert q.edge_ratio_bound.value == pytest.approx(corner_ratio(th), rel=1e-8)
    assert q.edge_ratio == pytest.approx(corner_ratio(th), rel=1e-8)
    assert_not_beaten(q)


@settings(max_examples=300, deadline=None)
@given(
    st.floats(0.5, 59.5), st.floats(0.5, 179.0),
)
def test_every_triangle_with_an_angle_has_at_least_the_corner_ratio(alpha, beta):
    """The lemma behind the corner term, on arbitrary triangles."""
    assume(alpha + beta < 179.5)
    gamma = 180 - alpha - beta
    sides = [math.sin(math.radians(x)) for x in (alpha, beta, gamma)]
    assert max(sides) / min(sides) >= corner_ratio(math.radians(alpha)) * (1 - 1e-12)


def grid_packing_distance(n):
    """A valid d_n for the unit square: n of the non-corner points of the finest
    m x m grid that has enough of them, so d_n = 1/m <= d_n*."""
    m = 1
    while (m + 1) ** 2 - 4 < n:
        m += 1
    return 1.0 / m


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.integers(0, 150), st.booleans())
def test_random_delaunay_never_beats_a_bound(seed, n, on_boundary):
    rng = np.random.default_rng(seed)
    extra = rng.random((n, 2))
    if on_boundary and n:
        k = rng.integers(0, n + 1)
        extra[:k, rng.integers(0, 2)] = rng.integers(0, 2)  # some points on the sides
    pts = np.vstack([SQUARE.vertices, extra])
    assume(len(np.unique(pts, axis=0)) == len(pts))
    tri = Delaunay(pts).simplices
    assume(len(tri) and np.isclose(quality(pts, tri).area, 1.0))
    for d_n in (grid_packing_distance(n), False):
        q = quality(pts, tri, SQUARE, d_n=d_n)
        assert_not_beaten(q)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(0, 60), st.floats(3.0, 59.0))
def test_random_triangulations_of_a_sharp_triangle(seed, n, apex):
    P = triangle_polygon(90 - apex / 2, 90 - apex / 2)
    rng = np.random.default_rng(seed)
    w = rng.dirichlet(np.ones(3), size=n)
    pts = np.vstack([P.vertices, w @ P.vertices])
    assume(len(np.unique(pts, axis=0)) == len(pts))
    tri = Delaunay(pts).simplices
    q = quality(pts, tri, P, d_n=False)
    assert q.edge_ratio_bound.value >= corner_ratio(math.radians(apex)) * (1 - 1e-8)
    assert_not_beaten(q)


def test_meshes_of_a_polygon_with_a_hole_never_beat_a_bound():
    triangle = pytest.importorskip("triangle")
    P = Polygon([(0, 0), (3, 0), (3, 1), (1, 1), (1, 2.5), (0, 2.5)],
                [[(0.3, 0.3), (0.7, 0.3), (0.7, 0.6), (0.3, 0.6)]])
    seg = P.edges
    for opts in ("p", "pq", "pq30a0.05", "pq30a0.005", "pa0.01"):
        r = triangle.triangulate(
            {"vertices": P.vertices.copy(), "segments": seg, "holes": [(0.5, 0.45)]}, opts
        )
        pts, tri = r["vertices"], r["triangles"]
        np.testing.assert_array_equal(pts[: len(P.vertices)], P.vertices)
        q = quality(pts, tri, P)
        assert q.area == pytest.approx(P.area)
        assert q.convex is False and q.t_max == 2 * q.n_steiner + 10 + 2 - 2
        assert_not_beaten(q)


def test_default_d_n_runs_insert():
    insert = pytest.importorskip("uniform2d.insert").insert
    from scipy.spatial import cKDTree

    hexagon = Polygon([(math.cos(a), math.sin(a)) for a in np.arange(6) * math.pi / 3])
    for n in (1, 5, 30):
        r = insert(hexagon, n)
        q = quality(r.mesh_points, r.triangles, hexagon)
        d, _ = cKDTree(r.mesh_points).query(r.mesh_points, k=2)
        assert q.d_n == pytest.approx(d[:, 1].min(), rel=1e-12)
        assert_not_beaten(q)


def test_bound_dataclass_is_hashable_and_plain():
    q = quality(*lattice_square(3), SQUARE, d_n=1 / 3)
    hash(q)
    assert isinstance(q.longest_edge_bound, Bound)
    assert all(type(v) is float for _, v in q.longest_edge_bound.terms)


def _split_reference(edges, n, t_max, K, c):
    """The ``split`` term by enumeration: every way of putting k <= n boundary
    points on the polygon edges (m_e - 1 on edge e), the longest piece
    max L_e / m_e, the value max(c * piece, sqrt(K / (t_max - k))), minimised."""
    import itertools

    best = math.inf
    for ks in itertools.product(range(n + 1), repeat=len(edges)):
        k = sum(ks)
        if k > n:
            continue
        piece = max(L / (j + 1) for L, j in zip(edges, ks))
        best = min(best, max(c * piece, math.sqrt(K / (t_max - k))))
    return best


@pytest.mark.parametrize(
    "ring, holes, n",
    [
        ([(0, 0), (4, 0), (4, 1), (0, 1)], [], 6),
        ([(0, 0), (3, 0), (3, 3), (0, 3)], [], 9),
        ([(0, 0), (5, 0), (2, 2)], [], 12),
        ([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)], [], 5),
        ([(0, 0), (6, 0), (6, 6), (0, 6)], [[(2, 2), (3, 2), (3, 3)]], 4),
    ],
)
def test_split_term_equals_enumeration_over_boundary_point_counts(ring, holes, n):
    P = Polygon(ring, holes)
    pts = np.vstack([P.vertices, np.full((n, 2), np.nan)])[: len(P.vertices)]
    tri = Delaunay(P.vertices).simplices  # only the bounds are checked
    q = quality(pts, tri, P, n_steiner=n)
    e = P.edges
    edges = np.linalg.norm(P.vertices[e[:, 1]] - P.vertices[e[:, 0]], axis=1)
    s = 1 - BOUND_SLACK
    A = P.area
    for bound, K, c in (
        (q.longest_edge_bound, 4 * A / SQRT3, 1.0),
        (q.max_perimeter_bound, 12 * SQRT3 * A, 2.0),
    ):
        terms = dict(bound.terms)
        want = _split_reference(edges, n, q.t_max, K, c) * s
        assert terms["split"] <= want * (1 + 1e-12)  # a bound: never above the minimum
        assert terms["split"] == pytest.approx(want, rel=1e-12)
        assert terms["split"] >= terms["area"] * (1 - 1e-15)
        assert terms["split"] >= terms["boundary"] * (1 - 1e-15)
        assert bound.term == "split"  # these cases are chosen so that it binds


def test_unique_edges_against_a_counter_of_sorted_pairs():
    from collections import Counter

    from uniform2d.geometry import unique_edges

    rng = np.random.default_rng(3)
    tri = rng.integers(0, 300, (2000, 3)).astype(np.int32)
    want = Counter(tuple(sorted((int(t[i]), int(t[(i + 1) % 3])))) for t in tri for i in range(3))
    edges, counts = unique_edges(tri, 300, return_counts=True)
    assert edges.dtype == np.int64 and edges.shape == (len(want), 2)
    assert [tuple(e) for e in edges.tolist()] == sorted(want)
    assert counts.tolist() == [want[k] for k in sorted(want)]
    assert np.array_equal(unique_edges(tri), edges)


@pytest.mark.parametrize("case", ["random", "fan"])
def test_quality_edges_by_vertex_against_a_counter_of_sorted_pairs(case):
    """The measures' bucketed edge list: small buckets (insertion sort) and a
    fan's apex, whose bucket holds every edge (numpy's sort)."""
    from collections import Counter

    from uniform2d.measures import edges_with_counts as _unique_edges

    rng = np.random.default_rng(5)
    if case == "random":
        tri = rng.integers(0, 300, (2000, 3))
    else:
        rim = rng.permutation(np.arange(1, 602))
        tri = np.column_stack([np.zeros(600, np.int64), rim[:-1], rim[1:]])
    want = Counter(tuple(sorted((int(t[i]), int(t[(i + 1) % 3])))) for t in tri for i in range(3))
    ro = np.array(tri, np.int64)
    ro.flags.writeable = False
    for arg in (tri, ro):
        edges, counts = _unique_edges(arg, 602)
        assert [tuple(e) for e in edges.tolist()] == sorted(want)
        assert counts.tolist() == [want[k] for k in sorted(want)]
