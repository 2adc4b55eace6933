"""INSERT and T+ on polygons with interior segments and fixed points.

INSERT is checked step by step against the brute-force reference
(``reference_insert``, which knows segments only as visibility blockers and
candidate carriers) on a free stiffener, T-junctions, a closed segment, fixed
points (one on a segment) and a hole; then for the kernel alone: non-increasing
weights, bit-identical repeated calls, invariance under scaling and
translation.  Every mesh passes ``uniform2d.testing.check_mesh`` (segments are chains of
mesh edges, fixed points are vertices, exactly n Steiner points), and a fuzz
test draws random constrained domains.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import uniform2d
from uniform2d.testing import check_mesh
from support.reference_insert import reference_insert
from uniform2d import Polygon
from uniform2d._kernel.validity import mesh_problem
from uniform2d.errors import InternalError

SQ = [(0, 0), (4, 0), (4, 3), (0, 3)]
HOLE = [(2.5, 0.5), (3.5, 0.5), (3.5, 1.2), (2.5, 1.2)]
CASES = {
    "free": (dict(outer=SQ, segments=[[(1, 1), (3, 2)]]), 60),
    "fixed": (dict(outer=SQ, segments=[[(1, 1), (3, 2)]], points=[(0.5, 2.5), (2, 1.5)]), 60),
    "tjunction": (dict(outer=SQ, segments=[[(2, 0), (2, 1.5), (3, 2.2)]]), 60),
    "closed": (dict(outer=SQ, segments=[[(1, 1), (3, 1), (3, 2.5), (1, 2.5), (1, 1)]]), 60),
    "hole": (
        dict(outer=SQ, holes=[HOLE], segments=[[(0, 1.5), (2.5, 1.2)], [(1, 2.5), (2, 2.5)]],
             points=[(3, 2.5)]),
        60,
    ),  # fmt: skip
    "crossing-ridge": (
        dict(outer=[(0, 0), (3, 0), (3, 2), (1.5, 3), (0, 2)],
             segments=[[(0, 2), (1.5, 1.2), (3, 2)], [(1.5, 0), (1.5, 1.2), (1.5, 3)]]),
        50,
    ),  # fmt: skip
}


def _polygon(case, scale=1.0, offset=(0.0, 0.0)):
    kw = dict(CASES[case][0])
    f = lambda pts: [(x * scale + offset[0], y * scale + offset[1]) for x, y in pts]  # noqa: E731
    return Polygon(
        f(kw["outer"]),
        [f(h) for h in kw.get("holes", ())],
        segments=[f(s) for s in kw.get("segments", ())],
        points=f(kw.get("points", [])),
    )


@functools.lru_cache(maxsize=None)
def _kernel(case):
    return uniform2d.insert(_polygon(case), CASES[case][1])


@pytest.mark.parametrize("case", list(CASES))
def test_insert_matches_reference(case):
    P, n = _polygon(case), CASES[case][1]
    res = _kernel(case)
    ref = reference_insert(P, n)
    dp = np.abs(res.points - ref.points).max(axis=1)
    dw = np.abs(res.weights - ref.weights) / ref.weights
    bad = np.flatnonzero((dp > 4e-9) | (dw > 1e-9) | (res.on_boundary != ref.on_boundary))
    assert not len(bad), (
        f"step {bad[0]}: kernel {res.points[bad[0]]} w={res.weights[bad[0]]!r} "
        f"on={res.on_boundary[bad[0]]}; reference {ref.points[bad[0]]} "
        f"w={ref.weights[bad[0]]!r} on={ref.on_boundary[bad[0]]}"
    )
    assert (np.diff(res.weights) <= 1e-9 * res.weights[1:]).all()
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=n)


def test_points_on_segments_are_split_exactly_once():
    res = _kernel("closed")
    P = _polygon("closed")
    # every point INSERT put on a constraint lies on the ring or the closed segment,
    # and the segment received some
    on = res.points[res.on_boundary]
    ring = Polygon(SQ).to_shapely().boundary
    import shapely

    line = shapely.LineString(P.segments[0])
    d_seg = shapely.distance(line, shapely.points(on))
    d_ring = shapely.distance(ring, shapely.points(on))
    assert (np.minimum(d_seg, d_ring) < 1e-12).all()
    assert (d_seg < 1e-12).sum() >= 4


def test_deterministic_and_invariant():
    case = "hole"
    n = 80
    base = uniform2d.insert(_polygon(case), n)
    again = uniform2d.insert(_polygon(case), n)
    assert base.points.tobytes() == again.points.tobytes()
    assert base.triangles.tobytes() == again.triangles.tobytes()
    for scale, off in ((1e-6, (0, 0)), (1e6, (0, 0)), (1.0, (1e6, -3e6)), (1e-3, (250.0, 40.0))):
        moved = uniform2d.insert(_polygon(case, scale, off), n)
        back = (moved.points - np.array(off)) / scale
        assert np.abs(back - base.points).max() <= 1e-9 * 4, (scale, off)
        assert np.allclose(moved.weights / scale, base.weights, rtol=1e-9, atol=0)
        assert np.array_equal(moved.on_boundary, base.on_boundary)
        check_mesh(moved.mesh_points, moved.triangles, moved.polygon, n_steiner=n)


@pytest.mark.parametrize(
    "case, n",
    [("free", 300), ("fixed", 300), ("tjunction", 300), ("hole", 300), ("crossing-ridge", 1000)],
)
def test_tplus_keeps_constraints(case, n):
    P = _polygon(case)
    mesh = uniform2d.tplus(P, n)
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=n)
    info = mesh.info
    assert info["k"] > 0 and info["d_n"] > 0
    # phase 2 put points on every segment piece longer than 3 d_n
    V = P.vertices
    E = P.segment_edges
    L = np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T)
    assert info["gap_max"] <= 3 * (1 + 1e-9)
    long_ = L > 3 * info["d_n"] * 1.01
    assert long_.any()


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("n", [60, 400])
def test_uniform_mesh_keeps_constraints(case, n):
    P = _polygon(case)
    mesh = uniform2d.uniform_mesh(P, n)
    # exactly n, segments are chains of edges through points on them, fixed points
    # are vertices where given, constrained Delaunay
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=n)
    start = mesh.info["start"]
    if start is not None:  # never worse than T+ on the objective
        assert mesh.info["objective_value"] <= start["objective"]
    assert mesh.info["fallback"] is None  # the optimiser's own mesh, not T+'s
    q = mesh.quality()
    assert q.edge_ratio < 2.0 and q.min_angle > 30.0


def test_points_slide_along_their_segment():
    from uniform2d.optimize import improve

    P = _polygon("free")
    sites = np.array([[2.0, 1.5], [1.5, 1.25], [2.5, 1.75], [3.0, 0.5], [1.0, 2.0]])
    pts, tri, info = improve(P, sites, href=0.6)
    check_mesh(pts, tri, P, n_steiner=len(sites))
    E = P.segment_edges[0]
    a, d = P.vertices[E[0]], P.vertices[E[1]] - P.vertices[E[0]]
    on = np.flatnonzero(info["edges"] >= P.n_ring_vertices)
    assert len(on) == 3
    rel = pts[len(P.vertices) + on] - a
    assert np.abs(d[0] * rel[:, 1] - d[1] * rel[:, 0]).max() <= 1e-12
    assert not np.array_equal(pts[len(P.vertices) + on], sites[on])  # they moved


def test_final_check_sees_a_missing_segment():
    P = _polygon("free")
    res = _kernel("free")
    # the same points triangulated without the segment: the piece is not a chain
    plain = Polygon(P.outer)
    from uniform2d.triangulation import triangulate

    pts, tri = triangulate(plain, np.concatenate([P.vertices[4:], res.points]))
    problem = mesh_problem(pts, tri, P, len(pts) - len(P.vertices), 1e-9)
    assert problem is not None and "segment piece" in problem
    with pytest.raises(AssertionError, match="segment piece"):
        check_mesh(pts, tri, P, delaunay=False)
    assert mesh_problem(res.mesh_points, res.triangles, P, len(res.points), 1e-9) is None


def test_sites_on_a_segment_split_it():
    P = _polygon("free")
    sites = [(2.0, 1.5), (1.5, 1.25), (0.5, 0.5)]
    res = uniform2d.insert(P, 10, sites=sites)
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=13)


# ------------------------------------------------------------------------------------
# fuzz: random constrained domains
# ------------------------------------------------------------------------------------
def _random_domain(seed):
    """A square with a hole, and random free, T-junction and closed segments,
    fixed points (some on a segment), some near-degenerate (ends 1e-9 from a ring,
    nearly collinear pieces); None if the draw is not a valid polygon."""
    rng = np.random.default_rng(seed)
    outer = [(0, 0), (1, 0), (1, 1), (0, 1)]
    holes = [[(0.7, 0.7), (0.7, 0.85), (0.85, 0.85), (0.85, 0.7)]] if rng.random() < 0.4 else []
    segs, pts = [], []
    for _ in range(int(rng.integers(1, 4))):
        kind = rng.integers(0, 4)
        a = rng.uniform(0.1, 0.6, 2)
        if kind == 0:  # free stiffener, maybe a polyline
            segs.append([tuple(a), tuple(a + rng.uniform(-0.3, 0.3, 2))])
        elif kind == 1:  # T-junction on the left or bottom edge
            start = (0.0, float(rng.uniform(0.1, 0.9))) if rng.random() < 0.5 else (
                float(rng.uniform(0.1, 0.9)), 0.0)
            segs.append([start, tuple(a)])
        elif kind == 2:  # closed triangle
            r = rng.uniform(0.05, 0.15)
            ang = rng.uniform(0, 2 * np.pi) + np.array([0, 2.1, 4.2])
            tri = [tuple(a + r * np.array([np.cos(t), np.sin(t)])) for t in ang]
            segs.append(tri + [tri[0]])
        else:  # near-degenerate: an end 1e-9 from the ring, a nearly straight bend
            y = float(rng.uniform(0.1, 0.6))
            segs.append([(1e-9, y), (0.3, y + 1e-10), (0.5, y + 0.2)])
    for s in segs[:1]:
        p, q = np.array(s[0]), np.array(s[1])
        pts.append(tuple(0.5 * (p + q)))  # on the first segment
    pts += [tuple(rng.uniform(0.05, 0.95, 2)) for _ in range(int(rng.integers(0, 3)))]
    try:
        return Polygon(outer, holes, segments=segs, points=pts)
    except uniform2d.InvalidPolygonError:
        return None


@settings(max_examples=30, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
@given(seed=st.integers(0, 10**6), n=st.integers(5, 150))
def test_fuzz_constrained(seed, n):
    P = _random_domain(seed)
    if P is None:
        return
    res = uniform2d.insert(P, n)
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=n)
    assert (np.diff(res.weights) <= 1e-9 * res.weights[1:]).all()
    mesh = uniform2d.uniform_mesh(P, n)
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=n)
    try:
        mesh = uniform2d.tplus(P, 4 * n)
    except uniform2d.InsufficientPointsError:
        return
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=4 * n)


# ------------------------------------------------------------------------------------
# certificates: no constrained mesh beats a bound
# ------------------------------------------------------------------------------------
@pytest.mark.parametrize("case", ["free", "fixed", "tjunction", "closed", "hole", "crossing-ridge"])
def test_bounds_not_beaten_by_constrained_meshes(case):
    from uniform2d.quality import quality

    P = _polygon(case)
    for n in (0, 7, 40, 150):
        res = uniform2d.insert(P, n)
        q = quality(res.mesh_points, res.triangles, P)
        for name, b in q.bounds.items():
            assert b.value <= b.achieved, (case, n, name, b)
        assert "packing" not in dict(q.bounds["longest_edge"].terms)


def test_t_max_counts_constraint_vertices_twice():
    from uniform2d.bounds import lower_bound_terms

    P = _polygon("fixed")
    c = len(P.vertices) - P.n_ring_vertices
    area = lower_bound_terms(P, 10, None)["longest_edge"][0]
    assert area.detail == f"{2 * 10 + len(P.vertices) + c - 2} triangles at most"
    # a mesh of P with 10 Steiner points inside really has that many triangles
    res = uniform2d.insert(P, 10)
    inner = (~res.on_boundary).sum()
    assert len(res.triangles) == 2 * inner + 2 * c + P.n_ring_vertices + (10 - inner) - 2


def test_uniform_mesh_power_of_two_scaling_is_exact():
    P = _polygon("hole")
    a = uniform2d.uniform_mesh(P, 150)
    b = uniform2d.uniform_mesh(P.transformed(2.0**-20), 150)
    assert np.array_equal(b.points, a.points * 2.0**-20)
    assert np.array_equal(b.triangles, a.triangles)


@pytest.mark.parametrize("s, off", [(1e-6, (0, 0)), (1e6, (0, 0)), (1.0, (1e6, -1e6))])
def test_uniform_mesh_scale_and_offset_keep_constraints_and_quality(s, off):
    P = _polygon("crossing-ridge")
    a = uniform2d.uniform_mesh(P, 150)
    Q = P.transformed(s, off)
    b = uniform2d.uniform_mesh(Q, 150)
    check_mesh(b.points, b.triangles, Q, n_steiner=150)
    qa, qb = a.quality(), b.quality()
    assert qb.edge_ratio == pytest.approx(qa.edge_ratio, rel=0.05)
    assert qb.min_angle == pytest.approx(qa.min_angle, rel=0.1)


def test_a_piece_through_a_vertex_is_refused_not_forced(monkeypatch):
    from uniform2d import triangulation
    from uniform2d._kernel import cdt, polytri
    from uniform2d.triangulation import rebuild

    P = Polygon(SQ, points=[(1, 1), (2, 2), (2.5, 2.5)])
    loaded = triangulation.load(P)
    u, _, v = (int(k) for k in P.fixed)
    # (2, 2) lies on the segment from (1, 1) to (2.5, 2.5): no edge can join them
    assert polytri.recover_pieces(loaded.m, np.array([u]), np.array([v])) == -1
    tri = cdt.triangle_list(loaded.m)
    with pytest.raises(InternalError, match="segment piece is not an edge.*please report"):
        rebuild(loaded.m, tri, (np.array([u]), np.array([v])))
    monkeypatch.setattr(polytri, "recover_pieces", lambda m, us, vs: -1)
    with pytest.raises(InternalError, match="could not recover the segment piece.*please report"):
        triangulation.load(_polygon("free"))
