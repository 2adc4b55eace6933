"""uniform2d.lattice_bound: the lattice term of the edge-ratio bound checked against
an independent enumeration (lattice points counted one by one), reached by real
lattice meshes where one fits, and attacked by meshes of every method we have."""

import itertools
import math

import numpy as np
import pytest
import shapely

from uniform2d import Polygon, uniform_mesh
from uniform2d.bounds import BOUND_SLACK, triangle_ratio_floor
from uniform2d.lattice_bound import G5, STEPS, lattice_count, lattice_ratio_floor
from uniform2d.quality import quality
from uniform2d.sites import site_edges
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate

BASIS = np.array([[1.0, 0.0], [0.5, math.sqrt(3) / 2]])


def regular(m, r=1.0, turn=0.0):
    return Polygon([(r * math.cos(turn + 2 * math.pi * i / m), r * math.sin(turn + 2 * math.pi * i / m))
                    for i in range(m)])


HEXAGON = regular(6)


def lattice_polygon(a, k):
    """The lattice polygon of sides ``a`` turning 180 - 60 k[v] degrees at side v:
    its corners in the plane (unit steps), counter-clockwise."""
    t = np.concatenate([[0], np.cumsum(3 - np.asarray(k[1:]))]) % 6
    corners = np.cumsum(np.asarray(a)[:, None] * STEPS[t], axis=0)
    return np.roll(corners, 1, axis=0) @ BASIS


def lattice_points_in(corners):
    """Every lattice point in the closed polygon ``corners``, counted one by one."""
    shp = shapely.Polygon(corners)
    x0, y0, x1, y1 = shp.bounds
    j = np.arange(math.floor(y0 / BASIS[1, 1]) - 1, math.ceil(y1 / BASIS[1, 1]) + 2)
    i = np.arange(math.floor(x0 - y1) - 2, math.ceil(x1 - y0) + 3)
    I, J = np.meshgrid(i, j)
    P = np.stack([I.ravel(), J.ravel()], axis=1) @ BASIS
    inside = shapely.covers(shapely.buffer(shp, 1e-9), shapely.points(P))
    return P[inside]


@pytest.mark.parametrize("a", [(1, 1, 1, 1, 1, 1), (3, 2, 4, 3, 2, 4), (5, 1, 4, 3, 3, 2),
                               (7, 7, 8, 7, 7, 8), (1, 3, 2, 2, 2, 3)])
def test_count_of_a_lattice_hexagon_is_its_lattice_points(a):
    n_points, T = lattice_count(a, [2] * 6)
    corners = lattice_polygon(a, [2] * 6)
    assert n_points == len(lattice_points_in(corners))
    assert T == pytest.approx(shapely.Polygon(corners).area / (math.sqrt(3) / 4))


def test_count_of_triangles_parallelograms_and_a_non_convex_path():
    assert lattice_count([4, 4, 4], [1, 1, 1]) == (15, 16)
    assert lattice_count([3, 2, 3, 2], [1, 2, 1, 2]) == (12, 12)
    # an L-like lattice hexagon with a 240 degree corner (k = 4)
    a, k = [4, 1, 2, 1, 2, 6], [1, 2, 2, 4, 2, 1]
    corners = lattice_polygon(a, k)
    assert lattice_count(a, k)[0] == len(lattice_points_in(corners))
    with pytest.raises(ValueError, match="does not close"):
        lattice_count([1, 2, 1, 1, 1, 1], [2] * 6)


def reference_floors(polygon, top):
    """N -> the least lattice floor below 2 sin 36 deg, by brute force: every corner
    split and every side vector with entries up to ``top``, closed paths kept,
    their points counted one by one (the formula's count must agree)."""
    V = polygon.vertices
    L = np.hypot(*(np.roll(V, -1, axis=0) - V).T)
    alphas = polygon.interior_angles()
    floors = {}
    splits = [ks for ks in itertools.product(*[range(1, 7)] * len(V)) if sum(ks) == 3 * len(V) - 6]
    for ks in splits:
        corner = max(triangle_ratio_floor(al / kv) for al, kv in zip(alphas, ks))
        if corner >= G5:
            continue
        for a in itertools.product(range(1, top + 1), repeat=len(V)):
            piece = L / np.asarray(a)
            if piece.max() >= G5 * piece.min():
                continue
            try:
                n_points, T = lattice_count(a, ks)
            except ValueError:
                continue
            if T <= 0:
                continue
            assert len(lattice_points_in(lattice_polygon(a, ks))) == n_points
            value = max(piece.max(), math.sqrt(4 * polygon.area / (math.sqrt(3) * T))) / piece.min()
            floors[n_points] = min(floors.get(n_points, G5), max(value, corner))
    return floors


@pytest.mark.parametrize("name, polygon, top, most", [
    ("hexagon", HEXAGON, 6, 90),
    ("long hexagon", Polygon(lattice_polygon([3, 1, 2, 3, 1, 2], [2] * 6)), 7, 60),
    ("triangle", regular(3), 14, 100),
    ("rhombus", Polygon(lattice_polygon([3, 3, 3, 3], [1, 2, 1, 2])), 10, 100),
])
def test_term_equals_brute_force(name, polygon, top, most):
    """Up to ``most`` points every candidate has sides below ``top`` (their pieces
    within 2 sin 36 deg of each other, their count at most ``most``)."""
    floors = reference_floors(polygon, top)
    lo = len(polygon.vertices)
    for N in range(lo + 1, most + 1):
        term = lattice_ratio_floor(polygon, N - lo)
        assert term is not None
        assert term.value == pytest.approx(floors.get(N, G5), rel=1e-12), (name, N)


@pytest.mark.parametrize("a", [(4, 4, 4, 4, 4, 4), (3, 4, 3, 4, 3, 4), (5, 3, 4, 4, 4, 3),
                               (6, 5, 6, 6, 5, 6)])
def test_a_lattice_mesh_reaches_ratio_one_and_is_not_beaten(a):
    """On a lattice hexagon the lattice itself is a mesh of ratio 1 with exactly its
    point count: the term must allow it (no more than 1)."""
    P = Polygon(lattice_polygon(a, [2] * 6))
    pts = lattice_points_in(P.outer)
    corner = (np.abs(pts[:, None, :] - P.vertices[None]).max(axis=2) < 1e-9).any(axis=1)
    sites = pts[~corner]
    _, edges = site_edges(P, sites)
    points, triangles = triangulate(P, sites, edges)
    check_mesh(points, triangles, P, n_steiner=len(sites))
    q = quality(points, triangles, P, d_n=False)
    assert q.edge_ratio == pytest.approx(1.0, abs=1e-9)
    assert q.edge_ratio_bound.value <= q.edge_ratio
    assert dict(q.edge_ratio_bound.terms)["lattice"] <= 1.0


@pytest.mark.parametrize("n", [40, 57, 99, 130, 250])
def test_no_mesh_of_any_method_beats_it_on_the_hexagon(n):
    """Ours (every objective, the ratio one included) and Gmsh's meshes of a
    regular hexagon, turned and scaled: never below the term."""
    from uniform2d.peers import base as peers

    P = regular(6, r=2.5, turn=0.3)
    meshes = {obj: uniform_mesh(P, n, objective=obj) for obj in ("balanced", "ratio")}
    meshes = {k: (m.points, m.triangles) for k, m in meshes.items()}
    if peers.available("gmsh"):
        pm = peers.mesh("gmsh", P, len(P.vertices) + n)
        meshes["gmsh"] = (pm.points, pm.triangles)
    for what, (pts, tri) in meshes.items():
        check_mesh(pts, tri, P, delaunay=False, area_rtol=1e-7)
        q = quality(pts, tri, P, d_n=False)
        term = dict(q.edge_ratio_bound.terms)["lattice"]
        assert term <= q.edge_ratio, (what, n, term, q.edge_ratio)


def test_jittered_lattice_meshes_stay_above_the_term():
    """A perfect lattice of 331 points, every point moved at random: ratio above 1,
    and still a lattice patch of 331 points, so never below the term (1 there)."""
    rng = np.random.default_rng(3)
    P = Polygon(lattice_polygon([10] * 6, [2] * 6))
    pts = lattice_points_in(P.outer)
    corner = (np.abs(pts[:, None, :] - P.vertices[None]).max(axis=2) < 1e-9).any(axis=1)
    sites0 = pts[~corner]
    _, edges = site_edges(P, sites0)
    for _ in range(5):
        sites = sites0 + np.where(edges[:, None] < 0, rng.normal(0, 0.05, sites0.shape), 0)
        points, triangles = triangulate(P, sites, edges)
        q = quality(points, triangles, P, d_n=False)
        assert q.edge_ratio_bound.value <= q.edge_ratio


def test_only_for_exactly_n_points_and_simple_polygons():
    m = uniform_mesh(HEXAGON, 60)
    assert "lattice" in dict(m.quality().edge_ratio_bound.terms)
    q = quality(m.points, m.triangles, HEXAGON, n_steiner=m.n_steiner + 3, d_n=False)
    assert "lattice" not in dict(q.edge_ratio_bound.terms)
    # a point no triangle uses: the triangulation has one point fewer
    extra = np.vstack([m.points, [[0.01, 0.02]]])
    q = quality(extra, m.triangles, HEXAGON, d_n=False)
    assert "lattice" not in dict(q.edge_ratio_bound.terms)
    assert lattice_ratio_floor(Polygon(HEXAGON.outer, [0.3 * regular(6).outer[::-1]]), 60) is None
    assert lattice_ratio_floor(regular(4), 60) is None      # 90 deg corners: 1.307 already
    assert lattice_ratio_floor(regular(12), 60) is None     # more edges than MAX_EDGES


def test_scale_rotation_and_slack():
    a = lattice_ratio_floor(HEXAGON, 300)
    b = lattice_ratio_floor(regular(6, r=7.0, turn=1.1), 300)
    assert a.value == pytest.approx(G5) and b.value == pytest.approx(a.value, rel=1e-12)
    m = uniform_mesh(HEXAGON, 300)
    bound = m.quality().edge_ratio_bound
    assert bound.term == "lattice" and bound.value == pytest.approx(G5 * (1 - BOUND_SLACK), rel=1e-14)
