"""The graded start in rows (uniform2d.optimize.packing): its spacing guarantees,
checked with scipy's KD-tree and shapely independently of the construction, the
exact count of rows_start, and what the rows buy in the graded mesh."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

import uniform2d
from uniform2d import Polygon, SizeField
from uniform2d.geometry import unique_edges
from uniform2d.graded import boundary_sites
from uniform2d.grading import as_field, scale_for_count
from uniform2d.optimize.packing import LINE_SPACING, SPACING, frontal_seed, rows_start
from uniform2d.testing import check_mesh

LSHAPE = Polygon([(0, 0), (1, 0), (1, 1), (-1, 1), (-1, -1), (0, -1)])
HOLED = Polygon([(0, 0), (4, 0), (4, 2), (0, 2)], [[(1, 0.6), (1.6, 0.6), (1.6, 1.2), (1, 1.2)]])


def corner(p):
    return 0.02 + 0.6 * np.hypot(p[:, 0], p[:, 1])


def ramp(p):
    return 0.05 + 0.1 * p[:, 0]


@pytest.mark.parametrize("poly,h,n", [(LSHAPE, corner, 600), (HOLED, ramp, 500)])
def test_rows_keep_their_spacing(poly, h, n):
    field = as_field(poly, h)
    s = scale_for_count(poly, field, n)
    b, _ = boundary_sites(poly, field, s, n)
    rows = frontal_seed(poly, field.scaled(s), b)
    assert len(rows) > 0.6 * n  # the rows make most of the count
    hs = s * field(rows)
    others = np.concatenate([poly.vertices, b])
    ho = s * field(others)
    # every row point is at least SPACING times the smaller of the two sizes from
    # every boundary point
    for i, nb in enumerate(cKDTree(others).query_ball_point(rows, SPACING * hs)):
        nb = np.asarray(nb, dtype=np.int64)
        d = np.linalg.norm(others[nb] - rows[i], axis=1)
        assert np.all(d >= SPACING * np.minimum(ho[nb], hs[i]) * (1 - 1e-12))
    # two row points are at least SPACING times the smaller of their sizes apart
    pairs = np.array(sorted(cKDTree(rows).query_pairs(SPACING * hs.max())))
    if len(pairs):
        dist = np.linalg.norm(rows[pairs[:, 0]] - rows[pairs[:, 1]], axis=1)
        assert np.all(dist >= SPACING * np.minimum(hs[pairs[:, 0]], hs[pairs[:, 1]]) * (1 - 1e-12))
    off = poly.ring_offsets
    rings = [poly.vertices[off[r]:off[r + 1]] for r in range(len(poly.rings))]
    shape = shapely.Polygon(rings[0], rings[1:])
    assert shapely.contains_xy(shape, rows[:, 0], rows[:, 1]).all()
    pr = shapely.points(rows)
    foot = shapely.get_coordinates(shapely.shortest_line(pr, shape.boundary))[1::2]
    limit = LINE_SPACING * np.minimum(hs, s * field(foot))
    assert np.all(shapely.distance(shape.boundary, pr) >= limit * (1 - 1e-12))


def test_first_row_around_a_hole_with_a_steep_size():
    """h growing at slope 0.27 from a 24-gon hole whose edges are about h long:
    every hole edge gets its apex, one ring of 24 points at one distance (an apex's
    own size is 1.2 times the edge's there, and spacing by it refused half of them)."""
    ang = -2 * np.pi * np.arange(24) / 24
    hole = np.column_stack([np.cos(ang), np.sin(ang)])
    poly = Polygon([(-6, -6), (6, -6), (6, 6), (-6, 6)], [hole])
    field = as_field(poly, lambda p: 0.27 + 0.27 * np.maximum(np.hypot(p[:, 0], p[:, 1]) - 1, 0))
    b, _ = boundary_sites(poly, field, 1.0, 10**6)
    rows = frontal_seed(poly, field, b)
    d = shapely.distance(shapely.LinearRing(hole), shapely.points(rows))
    first = d < 0.5 * float(field(hole[:1])[0]) + d.min()
    assert first.sum() == 24
    # one apex per hole edge: the nearest hole edge of each is a different one
    mids = 0.5 * (hole + np.roll(hole, -1, axis=0))
    _, edge = cKDTree(mids).query(rows[first])
    assert len(set(edge.tolist())) == 24


@pytest.mark.parametrize("n", [5, 80, 700])
def test_rows_start_exact_count(n):
    field = as_field(HOLED, ramp)
    s = scale_for_count(HOLED, field, n)
    b, e = boundary_sites(HOLED, field, s, n)
    pts, fixed = rows_start(HOLED, n, field, s, b, e)
    assert pts.shape == (n, 2) and fixed.shape == (n,)
    assert np.array_equal(pts[: len(b)], b) and fixed[: len(b)].all()
    assert len(np.unique(pts, axis=0)) == n


def test_graded_mesh_from_rows_is_regular():
    """The rows leave most interior vertices with six neighbours, and q's CV low
    (INSERT's start left 28 % irregular and a CV of 0.092 on this case)."""
    m = uniform2d.uniform_mesh(LSHAPE, 1994, size=corner)
    check_mesh(m.points, m.triangles, LSHAPE, n_steiner=1994)
    r = m.quality().relative
    assert r.q_cv < 0.08 and r.q_ratio < 1.6
    E = unique_edges(m.triangles)
    val = np.bincount(E.ravel(), minlength=len(m.points))
    inner = np.ones(len(m.points), bool)
    inner[: len(LSHAPE.vertices)] = False
    d = shapely.distance(shapely.Polygon(LSHAPE.vertices).boundary, shapely.points(m.points))
    inner &= d > 1e-12
    assert np.mean(val[inner] != 6) < 0.2


def test_uniform_field_rows_are_a_lattice():
    """With a constant size the rows are hexagonal: nearly every row point's nearest
    neighbour is within [0.8, 1.15] h."""
    sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    f = SizeField.constant(sq.bounds, 1.0)
    b, _ = boundary_sites(sq, f, 0.05, 10000)
    rows = frontal_seed(sq, f.scaled(0.05), b)
    d, _ = cKDTree(np.concatenate([sq.vertices, b, rows])).query(rows, k=2)
    nn = d[:, 1] / 0.05
    assert nn.min() >= SPACING * (1 - 1e-12)
    assert np.mean(nn <= 1.15) > 0.9


def test_rows_around_a_hole_take_the_count_their_circumference_asks():
    """A 24-gon hole whose edges are 1.12 h long, h growing with the radius: one apex
    per edge would keep 24 points on every ring (edges 1.12 h long on all of
    them); the rings get about ∮ ds / h points instead."""
    ang = -2 * np.pi * np.arange(24) / 24
    hole = np.column_stack([np.cos(ang), np.sin(ang)])

    def h(p):
        return 0.2333 + 0.27 * np.maximum(np.hypot(p[:, 0], p[:, 1]) - 1, 0)

    poly = Polygon([(-6, -6), (6, -6), (6, 6), (-6, 6)], [hole])
    field = as_field(poly, h)
    b, _ = boundary_sites(poly, field, 1.0, 10**6)
    rows = frontal_seed(poly, field, b)
    r = np.hypot(rows[:, 0], rows[:, 1])
    for lo, hi in ((1.0, 1.35), (1.35, 1.75)):  # the first two rings
        ring = (r > lo) & (r < hi)
        rm = float(r[ring].mean())
        asks = 2 * np.pi * rm / float(h(np.array([[rm, 0.0]]))[0])
        assert ring.sum() > 24
        assert abs(ring.sum() - asks) <= 1.0


@pytest.mark.parametrize("poly,h", [(Polygon([(0, 0), (4, 0), (4, 2), (0, 2)]), ramp),
                                    (HOLED, ramp)])
def test_front_of_the_active_points_is_the_front_of_all(poly, h):
    """frontal_seed triangulates only the points on an open triangle: round by round
    the front it finds (its apexes) is the one of all the points' triangulation."""
    from scipy.spatial import Delaunay

    from uniform2d.optimize.packing import _clear, _front, _greedy, _shape

    field = as_field(poly, h)
    s = scale_for_count(poly, field, 400)
    size = field.scaled(s)
    b, _ = boundary_sites(poly, field, s, 400)
    shape, lines = _shape(poly)
    P = np.concatenate([poly.vertices, b])
    n0 = len(P)
    active = np.ones(n0, bool)
    for _ in range(12):
        act = np.flatnonzero(active)
        closed = (lambda X, r, _, t=cKDTree(P[~active]): t.query(X)[0] < r) if (~active).any() else None
        mine, hc, on_open = _front(P, act, Delaunay(P[act]), size, shape, n0, closed)
        full, _, _ = _front(P, np.arange(len(P)), Delaunay(P), size, shape, n0, None)
        assert len(mine) == len(full)
        if poly.n_holes == 0:  # no ring respaced: the same apexes, up to rounding and
            # the diagonal Qhull picks among four cocircular points (lattice rows
            # meeting at a corner)
            d, _ = cKDTree(full).query(mine)
            assert np.mean(d < 1e-12) >= 0.97
        active[act] = False
        active[on_open] = True
        ok = shapely.contains_xy(shape, mine[:, 0], mine[:, 1])
        ok[ok] = _clear(mine[ok], hc[ok], P, size(P), lines, size)
        keep = np.flatnonzero(ok)
        if not len(keep):
            break
        keep = keep[_greedy(mine[keep], hc[keep])]
        P = np.concatenate([P, mine[keep]])
        active = np.concatenate([active, np.ones(len(keep), bool)])
    assert (~active).sum() > n0 // 2  # the rows left points behind the front


def test_grown_point_set_answers_as_one_tree():
    """_Grown keeps two KD-trees (one rebuilt now and then): its nearest distances
    and ball pairs are those of one tree over all its points, at every size."""
    from uniform2d.optimize.packing import _Grown

    rng = np.random.default_rng(3)
    g = _Grown(np.empty((0, 2)))
    P = np.empty((0, 2))
    X = rng.random((50, 2))
    r = rng.uniform(0.01, 0.2, 50)
    for k in (1, 5, 300, 40, 40, 40, 700, 3):
        Q = rng.random((k, 2))
        g.add(Q)
        P = np.vstack([P, Q])
        one = cKDTree(P)
        assert np.array_equal(g.nearest(X), one.query(X)[0])
        i, j = g.ball(X, r)
        want = sorted((a, b) for a, lst in enumerate(one.query_ball_point(X, r)) for b in lst)
        assert sorted(zip(i.tolist(), j.tolist())) == want


def test_clockwise_front_loops_are_respaced_counter_clockwise_ones_kept():
    """A front loop turning clockwise (open side outside: a ring growing outward) gets
    round(∮ ds / h) points evenly spaced; the same loop turning counter-clockwise
    (a front closing in on an open region) keeps its apexes."""
    from uniform2d.optimize.packing import _respace_rings

    k = 12
    ang = -2 * np.pi * np.arange(k) / k  # clockwise
    cw = np.column_stack([np.cos(ang), np.sin(ang)])
    ends = np.column_stack([np.arange(k), (np.arange(k) + 1) % k]) + 100  # not boundary points
    perimeter = np.sum(np.linalg.norm(np.roll(cw, -1, axis=0) - cw, axis=1))
    field = SizeField.constant((-2, -2, 2, 2), perimeter / 20)
    ring = _respace_rings(cw, ends, field, 0)
    assert len(ring) == 20
    gaps = np.linalg.norm(np.diff(ring, axis=0), axis=1)
    assert np.allclose(gaps, perimeter / 20, rtol=0.1)
    ccw = cw[::-1].copy()
    assert np.array_equal(_respace_rings(ccw, ends, field, 0), ccw)
