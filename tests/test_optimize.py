"""uniform2d.optimize: the optimised mesh with exactly n Steiner points."""

import numpy as np
import pytest

import uniform2d
from uniform2d.optimize import OBJECTIVES, optimize_mesh, target_size

from uniform2d.testing import check_mesh
from support.benchmarks import benchmark_polygons
from uniform2d.testing.polygons import convex, star, with_holes

BENCH = benchmark_polygons()


def _crit(q):
    return q.edge_ratio, q.longest_edge, q.max_perimeter


@pytest.mark.parametrize("name", sorted(BENCH))
def test_benchmark_n200_beats_tplus_on_all_three(name):
    p = BENCH[name]
    tp = uniform2d.tplus(p, 200)
    m = optimize_mesh(p, 200, start=tp)
    assert m.n_steiner == 200 and len(m.points) == len(p.vertices) + 200
    check_mesh(m.points, m.triangles, p)
    qa, qb = m.quality(), tp.quality()
    for a, b in zip(_crit(qa), _crit(qb)):
        assert a < b
    assert m.info["method"] == "uniform" and m.info["objective"] == "balanced"
    assert m.info["fallback"] is None


@pytest.mark.parametrize("objective", OBJECTIVES)
@pytest.mark.parametrize("seed", range(3))
def test_random_polygons_valid_exact_and_never_worse(objective, seed):
    rng = np.random.default_rng(1000 + seed)
    for p in (convex(rng), star(rng), with_holes(rng)):
        n = 150
        try:
            tp = uniform2d.tplus(p, n)
        except uniform2d.InsufficientPointsError:
            continue
        m = optimize_mesh(p, n, objective=objective, start=tp)
        assert m.n_steiner == n and len(m.points) == len(p.vertices) + n
        check_mesh(m.points, m.triangles, p)
        h = target_size(p, n)
        from uniform2d.optimize import objective_value

        qa, qb = m.quality(d_n=False), tp.quality(d_n=False)
        va = objective_value(objective, qa.longest_edge, qa.shortest_edge, qa.max_perimeter, h)
        vb = objective_value(objective, qb.longest_edge, qb.shortest_edge, qb.max_perimeter, h)
        assert va <= vb


@pytest.mark.parametrize("n", [1, 2, 5])
def test_n_too_small_for_tplus_still_gives_exactly_n(n):
    # T+ needs room for its boundary points; the optimised mesh does not
    p = BENCH["square2holes"]
    with pytest.raises(uniform2d.InsufficientPointsError):
        uniform2d.tplus(p, n)
    m = uniform2d.uniform_mesh(p, n)
    assert m.n_steiner == n and len(m.points) == len(p.vertices) + n
    check_mesh(m.points, m.triangles, p)
    assert m.info["start"] is None and m.info["before"] is None and m.info["fallback"] is None
    assert m.info["d_n"] == uniform2d.insert(p, n).min_distance()
    q = m.quality()
    for b in (q.longest_edge_bound, q.max_perimeter_bound, q.edge_ratio_bound):
        assert b.factor >= 1.0


def test_n_too_small_for_tplus_uses_the_packing_distance_of_insert():
    p = BENCH["heptagon_short"]  # convex: the packing terms (from d_n) apply
    n = 3
    with pytest.raises(uniform2d.InsufficientPointsError):
        uniform2d.tplus(p, n)
    m = uniform2d.uniform_mesh(p, n)
    d_n = uniform2d.insert(p, n).min_distance()
    assert m.info["d_n"] == d_n and m.info["start"] is None
    q = m.quality()
    assert q.d_n == d_n
    assert dict(q.longest_edge_bound.terms)
    assert q.longest_edge_bound.value >= np.sqrt(3) / 2 * d_n


@pytest.mark.parametrize("n", [3, 50])
def test_tiny_hole_far_below_the_target_size(n):
    # the hole's edges are some 1 % of the target: edge**p underflows at p = 256
    # (the short-edge term used to divide by it: ZeroDivisionError)
    hole = [(0.02 + 0.006 * np.cos(t), 0.5 + 0.006 * np.sin(t)) for t in np.linspace(0, 2 * np.pi, 7)[:-1]]
    p = uniform2d.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], [hole])
    for objective in OBJECTIVES:
        m = optimize_mesh(p, n, objective=objective)
        assert m.n_steiner == n and len(m.points) == len(p.vertices) + n
        check_mesh(m.points, m.triangles, p)


def test_deterministic():
    p = BENCH["star10"]
    a = optimize_mesh(p, 300)
    b = optimize_mesh(p, 300)
    assert np.array_equal(a.points, b.points)
    assert np.array_equal(a.triangles, b.triangles)


def test_info_and_certificates():
    p = BENCH["square"]
    m = optimize_mesh(p, 200, objective="ratio")
    i = m.info
    for key in ("method", "objective", "d_n", "start", "before", "after", "relax_iterations"):
        assert key in i
    q = m.quality()
    assert q.longest_edge_bound.factor >= 1 and q.max_perimeter_bound.factor >= 1
    assert i["after"]["edge_ratio"] == pytest.approx(q.edge_ratio)


def test_bad_objective():
    with pytest.raises(ValueError):
        optimize_mesh(BENCH["square"], 50, objective="nope")


def _transformed(p, s, off=(0.0, 0.0)):
    rings = [np.asarray(r) * s + np.asarray(off) for r in p.rings]
    return uniform2d.Polygon(rings[0], rings[1:])


@pytest.mark.parametrize("k", [-20, 20])
def test_power_of_two_scaling_gives_the_scaled_mesh_exactly(k):
    p = BENCH["square2holes"]
    a = optimize_mesh(p, 150)
    b = optimize_mesh(_transformed(p, 2.0**k), 150)
    assert np.array_equal(b.points, a.points * 2.0**k)
    assert np.array_equal(b.triangles, a.triangles)


@pytest.mark.parametrize("s, off", [(1e-6, (0, 0)), (1e6, (0, 0)), (1.0, (1e6, -1e6))])
def test_scale_and_offset_keep_the_quality(s, off):
    p = BENCH["star10"]
    a = optimize_mesh(p, 150)
    q = _transformed(p, s, off)
    b = optimize_mesh(q, 150)
    assert b.n_steiner == 150 and b.info["fallback"] is None
    check_mesh(b.points, b.triangles, q)
    qa, qb = a.quality(), b.quality()
    # not bit-identical (the normalised coordinates differ by rounding, and the
    # moves amplify that), but the same mesh quality
    assert qb.edge_ratio == pytest.approx(qa.edge_ratio, rel=0.05)
    assert qb.cv_edge == pytest.approx(qa.cv_edge, rel=0.2)
    assert qb.min_angle == pytest.approx(qa.min_angle, rel=0.1)


@pytest.mark.parametrize("off", [1e7, 1e9])
def test_far_from_the_origin_the_boundary_points_still_count_as_on_it(off):
    # a unit polygon at 1e7 (site or map coordinates) carries ~2e-9 of absolute
    # precision, above the 1e-10 relative boundary tolerance: the sliding points,
    # recomputed on their slanted edges, used to fall "outside" (InvalidSitesError)
    p = BENCH["star10"]
    q = uniform2d.Polygon(p.outer + off, [h + off for h in p.holes])
    m = optimize_mesh(q, 150)
    assert m.n_steiner == 150 and m.info["fallback"] is None
    # the boundary points are on their edges within rounding of 1e9-sized
    # coordinates (~1e-7), so the area agrees to about that
    check_mesh(m.points, m.triangles, q, area_rtol=1e-6)
    assert m.quality().edge_ratio == pytest.approx(optimize_mesh(p, 150).quality().edge_ratio, rel=0.05)


@pytest.mark.parametrize("name", ["lshape", "square2holes", "star10"])
def test_relocation_keeps_the_count_and_a_valid_cdt_and_never_raises_the_objective(name):
    from uniform2d.optimize import improve, objective_value
    from uniform2d.optimize.objective import extremes as _extremes
    from uniform2d.optimize.relocate import relocate as _relocate
    from uniform2d.optimize.schedule import RELOCATE

    p = BENCH[name]
    n, nV = 150, len(p.vertices)
    h = target_size(p, n)
    sites = uniform2d.insert(p, n).points  # INSERT's points: far from uniform, much to move
    pts, tri, info = improve(p, sites, href=h, **RELOCATE)
    before = objective_value("balanced", *_extremes(pts, tri), h)
    out, tri2, kept, _ = _relocate(p, pts, tri, np.zeros(n, bool), "balanced", h, {}, info["edges"])
    after = objective_value("balanced", *_extremes(out, tri2), h)
    assert len(out) == nV + n and np.array_equal(out[:nV], p.vertices)
    check_mesh(out, tri2, p)
    fresh = uniform2d.insert(p, 0, sites=out[nV:])  # the exact CDT of the points it returns
    assert {tuple(sorted(t)) for t in fresh.triangles.tolist()} == {tuple(sorted(t)) for t in tri2.tolist()}
    assert after <= before
    if kept:
        assert after < before and not np.array_equal(out, pts)
    else:
        assert np.array_equal(out, pts)


def test_balanced_ranks_the_starts_by_the_edge_cv_too(monkeypatch):
    """On a 4:1 rectangle, a lattice aligned with a short side meets both long
    sides along a row of 5-7 pairs: ranking the starts by the extremes alone
    picks it at n = 300, the CV-weighted ranking picks the lattice along the long
    sides, whose edges are far more even, for a small cost in the extremes."""
    import uniform2d.optimize as O
    import uniform2d.optimize.schedule as S
    from uniform2d.geometry import polygon_edges

    p = BENCH["rect4x1"]
    a = optimize_mesh(p, 300)
    monkeypatch.setattr(S, "CV_WEIGHT", 0.0)
    b = optimize_mesh(p, 300)
    check_mesh(a.points, a.triangles, p)
    _, _, L = polygon_edges(p)
    assert a.info["lattice_edge"] == int(np.argmax(L)) != b.info["lattice_edge"]
    qa, qb = a.quality(), b.quality()
    assert qa.cv_edge < 0.75 * qb.cv_edge
    h = target_size(p, 300)
    va = O.objective_value("balanced", qa.longest_edge, qa.shortest_edge, qa.max_perimeter, h)
    vb = O.objective_value("balanced", qb.longest_edge, qb.shortest_edge, qb.max_perimeter, h)
    assert va < 1.05 * vb


def test_hex_lattice_is_every_lattice_point_in_the_box_row_by_row():
    """The lattice's points, bit for bit and in order, are those of the plain
    formula over a wide range of rows and columns that fall in the box."""
    import math

    from uniform2d.optimize import lattice

    for bounds, sp, angle, origin in (((0.0, 0.0, 3.0, 1.0), 0.21, 0.3, (3.0, 1.0)),
                                      ((-1.5, 0.25, 0.5, 2.0), 0.13, -2.1, (0.1, -0.3))):
        xmin, ymin, xmax, ymax = bounds
        c, s, dy = math.cos(angle), math.sin(angle), sp * math.sqrt(3.0) / 2
        want = []
        for j in range(-80, 81):
            for i in range(-80, 81):
                u, v = (i + 0.5 * (j & 1)) * sp, j * dy
                x, y = origin[0] + c * u - s * v, origin[1] + s * u + c * v
                if xmin <= x <= xmax and ymin <= y <= ymax:
                    want.append((x, y))
        got = lattice.hex_lattice(bounds, sp, angle, origin)
        assert len(want) > 50 and got.tobytes() == np.array(want).tobytes()


def test_hex_lattice_does_not_depend_on_its_row_blocks(monkeypatch):
    """The lattice is made LATTICE_ROWS rows at a time: the same points, in the same
    order, as rows one at a time or all at once; spacing and rotation as asked."""
    from uniform2d.optimize import lattice

    args = ((0.0, 0.0, 3.0, 1.0), 0.05, 0.3, (3.0, 1.0))
    got = lattice.hex_lattice(*args)
    monkeypatch.setattr(lattice, "LATTICE_ROWS", 1)
    one = lattice.hex_lattice(*args)
    monkeypatch.setattr(lattice, "LATTICE_ROWS", 10**6)
    whole = lattice.hex_lattice(*args)
    assert got.tobytes() == one.tobytes() == whole.tobytes()
    # nearest neighbours at the spacing, one of them along the rotated rows
    from scipy.spatial import cKDTree

    d, j = cKDTree(got).query(got, k=2)
    assert np.allclose(d[:, 1], 0.05)
    step = got[j[:, 1]] - got
    ang = np.degrees(np.arctan2(step[:, 1], step[:, 0])) - np.degrees(0.3)
    assert np.allclose((ang + 30.0) % 60.0 - 30.0, 0.0, atol=1e-6)


@pytest.mark.parametrize("given", [False, True])
def test_fallback_returns_tplus_exactly(monkeypatch, given):
    # an objective that ranks every mesh by its edge ratio, reversed: the
    # optimised mesh (a lower ratio than T+'s) loses, and T+ is returned, the
    # caller's or made again
    from uniform2d.optimize import pipeline

    monkeypatch.setattr(pipeline, "quality_objective", lambda objective, q, h: -q.edge_ratio)
    p = BENCH["square"]
    tp = uniform2d.tplus(p, 200)
    m = optimize_mesh(p, 200, start=tp if given else None)
    assert m.info["fallback"] == "tplus" and m.info["start"]["method"] == "paper"
    np.testing.assert_array_equal(m.points, tp.points)
    np.testing.assert_array_equal(m.triangles, tp.triangles)
    assert m.info["d_n"] == tp.info["d_n"] and m.info["theorem_applies"] == tp.info["theorem_applies"]


def test_fallback_refuses_if_tplus_cannot_be_made_again(monkeypatch):
    # T+ is deterministic, so this cannot happen unless the library is broken:
    # then an InternalError that asks for a report, not a wrong mesh
    from uniform2d.errors import InternalError
    from uniform2d.optimize import pipeline

    monkeypatch.setattr(pipeline, "quality_objective", lambda objective, q, h: -q.edge_ratio)
    made = []
    real = pipeline.tplus_if_feasible

    def once(polygon, n):
        made.append(n)
        return real(polygon, n) if len(made) == 1 else None

    monkeypatch.setattr(pipeline, "tplus_if_feasible", once)
    with pytest.raises(InternalError, match="could not be made again.*report"):
        optimize_mesh(BENCH["square"], 200)
    assert made == [200, 200]
